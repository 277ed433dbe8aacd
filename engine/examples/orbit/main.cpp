// orbit — a lit mesh seen by a camera that circles it: N frames to PNG, a progress bar, and
// frames per second.
//
// Takes: [mesh.obj] [--frames N] [--size W H] [--samples 1|4|8|16] [--threads N]
//        [--out-dir DIR] [--no-images]
// Gives: DIR/frame_0000.png, frame_0001.png, … (one per frame, unless --no-images), a progress
// bar on stderr, and the frame rate of the renderer alone and of the whole loop on stdout.
//
// Without an OBJ file the mesh is a procedural (2,3) torus knot with smooth normals; an OBJ file
// is read with mosaic::load_obj (indexed, with the file's normals, or face normals where it has
// none) and its positions taken back to model space through Scene::camera. Either is a
// mosaic::Mesh drawn as `mosaic render` draws one, through Mesh::draw(Shading::kLambert, light):
// the normals are vertex attributes, interpolated perspective-correctly per pixel and lit by the
// built-in Lambert shader, whose light moves with the camera. Only the positions differ: model
// space, with the orbiting camera as the draw's transform. Uses only the public API.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <mosaic/mosaic.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr double kPi = 3.14159265358979323846;
/// Frames of one full turn by default: two seconds of video at 24 frames per second.
constexpr int kDefaultFrames = 48;
/// Upper bound of --frames: a guard against a typo that would fill the disk with images.
constexpr int kMaxFrames = 100000;
/// The torus knot winds kKnotP times around its axis and kKnotQ times through its hole.
constexpr int kKnotP = 2, kKnotQ = 3;
/// Tube radius of the knot, against a curve radius of 2 ± 1: thick, yet the strands never touch.
constexpr double kKnotTube = 0.4;
/// Tessellation: segments along the curve and sides around the tube. 512 × 48 gives 49,152
/// triangles of a few pixels each at 1280×720, smooth silhouettes with a realistic load.
constexpr int kKnotSegments = 512, kKnotSides = 48;
/// Vertical field of view of the camera: a natural lens.
constexpr double kFovY = 50.0 * kPi / 180.0;
/// The bounding sphere fills this fraction of the narrower field of view.
constexpr double kFrameFill = 0.9;
/// The camera looks down at the model from this angle above the orbit plane.
constexpr double kElevation = 25.0 * kPi / 180.0;
/// Near and far planes sit this factor of the radius before and after the centre, so that the
/// model never touches them; the near plane never comes nearer than kMinNearFraction of the
/// distance, which bounds the depth precision lost when the camera is inside the sphere.
constexpr double kDepthMargin = 1.05;
constexpr double kMinNearFraction = 1e-3;
/// Direction towards the light in view space: upper left, from behind the viewer.
constexpr glm::dvec3 kLightView{-0.4, 0.6, 0.7};
/// Lambert shading: albedo * (ambient + diffuse * n·l). The ambient keeps unlit sides readable.
constexpr double kAmbient = 0.15, kDiffuse = 0.85;
/// Albedo of the knot (warm copper) and of OBJ meshes (light grey).
constexpr glm::dvec3 kKnotAlbedo{0.95, 0.55, 0.30};
constexpr glm::dvec3 kObjAlbedo{0.85, 0.85, 0.85};
/// Background: dark blue-grey.
constexpr mosaic::Rgba8 kBackground{20, 22, 30, 255};
/// Width of the progress bar in characters.
constexpr int kBarWidth = 30;

/// A lit mesh: its normals, indices and state in a mosaic::Mesh (whose clip-space positions
/// stay empty), and its positions in model space, drawn through the orbiting camera.
struct LitMesh {
  mosaic::Mesh mesh;
  std::vector<glm::vec3> positions;
  glm::dvec3 albedo{1.0};
  /// Lit from both sides (|n·l|) and not culled: OBJ files disagree on winding.
  bool two_sided = false;
};

/// Point of the (p, q) torus knot at parameter t, lying around the y axis.
glm::dvec3 knot_point(double t) {
  const double r = 2.0 + std::cos(kKnotQ * t);
  return {r * std::cos(kKnotP * t), std::sin(kKnotQ * t), r * std::sin(kKnotP * t)};
}

/// Its derivative d/dt.
glm::dvec3 knot_tangent(double t) {
  const double r = 2.0 + std::cos(kKnotQ * t), dr = -kKnotQ * std::sin(kKnotQ * t);
  return {dr * std::cos(kKnotP * t) - r * kKnotP * std::sin(kKnotP * t),
          kKnotQ * std::cos(kKnotQ * t),
          dr * std::sin(kKnotP * t) + r * kKnotP * std::cos(kKnotP * t)};
}

/// A tube around the torus knot. The tube's frame is N = T × y, B = T × N: the tangent's
/// horizontal part (at least p·1 = 2) always outweighs its vertical part (at most q = 3) by
/// enough that T is never parallel to y, so the frame never flips. The normal of a tube is
/// exact: the unit offset from the curve.
LitMesh torus_knot() {
  LitMesh lit;
  lit.albedo = kKnotAlbedo;
  std::vector<glm::vec3>& positions = lit.positions;
  mosaic::Mesh& m = lit.mesh;
  positions.reserve(static_cast<std::size_t>(kKnotSegments) * kKnotSides);
  m.normals.reserve(positions.capacity());
  for (int i = 0; i < kKnotSegments; ++i) {
    const double t = 2.0 * kPi * i / kKnotSegments;
    const glm::dvec3 c = knot_point(t), tangent = glm::normalize(knot_tangent(t));
    const glm::dvec3 n = glm::normalize(glm::cross(tangent, glm::dvec3(0, 1, 0)));
    const glm::dvec3 b = glm::cross(tangent, n);
    for (int j = 0; j < kKnotSides; ++j) {
      const double v = 2.0 * kPi * j / kKnotSides;
      const glm::dvec3 normal = std::cos(v) * n + std::sin(v) * b;
      positions.emplace_back(c + kKnotTube * normal);
      m.normals.emplace_back(normal);
    }
  }
  const auto at = [](int i, int j) {
    return static_cast<std::uint32_t>((i % kKnotSegments) * kKnotSides + j % kKnotSides);
  };
  // Counter-clockwise seen from outside, so back-face culling keeps the outside: decided on
  // the first quad against its normal (the sign is the same all along the smooth tube).
  const glm::vec3 e1 = positions[at(1, 0)] - positions[at(0, 0)];
  const glm::vec3 e2 = positions[at(1, 1)] - positions[at(0, 0)];
  const bool ccw = glm::dot(glm::cross(e1, e2), m.normals[at(0, 0)]) > 0.0f;
  for (int i = 0; i < kKnotSegments; ++i) {
    for (int j = 0; j < kKnotSides; ++j) {
      const std::uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (ccw) {
        m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
      } else {
        m.indices.insert(m.indices.end(), {a, c, b, a, d, c});
      }
    }
  }
  m.state.cull = mosaic::CullMode::kBack;
  return lit;
}

/// An OBJ mesh through mosaic::load_obj, as `mosaic render` reads it, with its clip-space
/// positions taken back to model space through the camera it was framed with.
LitMesh obj_mesh(const fs::path& path) {
  mosaic::Scene scene = mosaic::load_obj(path);
  const glm::dmat4 to_model = glm::inverse(glm::dmat4(scene.camera.view_projection));
  LitMesh lit;
  lit.albedo = kObjAlbedo;
  lit.two_sided = true;
  lit.mesh = std::move(scene.meshes.front());  // load_obj gives one mesh
  for (const glm::vec4& p : lit.mesh.positions) {
    const glm::dvec4 q = to_model * glm::dvec4(p);
    lit.positions.emplace_back(glm::dvec3(q) / q.w);
  }
  lit.mesh.positions.clear();
  lit.mesh.state.cull = mosaic::CullMode::kNone;
  return lit;
}

/// Centre (of the bounding box) and radius of a bounding sphere.
void bounding_sphere(const LitMesh& m, glm::dvec3& centre, double& radius) {
  glm::dvec3 lo(m.positions[0]), hi = lo;
  for (const glm::vec3& p : m.positions) {
    lo = glm::min(lo, glm::dvec3(p));
    hi = glm::max(hi, glm::dvec3(p));
  }
  centre = (lo + hi) * 0.5;
  radius = 0;
  for (const glm::vec3& p : m.positions)
    radius = std::max(radius, glm::length(glm::dvec3(p) - centre));
  if (!(radius > 0) || !std::isfinite(radius)) radius = 1.0;  // a point: any size will do
}

/// Parses an integer in [lo, hi]; false for anything else.
bool parse_int(const char* text, int lo, int hi, int& out) {
  const std::string_view s(text);
  int v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || v < lo || v > hi) return false;
  out = v;
  return true;
}

int usage() {
  std::fprintf(stderr,
               "usage: orbit [mesh.obj] [--frames N] [--size W H] [--samples 1|4|8|16] "
               "[--threads N] [--out-dir DIR] [--no-images]\n");
  return 2;
}

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::string obj_path;
  fs::path out_dir = "orbit_frames";
  int frames = kDefaultFrames, width = 1280, height = 720, samples = 4, threads = 0;
  bool images = true;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    const bool has1 = i + 1 < argc, has2 = i + 2 < argc;
    if (a == "--frames" && has1) {
      if (!parse_int(argv[++i], 1, kMaxFrames, frames)) return usage();
    } else if (a == "--size" && has2) {
      if (!parse_int(argv[i + 1], 1, mosaic::kMaxTargetSize, width) ||
          !parse_int(argv[i + 2], 1, mosaic::kMaxTargetSize, height))
        return usage();
      i += 2;
    } else if (a == "--samples" && has1) {
      if (!parse_int(argv[++i], 1, 16, samples)) return usage();
    } else if (a == "--threads" && has1) {
      if (!parse_int(argv[++i], 0, mosaic::kMaxThreads, threads)) return usage();
    } else if (a == "--out-dir" && has1) {
      out_dir = argv[++i];
    } else if (a == "--no-images") {
      images = false;
    } else if (!a.empty() && a[0] != '-' && obj_path.empty()) {
      obj_path = a;
    } else {
      return usage();
    }
  }

  try {
    const LitMesh lit = obj_path.empty() ? torus_knot() : obj_mesh(obj_path);
    glm::dvec3 centre;
    double radius;
    bounding_sphere(lit, centre, radius);

    // Camera distance: the sphere's half-angle asin(r / d) must fit the narrower half field.
    const double aspect = static_cast<double>(width) / height;
    const double half_fov_y = kFovY / 2;
    const double half_fov = std::min(half_fov_y, std::atan(std::tan(half_fov_y) * aspect));
    const double dist = radius / (kFrameFill * std::sin(half_fov));
    const double near_plane = std::max(dist - kDepthMargin * radius, dist * kMinNearFraction);
    const double far_plane = dist + kDepthMargin * radius;
    // Depth z/w in [0, 1], as mosaic's clip space wants.
    const glm::dmat4 projection = glm::perspectiveRH_ZO(kFovY, aspect, near_plane, far_plane);

    mosaic::RenderTarget target(width, height, samples);
    target.set_clear(kBackground);
    mosaic::RendererOptions options;
    options.threads = threads;
    mosaic::Renderer renderer(options);
    if (images) fs::create_directories(out_dir);

    mosaic::Lambert lambert;
    lambert.albedo = glm::vec3(lit.albedo);
    lambert.ambient = static_cast<float>(kAmbient);
    lambert.diffuse = static_cast<float>(kDiffuse);
    lambert.two_sided = lit.two_sided;
    mosaic::Draw draw;
    mosaic::Frame frame;
    frame.draws = std::span<const mosaic::Draw>(&draw, 1);

    const std::size_t triangles =
        (lit.mesh.indices.empty() ? lit.positions.size() : lit.mesh.indices.size()) / 3;
    std::printf("orbit: %s, %zu triangles, %dx%d, %dx, %d frames\n",
                obj_path.empty() ? "torus knot" : obj_path.c_str(), triangles, width, height,
                samples, frames);
    double render_ms = 0;
    const Clock::time_point start = Clock::now();
    mosaic::FrameStats stats;
    for (int f = 0; f < frames; ++f) {
      const double angle = 2.0 * kPi * f / frames;
      const glm::dvec3 eye =
          centre + dist * glm::dvec3(std::cos(kElevation) * std::sin(angle), std::sin(kElevation),
                                     std::cos(kElevation) * std::cos(angle));
      const glm::dmat4 view = glm::lookAtRH(eye, centre, glm::dvec3(0, 1, 0));

      // Lambert per pixel on the interpolated normal: the view-space light taken to model space
      // (the inverse of the view's rotation is its transpose), where the normals are.
      lambert.light_dir = glm::vec3(glm::transpose(glm::dmat3(view)) * glm::normalize(kLightView));
      draw = lit.mesh.draw(mosaic::Shading::kLambert, lambert);
      draw.positions_xyz = lit.positions;
      draw.transform = glm::mat4(projection * view);

      const Clock::time_point t0 = Clock::now();
      stats = renderer.render(frame, target);
      render_ms += ms_since(t0);
      if (images) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%04d.png", f);
        mosaic::write_image(target, out_dir / name);
      }

      const int done = (f + 1) * kBarWidth / frames;
      std::fprintf(stderr, "\r[%s%s] %d/%d frames, %.1f frames/s", std::string(done, '#').c_str(),
                   std::string(kBarWidth - done, '-').c_str(), f + 1, frames,
                   1000.0 * (f + 1) / ms_since(start));
    }
    std::fprintf(stderr, "\n");
    const double total_ms = ms_since(start);
    std::printf("renderer: %.2f ms/frame, %.1f frames/s (%s, %d threads, %llu triangles drawn)\n",
                render_ms / frames, 1000.0 * frames / render_ms, mosaic::to_string(stats.isa),
                stats.threads, static_cast<unsigned long long>(stats.triangles_drawn));
    std::printf("whole loop (rendering%s): %.2f ms/frame, %.1f frames/s\n", images ? ", PNG" : "",
                total_ms / frames, 1000.0 * frames / total_ms);
    if (images)
      std::printf("wrote %s/frame_0000.png ... frame_%04d.png\n", out_dir.string().c_str(),
                  frames - 1);
    return 0;
  } catch (const mosaic::Error& e) {
    std::fprintf(stderr, "\norbit: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {  // e.g. the output folder cannot be made
    std::fprintf(stderr, "\norbit: %s\n", e.what());
    return 1;
  }
}
