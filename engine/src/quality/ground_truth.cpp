// quality/ground_truth.cpp — ideal box-filtered images of a scene, and error metrics.
//
// Takes: a Scene and a pixel rectangle. Gives: the exact box-filtered image (exact_area.hpp on
// every triangle and pixel), the 64×64 supersampled one (the Renderer on a magnified scene), and
// RMS / max / PSNR between images. See mosaic/quality.hpp for the contracts.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "front/fixed_point.hpp"
#include "front/setup.hpp"
#include "mosaic/errors.hpp"
#include "parallel/stage_edges.hpp"
#include "quality/exact_area.hpp"
#include "quality/quality.hpp"

namespace mosaic::quality {
namespace {

/// Largest 8-bit channel value: colours are stored as value / 255.
constexpr double kMaxChannel = 255.0;
/// Rows per band of the exact image: the unit of parallel work (few enough triangles per band
/// to bin cheaply, enough bands to keep every core busy).
constexpr int kBandRows = 8;
/// Slack of the overlap check: the per-pixel sum of areas is a sum of doubles each rounded once,
/// so a watertight partition can exceed 1 by a few ulps. The check guards against misuse (an
/// overlapping scene given to the exact path); overlaps thinner than this go unnoticed.
constexpr double kOverlapSlack = 1e-9;

void check_rect(const Scene& scene, const Rect& r) {
  if (r.width < 1 || r.height < 1 || r.x < 0 || r.y < 0 || r.x + r.width > scene.width ||
      r.y + r.height > scene.height) {
    throw Error(Errc::kInvalidArgument, "quality: rectangle outside the scene's image");
  }
}

/// A triangle ready for the ground truth: snapped vertices, colour, and its pixel bounding box.
struct GtTriangle {
  SnappedTriangle t;
  std::array<double, 3> color{};
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // pixels [x0, x1) × [y0, y1)
};

/// Vertex index `k` of triangle `tri` of a mesh, honouring its index buffer.
std::size_t vertex_index(const Mesh& m, std::size_t tri, int k) {
  const std::size_t i = 3 * tri + static_cast<std::size_t>(k);
  if (m.indices.empty()) return i;
  if (m.indices[i] >= m.positions.size())
    throw Error(Errc::kIndexOutOfRange, "quality: index out of range");
  return m.indices[i];
}

/// Checks what both ground truths need: screen space, w = 1, depth in [0, 1] and coordinates in
/// the guard band (so the renderer clips nothing and draws exactly the snapped triangle), and no
/// culling.
void check_mesh(const Mesh& m) {
  if (m.space != Space::kScreen)
    throw Error(Errc::kInvalidArgument, "quality: ground truth needs screen-space meshes");
  if (m.state.cull != CullMode::kNone)
    throw Error(Errc::kInvalidArgument, "quality: ground truth needs culling off");
  constexpr float kLimit = static_cast<float>(front::kGuardBandPx) / 2;
  for (const glm::vec4& p : m.positions) {
    if (!(p.w == 1.0f && p.z >= 0.0f && p.z <= 1.0f && std::fabs(p.x) < kLimit &&
          std::fabs(p.y) < kLimit)) {
      throw Error(Errc::kInvalidArgument,
                  "quality: ground truth needs w = 1, depth in [0, 1] and |x|, |y| < 16384");
    }
  }
}

std::array<double, 3> unit_rgb(Rgba8 c) {
  return {c.r / kMaxChannel, c.g / kMaxChannel, c.b / kMaxChannel};
}

}  // namespace

Image to_image(std::span<const Rgba8> rgba, int width, int height, Rect r) {
  if (width < 1 || height < 1 || rgba.size() != static_cast<std::size_t>(width) * height ||
      r.width < 1 || r.height < 1 || r.x < 0 || r.y < 0 || r.x + r.width > width ||
      r.y + r.height > height) {
    throw Error(Errc::kInvalidArgument, "quality: crop outside the image, or wrong buffer size");
  }
  Image img{r.width, r.height, {}};
  img.rgb.reserve(static_cast<std::size_t>(r.width) * r.height * 3);
  for (int y = r.y; y < r.y + r.height; ++y) {
    for (int x = r.x; x < r.x + r.width; ++x) {
      const Rgba8 c = rgba[static_cast<std::size_t>(y) * width + x];
      for (double v : unit_rgb(c)) img.rgb.push_back(v);
    }
  }
  return img;
}

std::vector<Rgba8> to_rgba8(const Image& image) {
  std::vector<Rgba8> out(static_cast<std::size_t>(image.width) * image.height);
  auto q = [](double v) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * kMaxChannel));
  };
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = {q(image.rgb[3 * i]), q(image.rgb[3 * i + 1]), q(image.rgb[3 * i + 2]), 255};
  return out;
}

Image exact_box_image(const Scene& scene, Rect r) {
  check_rect(scene, r);
  std::vector<GtTriangle> tris;
  for (const Mesh& m : scene.meshes) {
    check_mesh(m);
    if (m.color_source == ColorSource::kPerVertex)
      throw Error(Errc::kInvalidArgument, "quality: exact ground truth needs flat colours");
    const std::size_t n = m.triangle_count();
    if (m.color_source == ColorSource::kPerTriangle && m.colors.size() < n)
      throw Error(Errc::kInvalidDraw, "quality: fewer colours than triangles");
    for (std::size_t i = 0; i < n; ++i) {
      GtTriangle g;
      g.t = snap_triangle(m.positions[vertex_index(m, i, 0)], m.positions[vertex_index(m, i, 1)],
                          m.positions[vertex_index(m, i, 2)]);
      g.color = unit_rgb(m.color_source == ColorSource::kPerTriangle ? m.colors[i] : m.color);
      const auto [mnx, mxx] = std::minmax({g.t.x[0], g.t.x[1], g.t.x[2]});
      const auto [mny, mxy] = std::minmax({g.t.y[0], g.t.y[1], g.t.y[2]});
      // Pixels that can meet the closed triangle: floor(min) .. ceil(max) - 1, inside the rect.
      g.x0 = std::max<int>(r.x, static_cast<int>(mnx >> front::kSubpixelBits));
      g.y0 = std::max<int>(r.y, static_cast<int>(mny >> front::kSubpixelBits));
      g.x1 = std::min<int>(r.x + r.width, static_cast<int>((mxx >> front::kSubpixelBits) + 1));
      g.y1 = std::min<int>(r.y + r.height, static_cast<int>((mxy >> front::kSubpixelBits) + 1));
      if (g.x0 < g.x1 && g.y0 < g.y1) tris.push_back(g);
    }
  }
  // Bin by bands of rows, then fill the bands in parallel: each band owns its pixels.
  const int bands = (r.height + kBandRows - 1) / kBandRows;
  std::vector<std::vector<std::uint32_t>> bin(static_cast<std::size_t>(bands));
  for (std::size_t i = 0; i < tris.size(); ++i) {
    for (int b = (tris[i].y0 - r.y) / kBandRows; b <= (tris[i].y1 - 1 - r.y) / kBandRows; ++b)
      bin[static_cast<std::size_t>(b)].push_back(static_cast<std::uint32_t>(i));
  }
  const std::size_t npix = static_cast<std::size_t>(r.width) * r.height;
  std::vector<double> covered(npix, 0.0);
  std::vector<double> color(npix * 3, 0.0);
  std::atomic<bool> overlap{false};
  parallel::StageEdges edges;
  tbb::parallel_for(0, bands, edges.task([&](int b) {
    const int yb0 = r.y + b * kBandRows, yb1 = std::min(r.y + r.height, yb0 + kBandRows);
    for (std::uint32_t i : bin[static_cast<std::size_t>(b)]) {
      const GtTriangle& g = tris[i];
      for (int y = std::max(yb0, g.y0); y < std::min(yb1, g.y1); ++y) {
        for (int x = g.x0; x < g.x1; ++x) {
          const double a = coverage(g.t, x, y);
          if (a == 0.0) continue;
          const std::size_t p = static_cast<std::size_t>(y - r.y) * r.width + (x - r.x);
          covered[p] += a;
          for (int c = 0; c < 3; ++c) color[3 * p + c] += a * g.color[c];
        }
      }
    }
    for (int y = yb0; y < yb1; ++y) {
      for (int x = 0; x < r.width; ++x) {
        if (covered[static_cast<std::size_t>(y - r.y) * r.width + x] > 1.0 + kOverlapSlack)
          overlap = true;
      }
    }
  }));
  edges.join();
  if (overlap)
    throw Error(Errc::kInvalidArgument,
                "quality: triangles overlap, the exact ground truth needs a partition");
  const std::array<double, 3> clear = unit_rgb(scene.clear_color);
  Image img{r.width, r.height, std::vector<double>(npix * 3)};
  for (std::size_t p = 0; p < npix; ++p) {
    const double rest = std::max(0.0, 1.0 - covered[p]);
    for (int c = 0; c < 3; ++c) img.rgb[3 * p + c] = color[3 * p + c] + rest * clear[c];
  }
  return img;
}

Image magnified_means(Rect r, int grid, const std::function<void(Rect, RenderTarget&)>& render) {
  // Tile edge in pixels: at a grid of 64 the magnified tile (4096 px square) costs 128 MiB of
  // colour and depth, and stays well under kMaxTargetSize.
  constexpr int kTile = 64;
  Image img{r.width, r.height,
            std::vector<double>(static_cast<std::size_t>(r.width) * r.height * 3)};
  for (int ty = r.y; ty < r.y + r.height; ty += kTile) {
    for (int tx = r.x; tx < r.x + r.width; tx += kTile) {
      const int tw = std::min(kTile, r.x + r.width - tx), th = std::min(kTile, r.y + r.height - ty);
      RenderTarget target(tw * grid, th * grid, 1);
      render({tx, ty, tw, th}, target);
      const std::span<const Rgba8> px = target.color();
      for (int y = 0; y < th; ++y) {
        for (int x = 0; x < tw; ++x) {
          std::array<std::uint64_t, 3> sum{};
          for (int sy = 0; sy < grid; ++sy) {
            const std::size_t row = static_cast<std::size_t>(y * grid + sy) * target.width();
            for (int sx = 0; sx < grid; ++sx) {
              const Rgba8 c = px[row + static_cast<std::size_t>(x * grid + sx)];
              sum[0] += c.r;
              sum[1] += c.g;
              sum[2] += c.b;
            }
          }
          const std::size_t p = static_cast<std::size_t>(ty - r.y + y) * r.width + (tx - r.x + x);
          for (int c = 0; c < 3; ++c)
            img.rgb[3 * p + c] = static_cast<double>(sum[c]) / (grid * grid * kMaxChannel);
        }
      }
    }
  }
  return img;
}

Image supersampled_image(const Scene& scene, Rect r, Renderer& renderer) {
  check_rect(scene, r);
  for (const Mesh& m : scene.meshes) check_mesh(m);
  constexpr int kGrid = kSupersampleGrid;
  // 1/256 px units per magnified pixel's 1/256: magnifying by 64 turns a 16.8 coordinate s into
  // s * 64 / 256 = s / 4 magnified pixels, a multiple of 1/4, exact in float below 2^22.
  constexpr float kUnitsToMagnified = static_cast<float>(front::kSubpixelOne) / kGrid;
  return magnified_means(r, kGrid, [&](Rect tile, RenderTarget& target) {
    Scene big;
    big.width = tile.width * kGrid;
    big.height = tile.height * kGrid;
    big.clear_color = scene.clear_color;
    big.clear_depth = scene.clear_depth;
    const std::int64_t ox = std::int64_t{tile.x} * front::kSubpixelOne;
    const std::int64_t oy = std::int64_t{tile.y} * front::kSubpixelOne;
    for (const Mesh& m : scene.meshes) {
      Mesh copy = m;
      for (glm::vec4& p : copy.positions) {
        // The snapped position, magnified exactly. Triangles reaching past the magnified
        // guard band (512 px of the original around the tile) are clipped there; the clip
        // moves their far vertices by under 1/256 magnified px, which tilts an edge by under
        // 1e-5 px inside the tile: far below kSupersampleBoundPerEdge.
        const std::int64_t sx = front::snap(p.x) - ox, sy = front::snap(p.y) - oy;
        p.x = static_cast<float>(sx) / kUnitsToMagnified;
        p.y = static_cast<float>(sy) / kUnitsToMagnified;
      }
      big.meshes.push_back(std::move(copy));
    }
    target.set_clear(big.clear_color, big.clear_depth);
    const std::vector<Draw> draws = big.draws();
    renderer.render(Frame{draws, false, false}, target);
  });
}

ErrorStats compare(const Image& truth, const Image& test) {
  if (truth.width != test.width || truth.height != test.height ||
      truth.rgb.size() != test.rgb.size() || truth.rgb.empty()) {
    throw Error(Errc::kInvalidArgument, "quality: images of different sizes");
  }
  double sq = 0, mx = 0;
  for (std::size_t i = 0; i < truth.rgb.size(); ++i) {
    const double d = test.rgb[i] - truth.rgb[i];
    sq += d * d;
    mx = std::max(mx, std::fabs(d));
  }
  ErrorStats s;
  s.rms = std::sqrt(sq / static_cast<double>(truth.rgb.size()));
  s.max = mx;
  s.psnr = s.rms > 0 ? 20.0 * std::log10(1.0 / s.rms) : std::numeric_limits<double>::infinity();
  return s;
}

void write_png(const std::filesystem::path& path, std::span<const Rgba8> rgba, int width,
               int height) {
  RenderTarget holder(width, height, 1);
  if (rgba.size() != holder.color().size())
    throw Error(Errc::kInvalidArgument, "quality: image buffer size does not match its size");
  std::copy(rgba.begin(), rgba.end(), holder.color_storage().begin());
  write_image(holder, path);
}

}  // namespace mosaic::quality
