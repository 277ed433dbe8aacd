// llvmpipe/llvmpipe_peer.cpp — EGL surfaceless context, scene upload and timed frames on
// llvmpipe. See llvmpipe_peer.hpp for what matches mosaic and why.
#include "llvmpipe/llvmpipe_peer.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

#include "llvmpipe/gl_api.hpp"
#include "mosaic/errors.hpp"
#include "raster/sample_patterns.hpp"

namespace mosaic::peers {
namespace {

// Under LeakSanitizer (the asan-ubsan preset), allocations made on this thread while one of
// these lives are not reported. Mesa makes a few one-time allocations in eglInitialize and at
// the first draws (behind pthread_once) that it keeps until the process exits; they are not
// ours, and no suppression can name them: the driver is unloaded before the leak check runs.
// Everything the peer calls into EGL or GL is wrapped; mosaic's own code never is.
class NotOurLeaks {
#if defined(__SANITIZE_ADDRESS__)
  __lsan::ScopedDisabler disabler_;
#endif
};

}  // namespace

const char* GlApi::load() {
#define MOSAIC_PEER_GL_LOAD(Name, NAME)                                      \
  Name = reinterpret_cast<PFNGL##NAME##PROC>(eglGetProcAddress("gl" #Name)); \
  if (Name == nullptr) return "gl" #Name;
  MOSAIC_PEER_GL_FUNCTIONS(MOSAIC_PEER_GL_LOAD)
#undef MOSAIC_PEER_GL_LOAD
  return nullptr;
}

namespace {

// The viewport is the largest power-of-two square P × P centred on the window origin that the
// driver allows (GL_MAX_VIEWPORT_DIMS, GL_VIEWPORT_BOUNDS_RANGE): then pixel → NDC is a
// multiplication by 2 / P and NDC → window the multiplication by P / 2, both exact in float, so
// a vertex on the 1/256 px grid reaches llvmpipe's snapping unchanged. (A W × H viewport would
// divide by 1920 and round.) Scene coordinates within ±P/2 px are drawn without clipping.
constexpr int kMaxViewportExtent = 1 << 15;
// Below this the scene sizes of the benchmarks (1920 × 1080) would not fit the viewport.
constexpr int kMinViewportExtent = 1 << 12;

// One context per process: they would share the EGL display that the destructor terminates.
std::atomic<bool> g_context_alive{false};

std::string egl_error_text() {
  char buf[32];
  std::snprintf(buf, sizeof buf, "EGL error 0x%04x", static_cast<unsigned>(eglGetError()));
  return buf;
}

bool has_word(const char* list, std::string_view word) {
  if (list == nullptr) return false;
  std::string_view s(list);
  std::size_t pos = 0;
  while ((pos = s.find(word, pos)) != std::string_view::npos) {
    const bool starts = pos == 0 || s[pos - 1] == ' ';
    const std::size_t end = pos + word.size();
    if (starts && (end == s.size() || s[end] == ' ')) return true;
    pos = end;
  }
  return false;
}

}  // namespace

struct LlvmpipeContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  bool initialized = false;
  bool owns_flag = false;
  GlApi gl;
  std::string renderer, version;
  int threads = 1;
  int viewport_extent = 0;  ///< P: the viewport is [-P/2, P/2)² window pixels

  ~Impl() {
    if (context != EGL_NO_CONTEXT) {
      eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(display, context);
    }
    // Terminating the display destroys llvmpipe's screen and its rasterizer threads, so the
    // next context reads LP_NUM_THREADS afresh.
    if (initialized) eglTerminate(display);
    if (owns_flag) {
      eglReleaseThread();
      g_context_alive = false;
    }
  }
};

LlvmpipeContext::LlvmpipeContext(int threads) : impl_(std::make_unique<Impl>()) {
  [[maybe_unused]] const NotOurLeaks not_ours;
  if (threads < 1) throw std::invalid_argument("llvmpipe thread count must be >= 1");
  if (g_context_alive.exchange(true))
    throw PeerError("only one llvmpipe context may exist at a time in a process");
  Impl& m = *impl_;
  m.owns_flag = true;
  m.threads = threads;

  // llvmpipe reads these when EGL creates its screen (eglInitialize). An explicit
  // LIBGL_ALWAYS_SOFTWARE or GALLIUM_DRIVER from the caller wins; the renderer check below
  // refuses anything that is not llvmpipe.
  setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 1);
  setenv("LIBGL_ALWAYS_SOFTWARE", "1", 0);
  setenv("GALLIUM_DRIVER", "llvmpipe", 0);

  if (!has_word(eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS), "EGL_MESA_platform_surfaceless"))
    throw PeerUnavailable("EGL has no surfaceless platform (EGL_MESA_platform_surfaceless)");
  m.display = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (m.display == EGL_NO_DISPLAY)
    throw PeerUnavailable("eglGetPlatformDisplay(surfaceless) failed: " + egl_error_text());
  EGLint major = 0, minor = 0;
  if (!eglInitialize(m.display, &major, &minor))
    throw PeerUnavailable("eglInitialize(surfaceless) failed: " + egl_error_text());
  m.initialized = true;
  const char* ext = eglQueryString(m.display, EGL_EXTENSIONS);
  if (!has_word(ext, "EGL_KHR_surfaceless_context") ||
      !(has_word(ext, "EGL_KHR_no_config_context") || has_word(ext, "EGL_MESA_configless_context")))
    throw PeerUnavailable("EGL display lacks surfaceless or configless contexts");
  if (!eglBindAPI(EGL_OPENGL_API))
    throw PeerUnavailable("eglBindAPI(EGL_OPENGL_API) failed: " + egl_error_text());
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                               4,
                               EGL_CONTEXT_MINOR_VERSION,
                               5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL_NONE};
  m.context = eglCreateContext(m.display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (m.context == EGL_NO_CONTEXT)
    throw PeerUnavailable("no OpenGL 4.5 core context: " + egl_error_text());
  if (!eglMakeCurrent(m.display, EGL_NO_SURFACE, EGL_NO_SURFACE, m.context))
    throw PeerUnavailable("eglMakeCurrent(surfaceless) failed: " + egl_error_text());
  if (const char* missing = m.gl.load())
    throw PeerUnavailable(std::string("OpenGL entry point missing: ") + missing);

  auto str = [&](GLenum name) {
    const GLubyte* s = m.gl.GetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
  };
  m.renderer = str(GL_RENDERER);
  m.version = str(GL_VERSION);
  if (m.renderer.find("llvmpipe") == std::string::npos)
    throw PeerUnavailable("GL_RENDERER is \"" + m.renderer +
                          "\", not llvmpipe: refusing to compare against another driver");

  GLint dims[2] = {0, 0};
  GLfloat bounds[2] = {0, 0};
  m.gl.GetIntegerv(GL_MAX_VIEWPORT_DIMS, dims);
  m.gl.GetFloatv(GL_VIEWPORT_BOUNDS_RANGE, bounds);
  for (int p = kMaxViewportExtent; p >= kMinViewportExtent; p /= 2) {
    const auto half = static_cast<float>(p / 2);
    if (p <= std::min(dims[0], dims[1]) && -half >= bounds[0] && half - 1 <= bounds[1]) {
      m.viewport_extent = p;
      break;
    }
  }
  if (m.viewport_extent == 0)
    throw PeerUnavailable("viewport limits too small for an exact power-of-two viewport");

  // Scene pixels are window pixels (y down from the first row in memory) and depth passes
  // through unchanged: window z = NDC z with GL_ZERO_TO_ONE.
  m.gl.ClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE);
  m.gl.Disable(GL_DITHER);  // mosaic does not dither; RGBA8 must round the same on both sides
  if (const GLenum e = m.gl.GetError(); e != GL_NO_ERROR)
    throw PeerError("GL error " + std::to_string(e) + " while setting up the llvmpipe context");
}

LlvmpipeContext::~LlvmpipeContext() = default;

const std::string& LlvmpipeContext::renderer() const noexcept { return impl_->renderer; }
const std::string& LlvmpipeContext::version() const noexcept { return impl_->version; }
int LlvmpipeContext::threads() const noexcept { return impl_->threads; }

int LlvmpipeContext::rasterizer_threads() const {
  std::error_code ec;
  std::filesystem::directory_iterator it("/proc/self/task", ec);
  if (ec) return -1;
  int n = 0;
  for (const auto& task : it) {
    std::ifstream comm(task.path() / "comm");
    std::string name;
    if (std::getline(comm, name) && name.rfind("llvmpipe-", 0) == 0) ++n;
  }
  return n;
}

namespace {

// One vertex as the GL vertex buffer holds it: pixels (y down) and depth, then RGBA8.
struct GlVertex {
  float x, y, z;
  std::uint8_t rgba[4];
};
static_assert(sizeof(GlVertex) == 16, "vertex layout is set up with this stride");
static_assert(sizeof(Rgba8) == 4, "glReadPixels writes RGBA8 straight into Rgba8");

// Flat triangles pass the same colour at all three vertices, so the provoking vertex does not
// matter; smooth triangles interpolate at the pixel centre, as mosaic shades (MSAA).
constexpr const char* kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;  // pixels, y down; depth in [0, 1]
layout(location = 1) in vec4 color;
layout(location = 0) uniform float pixels_to_ndc;  // 2 / P, a power of two: exact
INTERP out vec4 v_color;
void main() {
  // With GL_UPPER_LEFT, window y = -(P/2) * ndc_y: pixel y lands on window y.
  gl_Position = vec4(position.x * pixels_to_ndc, -position.y * pixels_to_ndc, position.z, 1.0);
  v_color = color;
}
)";
constexpr const char* kFragmentShader = R"(#version 450 core
INTERP in vec4 v_color;
layout(location = 0) out vec4 frag_color;
void main() { frag_color = v_color; }
)";

std::string with_interpolation(const char* source, bool smooth) {
  std::string s(source);
  const std::string key = "INTERP";
  s.replace(s.find(key), key.size(), smooth ? "smooth" : "flat");
  return s;
}

GLuint compile(const GlApi& gl, GLenum type, const std::string& source) {
  const GLuint shader = gl.CreateShader(type);
  const char* text = source.c_str();
  gl.ShaderSource(shader, 1, &text, nullptr);
  gl.CompileShader(shader);
  GLint ok = GL_FALSE;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[1024] = {};
    gl.GetShaderInfoLog(shader, sizeof log, nullptr, log);
    gl.DeleteShader(shader);
    throw PeerError(std::string("shader does not compile: ") + log);
  }
  return shader;
}

GLuint link_program(const GlApi& gl, bool smooth) {
  const GLuint vs = compile(gl, GL_VERTEX_SHADER, with_interpolation(kVertexShader, smooth));
  const GLuint fs = compile(gl, GL_FRAGMENT_SHADER, with_interpolation(kFragmentShader, smooth));
  const GLuint program = gl.CreateProgram();
  gl.AttachShader(program, vs);
  gl.AttachShader(program, fs);
  gl.LinkProgram(program);
  gl.DeleteShader(vs);
  gl.DeleteShader(fs);
  GLint ok = GL_FALSE;
  gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[1024] = {};
    gl.GetProgramInfoLog(program, sizeof log, nullptr, log);
    gl.DeleteProgram(program);
    throw PeerError(std::string("program does not link: ") + log);
  }
  return program;
}

GLenum gl_depth_func(DepthTest t) {
  switch (t) {
    case DepthTest::kLess:
      return GL_LESS;
    case DepthTest::kLessEqual:
      return GL_LEQUAL;
    case DepthTest::kGreater:
      return GL_GREATER;
    case DepthTest::kGreaterEqual:
      return GL_GEQUAL;
    case DepthTest::kAlways:
      return GL_ALWAYS;
  }
  return GL_LESS;
}

// A run of consecutive triangles of one mesh drawn with one program.
struct Batch {
  GLint first = 0;
  GLsizei count = 0;
  std::size_t mesh = 0;
  bool smooth = false;
  DrawState state;
};

float unorm(std::uint8_t c) { return static_cast<float>(c) / 255.0f; }

}  // namespace

struct LlvmpipeScene::Impl {
  const GlApi* gl = nullptr;
  int width = 0, height = 0, samples = 1, viewport_extent = 0;
  std::array<GLfloat, 4> clear_color{};
  GLfloat clear_depth = 1.0f;
  std::vector<Batch> batches;
  GLuint vbo = 0, vao = 0, query = 0;
  GLuint program[2] = {0, 0};  // flat, smooth
  GLuint draw_fbo = 0, resolve_fbo = 0;
  GLuint draw_color = 0, draw_depth = 0, resolve_color = 0;

  ~Impl() {
    if (gl == nullptr) return;
    gl->DeleteQueries(1, &query);
    gl->DeleteFramebuffers(1, &draw_fbo);
    if (resolve_fbo != draw_fbo) gl->DeleteFramebuffers(1, &resolve_fbo);
    gl->DeleteRenderbuffers(1, &draw_color);
    gl->DeleteRenderbuffers(1, &draw_depth);
    if (resolve_color != draw_color) gl->DeleteRenderbuffers(1, &resolve_color);
    gl->DeleteVertexArrays(1, &vao);
    gl->DeleteBuffers(1, &vbo);
    for (GLuint p : program) gl->DeleteProgram(p);
  }

  void apply(const DrawState& s) const {
    if (s.depth_test == DepthTest::kAlways && !s.depth_write) {
      gl->Disable(GL_DEPTH_TEST);  // also stops depth writes, as depth_write = false asks
    } else {
      gl->Enable(GL_DEPTH_TEST);
      gl->DepthFunc(gl_depth_func(s.depth_test));
      gl->DepthMask(s.depth_write ? GL_TRUE : GL_FALSE);
    }
    if (s.cull == CullMode::kNone) {
      gl->Disable(GL_CULL_FACE);
    } else {
      gl->Enable(GL_CULL_FACE);
      gl->CullFace(s.cull == CullMode::kBack ? GL_BACK : GL_FRONT);
      // Under GL_UPPER_LEFT, GL negates the window-space area, so GL_CCW means
      // counter-clockwise as the image is seen (y down): mosaic's kCounterClockwise.
      gl->FrontFace(s.front_face == FrontFace::kCounterClockwise ? GL_CCW : GL_CW);
    }
  }

  void draw() const {
    gl->BindFramebuffer(GL_DRAW_FRAMEBUFFER, draw_fbo);
    gl->Viewport(-viewport_extent / 2, -viewport_extent / 2, viewport_extent, viewport_extent);
    gl->DepthMask(GL_TRUE);  // the depth clear honours the depth mask
    gl->ClearNamedFramebufferfv(draw_fbo, GL_COLOR, 0, clear_color.data());
    gl->ClearNamedFramebufferfv(draw_fbo, GL_DEPTH, 0, &clear_depth);
    gl->BindVertexArray(vao);
    for (const Batch& b : batches) {
      apply(b.state);
      gl->UseProgram(program[b.smooth ? 1 : 0]);
      gl->DrawArrays(GL_TRIANGLES, b.first, b.count);
    }
  }

  void resolve() const {
    gl->BlitNamedFramebuffer(draw_fbo, resolve_fbo, 0, 0, width, height, 0, 0, width, height,
                             GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }

  void check(const char* what) const {
    if (const GLenum e = gl->GetError(); e != GL_NO_ERROR)
      throw PeerError("GL error 0x" + std::to_string(e) + " in " + what);
  }
};

namespace {

// Flattens a screen-space scene into non-indexed GL vertices, three per triangle in scene
// order, and the runs of triangles that share a mesh and an interpolation mode.
void flatten(const Scene& scene, std::vector<GlVertex>& vertices, std::vector<Batch>& batches) {
  for (std::size_t mi = 0; mi < scene.meshes.size(); ++mi) {
    const Mesh& mesh = scene.meshes[mi];
    const std::string where = "llvmpipe peer: mesh " + std::to_string(mi) + ": ";
    if (mesh.space != Space::kScreen)
      throw Error(Errc::kInvalidArgument,
                  where + "is in clip space; the peer draws screen-space (.tris) scenes only");
    const std::size_t tris = mesh.triangle_count();
    const std::size_t nv = mesh.positions.size();
    if (mesh.indices.empty() ? nv % 3 != 0 : mesh.indices.size() % 3 != 0)
      throw Error(Errc::kInvalidDraw, where + "vertex or index count is not a multiple of 3");
    if (mesh.color_source == ColorSource::kPerTriangle && mesh.colors.size() != tris)
      throw Error(Errc::kInvalidDraw, where + "needs one colour per triangle");
    if (mesh.color_source == ColorSource::kPerVertex && mesh.colors.size() != nv)
      throw Error(Errc::kInvalidDraw, where + "needs one colour per vertex");
    for (std::size_t t = 0; t < tris; ++t) {
      std::array<std::uint32_t, 3> idx{};
      for (std::size_t k = 0; k < 3; ++k) {
        idx[k] =
            mesh.indices.empty() ? static_cast<std::uint32_t>(3 * t + k) : mesh.indices[3 * t + k];
        if (idx[k] >= nv) throw Error(Errc::kIndexOutOfRange, where + "index out of range");
      }
      std::array<Rgba8, 3> c;
      switch (mesh.color_source) {
        case ColorSource::kConstant:
          c.fill(mesh.color);
          break;
        case ColorSource::kPerTriangle:
          c.fill(mesh.colors[t]);
          break;
        case ColorSource::kPerVertex:
          for (int k = 0; k < 3; ++k) c[k] = mesh.colors[idx[k]];
          break;
      }
      // Equal vertex colours are drawn flat, as mosaic's setup does: exact and cheaper.
      const bool smooth = !(c[0] == c[1] && c[0] == c[2]);
      if (batches.empty() || batches.back().mesh != mi || batches.back().smooth != smooth) {
        Batch b;
        b.first = static_cast<GLint>(vertices.size());
        b.mesh = mi;
        b.smooth = smooth;
        b.state = mesh.state;
        batches.push_back(b);
      }
      for (int k = 0; k < 3; ++k) {
        const glm::vec4& p = mesh.positions[idx[k]];
        vertices.push_back({p.x, p.y, p.z, {c[k].r, c[k].g, c[k].b, c[k].a}});
      }
      batches.back().count += 3;
    }
  }
}

}  // namespace

LlvmpipeScene::LlvmpipeScene(LlvmpipeContext& context, const Scene& scene, int samples)
    : impl_(std::make_unique<Impl>()) {
  [[maybe_unused]] const NotOurLeaks not_ours;
  Impl& m = *impl_;
  const LlvmpipeContext::Impl& ctx = context.impl();
  const GlApi& gl = ctx.gl;
  m.viewport_extent = ctx.viewport_extent;
  if (scene.width < 1 || scene.height < 1 || scene.width > m.viewport_extent / 2 ||
      scene.height > m.viewport_extent / 2)
    throw Error(Errc::kInvalidTargetSize, "llvmpipe peer: scene size " +
                                              std::to_string(scene.width) + "x" +
                                              std::to_string(scene.height) + " outside 1.." +
                                              std::to_string(m.viewport_extent / 2));
  GLint max_samples = 1;
  gl.GetIntegerv(GL_MAX_SAMPLES, &max_samples);
  if (samples < 1 || samples > max_samples || (samples & (samples - 1)) != 0)
    throw Error(Errc::kUnsupportedSampleCount, "llvmpipe peer: " + std::to_string(samples) +
                                                   " samples (llvmpipe has 1.." +
                                                   std::to_string(max_samples) + ")");
  m.width = scene.width;
  m.height = scene.height;
  m.samples = samples;
  m.clear_color = {unorm(scene.clear_color.r), unorm(scene.clear_color.g),
                   unorm(scene.clear_color.b), unorm(scene.clear_color.a)};
  m.clear_depth = scene.clear_depth;

  std::vector<GlVertex> vertices;
  flatten(scene, vertices, m.batches);
  m.gl = &gl;

  for (int smooth = 0; smooth < 2; ++smooth) {
    m.program[smooth] = link_program(gl, smooth != 0);
    gl.ProgramUniform1f(m.program[smooth], 0, 2.0f / static_cast<float>(m.viewport_extent));
  }

  gl.CreateBuffers(1, &m.vbo);
  // A buffer may not be empty; an empty scene still gets one (never drawn) vertex.
  const GlVertex dummy{};
  gl.NamedBufferStorage(
      m.vbo, static_cast<GLsizeiptr>(std::max<std::size_t>(1, vertices.size()) * sizeof(GlVertex)),
      vertices.empty() ? &dummy : vertices.data(), 0);
  gl.CreateVertexArrays(1, &m.vao);
  gl.VertexArrayVertexBuffer(m.vao, 0, m.vbo, 0, sizeof(GlVertex));
  gl.EnableVertexArrayAttrib(m.vao, 0);
  gl.VertexArrayAttribFormat(m.vao, 0, 3, GL_FLOAT, GL_FALSE, offsetof(GlVertex, x));
  gl.VertexArrayAttribBinding(m.vao, 0, 0);
  gl.EnableVertexArrayAttrib(m.vao, 1);
  gl.VertexArrayAttribFormat(m.vao, 1, 4, GL_UNSIGNED_BYTE, GL_TRUE, offsetof(GlVertex, rgba));
  gl.VertexArrayAttribBinding(m.vao, 1, 0);

  // With one sample the frame is drawn straight into the image that is read back; with more,
  // into multisampled storage that glBlitFramebuffer resolves into it.
  auto make_fbo = [&](GLuint& fbo, GLuint& color, GLuint* depth, int n) {
    const GLsizei s = n > 1 ? n : 0;
    gl.CreateFramebuffers(1, &fbo);
    gl.CreateRenderbuffers(1, &color);
    gl.NamedRenderbufferStorageMultisample(color, s, GL_RGBA8, m.width, m.height);
    gl.NamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    if (depth != nullptr) {
      gl.CreateRenderbuffers(1, depth);
      gl.NamedRenderbufferStorageMultisample(*depth, s, GL_DEPTH_COMPONENT32F, m.width, m.height);
      gl.NamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, *depth);
    }
    if (gl.CheckNamedFramebufferStatus(fbo, GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw PeerError("llvmpipe peer: incomplete framebuffer");
    GLint got = 0;
    gl.GetNamedRenderbufferParameteriv(color, GL_RENDERBUFFER_SAMPLES, &got);
    if (std::max(got, 1) != n)
      throw PeerError("llvmpipe peer: asked for " + std::to_string(n) + " samples, got " +
                      std::to_string(got));
  };
  make_fbo(m.draw_fbo, m.draw_color, &m.draw_depth, samples);
  if (samples > 1) {
    make_fbo(m.resolve_fbo, m.resolve_color, nullptr, 1);
  } else {
    m.resolve_fbo = m.draw_fbo;
    m.resolve_color = m.draw_color;
  }

  // The sample positions must be mosaic's (the standard pattern, y down). GL reports them in
  // window coordinates, which here are scene coordinates.
  if (samples > 1) {
    gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, m.draw_fbo);
    const auto pattern = raster::sample_pattern(samples);
    for (int s = 0; s < samples; ++s) {
      GLfloat pos[2] = {0, 0};
      gl.GetMultisamplefv(GL_SAMPLE_POSITION, static_cast<GLuint>(s), pos);
      const float ex = 0.5f + static_cast<float>(pattern.empty() ? 0 : pattern[s].dx) / 16.0f;
      const float ey = 0.5f + static_cast<float>(pattern.empty() ? 0 : pattern[s].dy) / 16.0f;
      if (pattern.empty() || pos[0] != ex || pos[1] != ey)
        throw PeerError("llvmpipe peer: sample " + std::to_string(s) + " lies at (" +
                        std::to_string(pos[0]) + ", " + std::to_string(pos[1]) +
                        "), not at mosaic's standard position");
    }
  }
  gl.CreateQueries(GL_SAMPLES_PASSED, 1, &m.query);
  m.check("scene upload");
}

LlvmpipeScene::~LlvmpipeScene() = default;

double LlvmpipeScene::render_frame() {
  [[maybe_unused]] const NotOurLeaks not_ours;
  const Impl& m = *impl_;
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  m.draw();
  m.gl->Finish();
  if (m.samples > 1) {
    m.resolve();
    m.gl->Finish();
  }
  const auto t1 = Clock::now();
  return std::chrono::duration<double, std::milli>(t1 - t0).count();
}

std::uint64_t LlvmpipeScene::samples_passed() {
  [[maybe_unused]] const NotOurLeaks not_ours;
  const Impl& m = *impl_;
  m.gl->BeginQuery(GL_SAMPLES_PASSED, m.query);
  m.draw();
  m.gl->EndQuery(GL_SAMPLES_PASSED);
  if (m.samples > 1) m.resolve();
  GLuint64 n = 0;
  m.gl->GetQueryObjectui64v(m.query, GL_QUERY_RESULT, &n);
  m.check("GL_SAMPLES_PASSED query");
  return n;
}

std::vector<Rgba8> LlvmpipeScene::read_image() {
  const Impl& m = *impl_;
  std::vector<Rgba8> pixels(static_cast<std::size_t>(m.width) * m.height);
  [[maybe_unused]] const NotOurLeaks not_ours;
  m.gl->NamedFramebufferReadBuffer(m.resolve_fbo, GL_COLOR_ATTACHMENT0);
  m.gl->BindFramebuffer(GL_READ_FRAMEBUFFER, m.resolve_fbo);
  m.gl->PixelStorei(GL_PACK_ALIGNMENT, 1);
  // Row 0 of glReadPixels is window row 0, which GL_UPPER_LEFT puts at the top of the scene:
  // the rows come out top first with no flip (tests/test_llvmpipe_peer.cpp checks it).
  m.gl->ReadPixels(0, 0, m.width, m.height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  m.check("glReadPixels");
  return pixels;
}

int LlvmpipeScene::width() const noexcept { return impl_->width; }
int LlvmpipeScene::height() const noexcept { return impl_->height; }
int LlvmpipeScene::samples() const noexcept { return impl_->samples; }
std::size_t LlvmpipeScene::batches() const noexcept { return impl_->batches.size(); }

double median(std::vector<double> values) {
  if (values.empty()) throw std::invalid_argument("median of no values");
  const std::size_t n = values.size();
  std::sort(values.begin(), values.end());
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace mosaic::peers
