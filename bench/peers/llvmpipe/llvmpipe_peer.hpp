// llvmpipe/llvmpipe_peer.hpp — the same frame as mosaic's, drawn by Mesa's llvmpipe.
//
// Takes: a screen-space mosaic::Scene (a .tris file, shared/formats/screen-triangles.md), a
// sample count and a thread count. Gives: the resolved RGBA8 image (top row first, like
// mosaic::RenderTarget::color()), the time of a whole frame (clear + draw + glFinish, and for
// multisampling + glBlitFramebuffer resolve + glFinish), and GL_SAMPLES_PASSED.
//
// OpenGL 4.5 core runs with no display, through EGL's surfaceless platform
// (EGL_MESA_platform_surfaceless) and a framebuffer object. The work matches mosaic's:
// RGBA8 colour, GL_DEPTH_COMPONENT32F depth, each mesh's depth test, 1 or 4 samples with the
// standard pattern, flat or (for triangles with three different vertex colours) smooth colour,
// and glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE) so that a scene pixel (x, y) is window
// pixel (x, y) and a scene depth is window depth. llvmpipe always applies OpenGL's fill rule;
// mosaic matches it with FillRule::kOpenGL.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "mosaic/scene.hpp"
#include "mosaic/types.hpp"

namespace mosaic::peers {

/// A failure of the GL side (a shader that does not compile, an incomplete framebuffer).
class PeerError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// No llvmpipe context can be created here: no EGL surfaceless platform, no OpenGL 4.5 core
/// context, or a GL_RENDERER that is not llvmpipe. Tests skip on this error and nothing else.
class PeerUnavailable : public PeerError {
 public:
  using PeerError::PeerError;
};

/// An EGL display and an OpenGL 4.5 core context on llvmpipe, current on the creating thread.
///
/// llvmpipe reads LP_NUM_THREADS when EGL creates its screen, so the constructor sets it (and
/// LIBGL_ALWAYS_SOFTWARE, GALLIUM_DRIVER=llvmpipe unless the caller set them) before
/// eglInitialize, and the destructor terminates the display. To change the thread count,
/// destroy the context and create another; only one may exist at a time in a process.
class LlvmpipeContext {
 public:
  /// Throws PeerUnavailable (see above) or PeerError; std::invalid_argument for threads < 1.
  explicit LlvmpipeContext(int threads);
  ~LlvmpipeContext();
  LlvmpipeContext(const LlvmpipeContext&) = delete;
  LlvmpipeContext& operator=(const LlvmpipeContext&) = delete;

  /// GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)", and GL_VERSION.
  const std::string& renderer() const noexcept;
  const std::string& version() const noexcept;
  /// The LP_NUM_THREADS value the context was created with.
  int threads() const noexcept;
  /// llvmpipe's rasterizer threads counted in /proc/self/task (named "llvmpipe-N"), or -1 where
  /// /proc cannot tell: the check that LP_NUM_THREADS took effect.
  int rasterizer_threads() const;

  struct Impl;
  Impl& impl() noexcept { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

/// One scene uploaded to llvmpipe with its framebuffers, ready to be drawn frame after frame.
/// Every call must come from the thread that created the context, while it lives.
class LlvmpipeScene {
 public:
  /// Uploads `scene` (every mesh in Space::kScreen; else mosaic::Error{kInvalidArgument}, as
  /// for bad indices or colour counts) for a scene.width × scene.height target with `samples`
  /// (1 or 4) samples per pixel. Each mesh's DrawState is honoured except its fill rule:
  /// DepthTest::kAlways without depth writes disables GL_DEPTH_TEST, as the brief asks.
  LlvmpipeScene(LlvmpipeContext& context, const Scene& scene, int samples);
  ~LlvmpipeScene();
  LlvmpipeScene(const LlvmpipeScene&) = delete;
  LlvmpipeScene& operator=(const LlvmpipeScene&) = delete;

  /// Draws one whole frame and returns its wall time in milliseconds: clear colour and depth,
  /// the draws, glFinish, and with 4 samples the resolve blit and a second glFinish.
  double render_frame();
  /// Draws one frame inside a GL_SAMPLES_PASSED query and returns the count: the covered
  /// samples that passed the depth test (all of them when the test is off), over all draws.
  std::uint64_t samples_passed();
  /// The resolved image of the last frame, row-major, top row first.
  std::vector<Rgba8> read_image();

  int width() const noexcept;
  int height() const noexcept;
  int samples() const noexcept;
  /// Draw calls per frame: runs of consecutive triangles of one mesh, flat or smooth.
  std::size_t batches() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The median of a non-empty list of frame times (the mean of the two middle ones for an even
/// count). Throws std::invalid_argument for an empty list.
double median(std::vector<double> values);

}  // namespace mosaic::peers
