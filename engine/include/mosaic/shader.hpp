// mosaic/shader.hpp — programmable fragment shading: a C++ callable over a batch of pixels.
//
// Takes: a callable (per pixel or per batch) and the number of varyings it reads. Gives: a Shader
// that Draw::shader carries to the renderer, and the built-in shaders (flat colour, vertex colour,
// Lambert-lit normal).
//
// How it runs. libmosaic's tile kernels are compiled ahead of time, once per instruction set, so a
// user's callable cannot be inlined into them. make_shader() instead instantiates, in the caller's
// translation unit, one function that loops the callable over a whole batch of kShaderBatch pixels
// (a loop with a constant trip count that the compiler inlines, unrolls and can vectorise). The
// kernels call that function through ONE function pointer PER BATCH of up to 16 pixels, never per
// pixel: the indirect call costs a few nanoseconds per 16 pixels.
//
// What the shader sees. Varying k of a pixel is attribute Draw::varyings[k] of the triangle's
// three vertices, interpolated perspective-correctly (attr·q planes divided by the 1/w plane, the
// way the renderer interpolates vertex colours), at the pixel centre under MSAA (once per pixel)
// or at each sample under SSAA. Only the attributes listed in Draw::varyings are interpolated.
// With ShaderUses::derivatives, each varying also comes with its screen-space derivatives along x
// and y, per pixel: analytic, from the triangle's planes (v = P / Q, so dv/dx = (dP/dx - v dQ/dx)
// / Q), not differences across a 2×2 quad, so that they are exact for every lane of a batch that
// packs pixels of many triangles, and equal on every path. Each lane also says whether its
// triangle faces the viewer (DrawState::front_face), and a shader that declares
// ShaderUses::discards may drop lanes: a discarded pixel (or sample under SSAA) writes neither
// colour nor depth, and does not count in FrameStats::samples_written.
//
// Contract. A shader must be a pure function of each lane's inputs: lane l's output may depend
// only on x[l], y[l] and varying[k][l] (and the callable's own constant state). The fast path
// shades lanes whose pixels are partly covered at pixel centres that may lie just outside the
// triangle (its varyings are then extrapolated, as on a GPU), and packs pixels of several
// triangles into one batch, so which lane a pixel gets is unspecified; the reference shades one
// lane at a time, and both must agree bit for bit. It is called concurrently from the worker
// threads, so it must be safe to call from several threads at once (a const callable is).
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <memory>
#include <optional>
#include <type_traits>
#include <utility>

#include "mosaic/texture.hpp"

namespace mosaic {

/// Most varyings a draw can feed its shader. 16 floats hold a normal, two UV sets, a colour and
/// a tangent (3 + 2 + 2 + 4 + 4 = 15); each costs a float plane (12 B) per triangle in the
/// frame's setup memory and a plane evaluation and a division per shaded pixel, and a batch's
/// varyings take kMaxVaryings × kShaderBatch floats (1 KiB) of the worker's stack.
inline constexpr int kMaxVaryings = 16;

/// Pixels per shader call: the lanes of the widest SIMD path (AVX-512: 16 × 32 bit), so that one
/// call covers one vector there and 2 or 4 on AVX2 or SSE4.1. Fixed on every path, so that a
/// per-pixel shader's loop has a compile-time trip count.
inline constexpr int kShaderBatch = 16;

/// One batch of pixels, structure of arrays: lane l is one pixel (or one sample under SSAA).
struct alignas(64) ShaderInput {
  // Every array starts on a 64-byte boundary (each is 64 bytes), so that the kernels store whole
  // SIMD vectors into them.
  float x[kShaderBatch];  ///< shading position in pixels, y down (pixel centre: px + 0.5)
  float y[kShaderBatch];
  /// varying[k][l]: varying k of lane l, perspective-correct. Rows k >= varying_count are unset.
  float varying[kMaxVaryings][kShaderBatch];
  /// ddx[k][l], ddy[k][l]: the derivatives of varying k of lane l along x and y, per pixel; set
  /// only for a shader made with ShaderUses::derivatives (rows k < varying_count).
  float ddx[kMaxVaryings][kShaderBatch];
  float ddy[kMaxVaryings][kShaderBatch];
  /// Bit l set: lane l will be written. Inactive lanes' varyings are 0 and their outputs are
  /// ignored; they are there so that the loop over the batch needs no branch.
  std::uint32_t active = 0;
  /// Bit l set: lane l's triangle faces the viewer (its winding is DrawState::front_face).
  std::uint32_t front_facing = 0;
  int varying_count = 0;  ///< Draw::varyings.size()
};

/// The colours of a batch, straight alpha, 0 to 1 per channel. The renderer converts each to
/// 8 bits as clamp(v * 255, 0, 255) rounded half up (NaN becomes 0).
struct alignas(64) ShaderOutput {
  float r[kShaderBatch], g[kShaderBatch], b[kShaderBatch], a[kShaderBatch];
  /// Bit l set: lane l is discarded. Read only for a shader made with ShaderUses::discards.
  std::uint32_t discard = 0;
};

/// What a shader is, after make_shader(): a function over one batch, and its state.
using ShaderFunction = void (*)(const void* state, const ShaderInput& in, ShaderOutput& out);

/// What a shader reads and does beyond its colour, declared to make_shader() so that draws pay
/// only for what their shader uses.
struct ShaderUses {
  int varyings = 0;          ///< varyings read: 0 .. varyings - 1
  bool derivatives = false;  ///< reads ShaderInput::ddx and ddy (Fragment::ddx(), sample())
  /// May set ShaderOutput::discard. Such a draw tests depth before shading but writes it after,
  /// for the lanes kept, and its pixels are shaded block by block rather than packed. A
  /// depth-only draw (DrawState::color_write off) runs no shader, so nothing is discarded there.
  bool discards = false;
};

/// One lane of a ShaderInput, for per-pixel shaders.
class Fragment {
 public:
  Fragment(const ShaderInput& in, int lane) : in_(&in), lane_(lane) {}
  float x() const { return in_->x[lane_]; }  ///< shading position in pixels
  float y() const { return in_->y[lane_]; }
  /// Varying k (0 <= k < varying count; unchecked).
  float varying(int k) const { return in_->varying[k][lane_]; }
  /// Varyings k, k + 1 (, k + 2 (, k + 3)) as a vector.
  glm::vec2 varying2(int k) const { return {varying(k), varying(k + 1)}; }
  glm::vec3 varying3(int k) const { return {varying(k), varying(k + 1), varying(k + 2)}; }
  glm::vec4 varying4(int k) const {
    return {varying(k), varying(k + 1), varying(k + 2), varying(k + 3)};
  }
  /// The derivatives of varying k along x and y, per pixel (ShaderUses::derivatives only).
  float ddx(int k) const { return in_->ddx[k][lane_]; }
  float ddy(int k) const { return in_->ddy[k][lane_]; }
  glm::vec2 ddx2(int k) const { return {ddx(k), ddx(k + 1)}; }
  glm::vec2 ddy2(int k) const { return {ddy(k), ddy(k + 1)}; }
  /// Whether this pixel's triangle faces the viewer.
  bool front_facing() const { return (in_->front_facing >> lane_) & 1u; }
  /// `texture` sampled at the UV in varyings k, k + 1, its level of detail from their
  /// derivatives (the shader must be made with ShaderUses::derivatives).
  glm::vec4 sample(const Texture& texture, const Sampler& sampler, int k) const {
    return texture.sample(sampler, varying2(k), ddx2(k), ddy2(k));
  }
  /// This pixel's lane in the batch (which lane a pixel gets is unspecified: the colour must
  /// not depend on it).
  int lane() const { return lane_; }

 private:
  const ShaderInput* in_;
  int lane_;
};

/// A fragment shader: empty (no shader: the draw's ColorSource colours it) or made by
/// make_shader(). Copyable; copies share the callable.
class Shader {
 public:
  Shader() = default;
  /// Whether this is a shader (not the empty default).
  explicit operator bool() const noexcept { return function_ != nullptr; }
  ShaderFunction function() const noexcept { return function_; }  ///< the batch function
  const void* state() const noexcept { return state_.get(); }     ///< its first argument
  /// Varyings the shader reads (varying 0 .. varyings_read() - 1); a draw must give at least
  /// this many in Draw::varyings.
  int varyings_read() const noexcept { return uses_.varyings; }
  const ShaderUses& uses() const noexcept { return uses_; }  ///< what make_shader() was told

  /// A shader from a batch function and its state (what make_shader() builds). `uses.varyings`
  /// is checked by Renderer::render() against each draw, like the rest of the draw.
  Shader(ShaderFunction fn, std::shared_ptr<const void> shared_state, const ShaderUses& uses)
      : function_(fn), state_(std::move(shared_state)), uses_(uses) {}

 private:
  ShaderFunction function_ = nullptr;
  std::shared_ptr<const void> state_;
  ShaderUses uses_;
};

namespace detail {

template <class T>
inline constexpr bool kIsOptional = false;
template <class T>
inline constexpr bool kIsOptional<std::optional<T>> = true;

// The batch loop of a per-pixel callable, instantiated in the caller's translation unit: the
// callable inlines into it. Every lane runs, active or not (inactive ones hold zeros), so the
// loop has no branch and a constant trip count. A callable returning std::optional discards
// the lanes it returns no colour for.
template <class F>
void shade_per_pixel(const void* state, const ShaderInput& in, ShaderOutput& out) {
  const F& f = *static_cast<const F*>(state);
  for (int l = 0; l < kShaderBatch; ++l) {
    glm::vec4 c;
    if constexpr (kIsOptional<std::invoke_result_t<const F&, const Fragment&>>) {
      const auto kept = f(Fragment(in, l));
      out.discard |= static_cast<std::uint32_t>(!kept) << l;
      c = kept.value_or(glm::vec4(0.0f));
    } else {
      c = f(Fragment(in, l));
    }
    out.r[l] = c.r;
    out.g[l] = c.g;
    out.b[l] = c.b;
    out.a[l] = c.a;
  }
}

template <class F>
void shade_per_batch(const void* state, const ShaderInput& in, ShaderOutput& out) {
  (*static_cast<const F*>(state))(in, out);
}

}  // namespace detail

/// Makes a Shader from a callable that uses what `uses` declares. The callable is either
///  - per pixel: `glm::vec4 f(const mosaic::Fragment&)` returning straight-alpha RGBA in 0..1, or
///    `std::optional<glm::vec4> f(const mosaic::Fragment&)`, which discards where it returns
///    std::nullopt (uses.discards is then implied), or
///  - per batch: `void f(const mosaic::ShaderInput&, mosaic::ShaderOutput&)`, filling every lane
///    (and, with uses.discards, setting ShaderOutput::discard bits).
/// It is copied into the Shader. See the top of this header for the contract (pure per lane,
/// thread-safe).
template <class F>
Shader make_shader(F f, ShaderUses uses) {
  using Fn = std::decay_t<F>;
  ShaderFunction fn = nullptr;
  if constexpr (std::is_invocable_v<const Fn&, const ShaderInput&, ShaderOutput&>) {
    fn = &detail::shade_per_batch<Fn>;
  } else {
    using R = std::invoke_result_t<const Fn&, const Fragment&>;
    static_assert(
        std::is_convertible_v<R, glm::vec4> || std::is_same_v<R, std::optional<glm::vec4>>,
        "a shader is glm::vec4(const mosaic::Fragment&), "
        "std::optional<glm::vec4>(const mosaic::Fragment&) or "
        "void(const mosaic::ShaderInput&, mosaic::ShaderOutput&)");
    fn = &detail::shade_per_pixel<Fn>;
    uses.discards = uses.discards || detail::kIsOptional<R>;
  }
  return Shader(fn, std::make_shared<const Fn>(std::move(f)), uses);
}

/// make_shader() of a shader that reads `varyings_read` varyings and nothing else.
template <class F>
Shader make_shader(F f, int varyings_read = 0) {
  return make_shader(std::move(f), ShaderUses{varyings_read, false, false});
}

/// Built-in: every pixel `color` (straight alpha, 0..1). Reads no varying.
Shader flat_color_shader(glm::vec4 color);

/// Built-in: the colour in varyings 0..3 (r, g, b, a in 0..1), e.g. a vertex colour attribute.
Shader vertex_color_shader();

/// Built-in: the normal in varyings 0..2 as a colour, rgb = 0.5 + 0.5 * normalize(n), alpha 1
/// (a zero normal is grey): for looking at a mesh's normals.
Shader normal_color_shader();

/// Built-in: the texture coordinates in varyings 0..1 as a colour, rgb = (fract(u), fract(v), 0),
/// alpha 1: for looking at a mesh's UVs (a repeating texture's tiles show as ramps).
Shader uv_color_shader();

/// Parameters of lambert_shader().
struct Lambert {
  glm::vec3 light_dir{0.0f, 0.0f, 1.0f};  ///< towards the light, in the normals' space; normalised
  glm::vec3 albedo{1.0f};                 ///< surface colour, 0..1
  float ambient = 0.15f;                  ///< light that reaches every side
  float diffuse = 0.85f;                  ///< weight of n·l
  bool two_sided = false;                 ///< |n·l| instead of max(n·l, 0): for open meshes
};

/// Built-in: Lambert lighting of the normal in varyings 0..2 (any length; normalised per pixel):
/// rgb = albedo * (ambient + diffuse * max(n·l, 0)), alpha 1, with n = normalize(varyings 0..2)
/// and l = normalize(light_dir). A zero normal is lit by the ambient term alone.
Shader lambert_shader(const Lambert& params);

}  // namespace mosaic
