// quality/quality.hpp — measuring antialiasing: ground truth images, error metrics, aliasing
// energy, and the scenes they are measured on.
//
// Takes: Scenes and rendered RGBA8 images. Gives: the ideal box-filtered image of a scene
// (exact, from the area of every triangle inside every pixel), or a 64×64-sample supersampled
// one for scenes with overlap and depth; RMS / max error and PSNR against it; the aliasing
// energy of a zone plate measured in the frequency domain (FFTW); and spectrum images.
// `mosaic report` (engine/cli/report_command.cpp) puts them together. It is the library
// mosaic_quality (GMP rationals, FFTW), a tool of this repository kept out of the installed
// libmosaic so that its users need neither.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <vector>

#include "mosaic/render_target.hpp"
#include "mosaic/renderer.hpp"
#include "mosaic/scene.hpp"
#include "mosaic/texture.hpp"
#include "mosaic/types.hpp"

namespace mosaic::quality {

/// A rectangle of pixels [x, x + width) × [y, y + height).
struct Rect {
  int x = 0, y = 0, width = 0, height = 0;
};

/// An RGB image with double channels in [0, 1] (an 8-bit value v is v / 255). Alpha is not
/// kept: the renderer does not blend, and every scene here is opaque.
struct Image {
  int width = 0, height = 0;
  std::vector<double> rgb;  ///< 3 per pixel, row-major, top row first
  double at(int x, int y, int c) const {
    return rgb[(static_cast<std::size_t>(y) * width + x) * 3 + c];
  }
};

/// The crop `rect` of a width × height RGBA8 image. Throws Error{kInvalidArgument} if the
/// rectangle does not lie inside the image or the buffer has the wrong size.
Image to_image(std::span<const Rgba8> rgba, int width, int height, Rect rect);
/// An Image rounded back to RGBA8 (alpha 255), for writing it out.
std::vector<Rgba8> to_rgba8(const Image& image);

/// The exact box-filtered image of `rect` of a scene whose triangles do not overlap: every pixel
/// is sum(area_t * colour_t) + (1 - sum(area_t)) * clear, with area_t the exact area of
/// triangle t inside the pixel (computed in rationals on the snapped 16.8 vertices, rounded once
/// to double). Needs screen-space meshes (w = 1, depth in [0, 1], inside the guard band) with
/// constant or per-triangle colour; throws Error{kInvalidArgument} otherwise, and when the
/// triangles in a pixel cover more than the pixel (they overlap: use supersampled_image).
Image exact_box_image(const Scene& scene, Rect rect);

/// Grid of the supersampled ground truth: kSupersampleGrid² samples per pixel.
inline constexpr int kSupersampleGrid = 64;
/// Worst-case error of the supersampled ground truth, per straight boundary crossing a pixel,
/// in units of the colour step across it: a line crosses at most 2 * 64 - 1 strata of the
/// 64 × 64 grid, and each one misjudged costs at most its area 1 / 4096.
inline constexpr double kSupersampleBoundPerEdge =
    (2.0 * kSupersampleGrid - 1.0) / (double{kSupersampleGrid} * kSupersampleGrid);

/// The box-filtered image of `rect` estimated with a regular 64 × 64 grid of samples per pixel
/// (one at the centre of each stratum), for scenes with overlap and depth. It renders the scene
/// with `renderer`, magnified 64 times, one 64 × 64-pixel tile of `rect` at a time, and averages
/// each 64 × 64 block. Error bound: kSupersampleBoundPerEdge per visible boundary crossing the
/// pixel (edges and intersection lines). Same scene requirements as exact_box_image except that
/// overlap and per-vertex colour are allowed.
Image supersampled_image(const Scene& scene, Rect rect, Renderer& renderer);

/// The mechanism of both supersampled ground truths: `rect` in tiles of at most 64 × 64 pixels;
/// render(tile, target) draws the pixels `tile` magnified `grid` times into `target` (1 sample,
/// tile.width * grid × tile.height * grid), and each pixel is the mean of its grid × grid block.
Image magnified_means(Rect rect, int grid, const std::function<void(Rect, RenderTarget&)>& render);

/// Error of `test` against `truth` over every pixel and RGB channel, in units of the full
/// colour range (1 = 255).
struct ErrorStats {
  double rms = 0;   ///< root mean square
  double max = 0;   ///< largest absolute error
  double psnr = 0;  ///< 20 log10(1 / rms) dB; +infinity when rms is 0
};
/// Throws Error{kInvalidArgument} unless both images have the same size.
ErrorStats compare(const Image& truth, const Image& test);

/// A zone plate: concentric rings alternating white and black on a black background, with ring
/// boundaries at radii sqrt(i / k) px, so the local frequency at radius r is k * r cycles/px.
/// It reaches the Nyquist frequency (0.5 cycles/px) at radius 0.5 / k and twice that at
/// `radius`, the outer edge.
struct ZonePlate {
  double cx = 0, cy = 0;  ///< centre, pixels
  double k = 0;           ///< chirp rate, cycles/px²
  double radius = 0;      ///< outer radius, pixels
  /// Radius where the local frequency is the Nyquist frequency.
  double nyquist_radius() const { return 0.5 / k; }
};
/// The zone plate fitted to a width × height image.
ZonePlate zone_plate_for(int width, int height);
/// The zone plate as a scene: thin triangles (each ring is a band of quads), flat white on black.
Scene zone_plate_scene(int width, int height);
/// A watertight mesh: a jittered grid of flat-coloured triangles sharing every edge, on a grey
/// background, covering the middle of the image. Deterministic for a size and seed.
Scene mesh_scene(int width, int height, std::uint64_t seed = 1);
/// Overlap and depth: random triangles that interpenetrate (per-vertex depth), for the
/// supersampled ground truth.
Scene overlap_scene(int width, int height, std::uint64_t seed = 1);

/// Texture aliasing: a black-and-white checkerboard texture (kTexturePlaneSize texels square,
/// cells of 8 texels, mipmapped by the library) on a floor seen at a grazing angle, so that the
/// texture is magnified near the camera and minified to about 3 cells per pixel far away.
inline constexpr int kTexturePlaneSize = 256;
/// Grid of the floor's ground truth: kTextureTruthGrid² point samples per pixel.
inline constexpr int kTextureTruthGrid = 8;
/// The floor rendered into `target` (at its size and sample count), its texture read with
/// `sampler`.
void render_textured_plane(const Sampler& sampler, RenderTarget& target, Renderer& renderer);
/// The floor's ground truth: the same camera rendered kTextureTruthGrid times larger with
/// nearest sampling and no mipmaps (point samples of the texture), each pixel the mean of its
/// kTextureTruthGrid² block: the box filter of the textured floor, up to the error of a regular
/// 8 × 8 grid on cells that are down to a third of a pixel wide.
Image textured_plane_truth(int width, int height, Renderer& renderer);

/// An annulus of pixels, the window of aliasing_energy().
struct Annulus {
  double cx = 0, cy = 0, r_in = 0, r_out = 0;
};
/// Aliasing energy of an image in a window where the scene has no content below the Nyquist
/// frequency (for the zone plate: radii beyond nyquist_radius()): everything an image shows
/// there is aliasing, energy the sampling folded back below Nyquist. Defined as
///   A = sum over DFT frequencies f != 0 of |DFT(w * (L - mean_w L))(f)|^2 / (N * sum w),
/// with L the Rec. 709 luma of the image (channel values in [0, 1], no linearisation), w the
/// window's indicator, N = width * height, the DFT unnormalised (FFTW's). By Parseval it is the
/// mean square luma deviation per window pixel; 0 for a perfectly band-limited image, and 0.25
/// for a full-contrast square wave left unfiltered.
double aliasing_energy(const Image& image, const Annulus& window);

/// The log power spectrum of the image's luma as a grey image of the same size, zero frequency
/// in the middle: 10 log10(|DFT(L - mean L)|^2 / N^2) mapped linearly from kSpectrumFloorDb
/// (black) to kSpectrumCeilDb (white), so that spectra of different images compare directly.
std::vector<Rgba8> spectrum_image(const Image& image);
inline constexpr double kSpectrumFloorDb = -100.0;
inline constexpr double kSpectrumCeilDb = -20.0;

/// Writes an RGBA8 buffer (width × height) as PNG. Throws Error{kIo} or Error{kInvalidArgument}.
void write_png(const std::filesystem::path& path, std::span<const Rgba8> rgba, int width,
               int height);

}  // namespace mosaic::quality
