// The cull of triangles that cover no sample, in setup: a box that holds no sample position
// (front/setup.hpp), or few candidates, all outside (front/sample_cull.hpp, and its lanes in the
// SIMD front end), checked against an independent exact oracle: orientation tests on the snapped
// vertices themselves, not the setup's edge functions. Tiny triangles, and needles along each
// axis and the diagonal whose boxes hold just up to and just over front::kMaxCullCandidates
// samples, on every path and sample count, drawn at the target's corner and through a viewport.
// A tested triangle that covers a sample keeps the box of its covered samples' pixels: checked
// against the oracle, and drawn through the tile kernels' one-pixel path against the reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "front/draw_area.hpp"
#include "front/sample_cull.hpp"
#include "front/setup.hpp"
#include "mosaic/mosaic.hpp"
#include "raster/sample_patterns.hpp"
#include "scenes/rng.hpp"

namespace {

using mosaic::Isa;
using Pt = std::array<std::int64_t, 2>;  // 16.8 units
constexpr std::int64_t kPx = 256;        // one pixel in 16.8 units

// Each triangle lives in its own cell, so that no two overlap.
constexpr int kCell = 40, kCellsPerRow = 8;

enum class Kind { kTiny, kNeedleX, kFatNeedleX, kNeedleY, kNeedleDiagonal };

struct Tri {
  std::array<Pt, 3> v;
  int cell = 0;  ///< the triangle lies inside cell (cell % kCellsPerRow, cell / kCellsPerRow)
  bool at_threshold = false;  ///< a needle whose box holds at most kMaxCullCandidates samples
};

std::int64_t orient(Pt a, Pt b, Pt p) {
  return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
}

// Sample positions within a pixel, in 16.8 units: the largest x and y offset of the pattern.
std::int64_t max_offset(std::span<const mosaic::raster::SampleOffset> pattern, bool y) {
  std::int64_t m = 0;
  for (const auto o : pattern)
    m = std::max(m,
                 y ? mosaic::raster::sample_y_fixed(0, o) : mosaic::raster::sample_x_fixed(0, o));
  return m;
}

// Whether the cull may test the triangle: its area is at most kCullMaxExpectedSamples samples.
bool small_area(const Tri& t, int samples) {
  const std::int64_t a2 = orient(t.v[0], t.v[1], t.v[2]);
  return (a2 < 0 ? -a2 : a2) * samples <=
         mosaic::front::kCullMaxExpectedSamples * mosaic::front::kPixelArea2;
}

// Box of a triangle as setup makes it: the pixels floor(min / 256) .. floor(max / 256).
int box_pixels(const Tri& t) {
  std::int64_t x0 = t.v[0][0], x1 = x0, y0 = t.v[0][1], y1 = y0;
  for (const Pt& p : t.v) {
    x0 = std::min(x0, p[0]);
    x1 = std::max(x1, p[0]);
    y0 = std::min(y0, p[1]);
    y1 = std::max(y1, p[1]);
  }
  return static_cast<int>((x1 / kPx - x0 / kPx + 1) * (y1 / kPx - y0 / kPx + 1));
}

// Needle and tiny triangles in cell (cx, cy). Needles lie between the pattern's last sample row
// (or column) and the next pixel, so that they cover no sample; `n` is their box length in px.
Tri make_tri(Kind kind, int n, mosaic::SplitMix64& rng, int cell,
             std::span<const mosaic::raster::SampleOffset> pattern) {
  const std::int64_t ox = (cell % kCellsPerRow) * kCell * kPx + kPx,
                     oy = (cell / kCellsPerRow) * kCell * kPx + kPx;
  const auto jitter = [&](std::int64_t lo, std::int64_t hi) {
    return lo + static_cast<std::int64_t>(rng.next() % static_cast<std::uint64_t>(hi - lo + 1));
  };
  Tri t;
  t.cell = cell;
  const std::int64_t gx = max_offset(pattern, false) + 2, gy = max_offset(pattern, true) + 2;
  switch (kind) {
    case Kind::kTiny: {
      // Up to 2.5 px: boxes of 1 to 3 pixels a side, some with samples, most without.
      const std::int64_t bx = ox + jitter(0, kPx), by = oy + jitter(0, kPx);
      for (Pt& p : t.v) p = {bx + jitter(0, 5 * kPx / 2), by + jitter(0, 5 * kPx / 2)};
      break;
    }
    case Kind::kNeedleX: {
      const std::int64_t x0 = ox + jitter(0, 20), x1 = ox + (n - 1) * kPx + jitter(200, 250);
      const std::int64_t ya = oy + jitter(gy, 250), yb = std::min<std::int64_t>(ya + 4, oy + 254);
      t.v = {Pt{x0, ya}, Pt{x1, ya}, Pt{x1, yb}};
      break;
    }
    case Kind::kFatNeedleX: {
      // As tall as the gap between sample rows: at 1x and 4x its area is over the cull's bound.
      const std::int64_t x0 = ox + jitter(0, 20), x1 = ox + (n - 1) * kPx + jitter(200, 250);
      t.v = {Pt{x0, oy + gy}, Pt{x1, oy + gy}, Pt{x1, oy + 254}};
      break;
    }
    case Kind::kNeedleY: {
      const std::int64_t y0 = oy + jitter(0, 20), y1 = oy + (n - 1) * kPx + jitter(200, 250);
      const std::int64_t xa = ox + jitter(gx, 250), xb = std::min<std::int64_t>(xa + 4, ox + 254);
      t.v = {Pt{xa, y0}, Pt{xb, y1}, Pt{xa, y1}};
      break;
    }
    case Kind::kNeedleDiagonal: {
      // From near the top-left corner of an n × n pixel box to near its bottom-right, 3 units wide.
      const std::int64_t x0 = ox + jitter(0, 40), y0 = oy + jitter(0, 40);
      const std::int64_t x1 = ox + (n - 1) * kPx + jitter(200, 250),
                         y1 = oy + (n - 1) * kPx + jitter(200, 250);
      t.v = {Pt{x0, y0}, Pt{x1, y1}, Pt{x1, y1 - 3}};
      break;
    }
  }
  return t;
}

struct Expected {
  std::vector<int> owner;  ///< per sample of the target: the triangle covering it, or -1
  std::vector<std::uint64_t> covered;  ///< per triangle
  /// Per triangle: some sample position lies in its vertices' bounding box.
  std::vector<bool> box_holds;
  std::uint64_t written = 0, culled = 0;
  /// Per triangle: some sample lies exactly on one of its edges, where the fill rule decides.
  std::vector<bool> ambiguous;
};

Expected oracle(const std::vector<Tri>& tris, int w, int h,
                std::span<const mosaic::raster::SampleOffset> pattern) {
  const int S = static_cast<int>(pattern.size());
  Expected e;
  e.owner.assign(static_cast<std::size_t>(w) * h * S, -1);
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const Tri& t = tris[i];
    std::uint64_t covered = 0;
    bool ambiguous = false, box_holds = false;
    std::int64_t bx0 = t.v[0][0], bx1 = bx0, by0 = t.v[0][1], by1 = by0;
    for (const Pt& q : t.v) {
      bx0 = std::min(bx0, q[0]);
      bx1 = std::max(bx1, q[0]);
      by0 = std::min(by0, q[1]);
      by1 = std::max(by1, q[1]);
    }
    const int cx = (t.cell % kCellsPerRow) * kCell, cy = (t.cell / kCellsPerRow) * kCell;
    for (int py = cy; py < std::min(h, cy + kCell); ++py) {
      for (int px = cx; px < std::min(w, cx + kCell); ++px) {
        for (int s = 0; s < S; ++s) {
          const Pt p{mosaic::raster::sample_x_fixed(px, pattern[s]),
                     mosaic::raster::sample_y_fixed(py, pattern[s])};
          box_holds |= p[0] >= bx0 && p[0] <= bx1 && p[1] >= by0 && p[1] <= by1;
          const std::int64_t o0 = orient(t.v[0], t.v[1], p), o1 = orient(t.v[1], t.v[2], p),
                             o2 = orient(t.v[2], t.v[0], p);
          if (o0 == 0 || o1 == 0 || o2 == 0) {
            // On an edge's line: ambiguous only if it is on the edge itself (within the box).
            const bool pos = (o0 >= 0 && o1 >= 0 && o2 >= 0), neg = (o0 <= 0 && o1 <= 0 && o2 <= 0);
            ambiguous |= pos || neg;
            continue;
          }
          if ((o0 > 0 && o1 > 0 && o2 > 0) || (o0 < 0 && o1 < 0 && o2 < 0)) {
            e.owner[(static_cast<std::size_t>(py) * w + px) * S + s] = static_cast<int>(i);
            ++covered;
          }
        }
      }
    }
    e.written += covered;
    e.covered.push_back(covered);
    e.box_holds.push_back(box_holds);
    e.ambiguous.push_back(ambiguous);
    // Setup culls a triangle whose box holds no sample position, and one whose few candidates
    // all fail.
    if (covered == 0 && (!box_holds || (box_pixels(t) * S <= mosaic::front::kMaxCullCandidates &&
                                        small_area(t, S))))
      ++e.culled;
  }
  return e;
}

mosaic::Rgba8 color_of(int i) {
  return {static_cast<std::uint8_t>(i + 1), static_cast<std::uint8_t>((i + 1) >> 8), 77, 255};
}

TEST(SampleCull, CulledTrianglesCoverNoSampleAndTheImageIsExact) {
  const std::vector<Isa> isas = mosaic::available_isas();  // the reference included
  mosaic::SplitMix64 rng{2024};
  for (int samples : {1, 4, 8, 16}) {
    const auto pattern = mosaic::raster::sample_pattern(samples);
    // The longest needle whose box still holds at most kMaxCullCandidates samples.
    const int line = mosaic::front::kMaxCullCandidates / samples;
    int diagonal = 1;
    while ((diagonal + 1) * (diagonal + 1) * samples <= mosaic::front::kMaxCullCandidates)
      ++diagonal;
    std::vector<Tri> tris;
    int cell = 0;
    for (int k = 0; k < 160; ++k) tris.push_back(make_tri(Kind::kTiny, 0, rng, cell++, pattern));
    for (int k = 0; k < 8; ++k) {
      for (const bool over : {false, true}) {
        for (const Kind kind : {Kind::kNeedleX, Kind::kNeedleY}) {
          Tri t = make_tri(kind, line + over, rng, cell++, pattern);
          t.at_threshold = !over;
          tris.push_back(t);
        }
        if (!over) tris.push_back(make_tri(Kind::kFatNeedleX, line, rng, cell++, pattern));
        Tri t = make_tri(Kind::kNeedleDiagonal, diagonal + over, rng, cell++, pattern);
        t.at_threshold = !over;
        tris.push_back(t);
      }
    }
    const int w = kCell * kCellsPerRow, h = kCell * ((cell + kCellsPerRow - 1) / kCellsPerRow);
    // The oracle leaves the fill rule to the other tests: drop triangles with a sample on an edge.
    const Expected first = oracle(tris, w, h, pattern);
    std::vector<Tri> kept;
    for (std::size_t i = 0; i < tris.size(); ++i)
      if (!first.ambiguous[i]) kept.push_back(tris[i]);
    tris = kept;
    const Expected want = oracle(tris, w, h, pattern);
    // The needles reach the threshold from both sides: some at it cover no sample (so the renders
    // must cull them), and some one pixel over it cover none either (so they must not).
    // Likewise for the area bound: at 1x and 4x the fat needles cover no sample, fit the box
    // bound, and are over the area bound, so they must not be culled.
    int empty_at = 0, empty_over = 0, empty_large = 0, empty_box = 0;
    for (std::size_t i = 0; i < tris.size(); ++i) {
      if (want.covered[i] != 0) continue;
      if (!want.box_holds[i]) {  // setup's cull: the box holds no sample position
        ++empty_box;
        continue;
      }
      const bool box_ok = box_pixels(tris[i]) * samples <= mosaic::front::kMaxCullCandidates;
      empty_at += tris[i].at_threshold && small_area(tris[i], samples);
      empty_over += !box_ok;
      empty_large += box_ok && !small_area(tris[i], samples);
    }
    std::printf(
        "%dx: %zu triangles, %llu culled; empty with a sample in the box: %d at the box\n"
        "bound, %d over it, %d over the area bound; %d with none in the box\n",
        samples, tris.size(), static_cast<unsigned long long>(want.culled), empty_at, empty_over,
        empty_large, empty_box);
    EXPECT_GT(empty_box, 0) << samples << "x";
    EXPECT_GT(empty_at, 0) << samples << "x";
    EXPECT_GT(empty_over, 0) << samples << "x";
    // At 4x the random tiny triangles include empty ones over the area bound (not culled).
    if (samples == 4) {
      EXPECT_GT(empty_large, 0);
    }

    std::vector<glm::vec4> positions;
    std::vector<mosaic::Rgba8> colors;
    for (std::size_t i = 0; i < tris.size(); ++i) {
      for (const Pt& p : tris[i].v)
        positions.push_back(
            {static_cast<float>(p[0]) / kPx, static_cast<float>(p[1]) / kPx, 0.5f, 1.0f});
      colors.push_back(color_of(static_cast<int>(i)));
    }
    mosaic::Draw d;
    d.space = mosaic::Space::kScreen;
    d.positions = positions;
    d.color_source = mosaic::ColorSource::kPerTriangle;
    d.colors = colors;
    d.state.depth_test = mosaic::DepthTest::kAlways;
    d.state.depth_write = false;
    // Through a viewport the triangles are set up in its pixels and then moved: the same culls.
    constexpr int kDx = 13, kDy = 7;
    for (const bool moved : {false, true}) {
      if (moved) d.state.viewport = mosaic::PixelRect{kDx, kDy, w, h};
      const int tw = moved ? w + kDx : w, th = moved ? h + kDy : h;
      const mosaic::Draw draws[] = {d};
      mosaic::Frame frame;
      frame.draws = draws;
      for (const Isa isa : isas) {
        for (const int threads : {1, 2}) {
          if (isa == Isa::kReference && threads == 2) continue;
          const std::string what = std::string(mosaic::to_string(isa)) + " " +
                                   std::to_string(samples) + "x " + std::to_string(threads) + "T" +
                                   (moved ? " through a viewport" : "");
          mosaic::RenderTarget target(tw, th, samples, {.keep_sample_color = true});
          ASSERT_EQ(target.sample_color().size(), static_cast<std::size_t>(tw) * th * samples);
          const mosaic::Rgba8 clear{0, 0, 0, 255};
          target.set_clear(clear, 1.0f);
          mosaic::Renderer r({.threads = threads, .isa = isa});
          const mosaic::FrameStats st = r.render(frame, target);
          EXPECT_EQ(st.triangles_no_sample, want.culled) << what;
          EXPECT_EQ(st.triangles_drawn, tris.size() - want.culled) << what;
          EXPECT_EQ(st.samples_written, want.written) << what;
          const auto sc = target.sample_color();
          std::size_t bad = 0;
          for (int y = 0; y < th; ++y) {
            for (int x = 0; x < tw; ++x) {
              const int vx = moved ? x - kDx : x, vy = moved ? y - kDy : y;
              const bool in = vx >= 0 && vy >= 0;
              for (int s = 0; s < samples; ++s) {
                const std::size_t i = (static_cast<std::size_t>(y) * tw + x) * samples + s;
                const int owner =
                    in ? want.owner[(static_cast<std::size_t>(vy) * w + vx) * samples + s] : -1;
                bad += !(sc[i] == (owner < 0 ? clear : color_of(owner)));
              }
            }
          }
          EXPECT_EQ(bad, 0u) << what;
        }
      }
    }
  }
}

// The pixels [x0, x1) × [y0, y1) holding a sample the triangle covers, by the oracle's
// orientation tests (empty when none).
struct PixelBox {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool operator==(const PixelBox&) const = default;
};
PixelBox covered_box(const Tri& t, std::span<const mosaic::raster::SampleOffset> pattern) {
  PixelBox b{1 << 20, 1 << 20, -(1 << 20), -(1 << 20)};
  const int cx = (t.cell % kCellsPerRow) * kCell, cy = (t.cell / kCellsPerRow) * kCell;
  for (int py = cy; py < cy + kCell; ++py)
    for (int px = cx; px < cx + kCell; ++px)
      for (const auto o : pattern) {
        const Pt p{mosaic::raster::sample_x_fixed(px, o), mosaic::raster::sample_y_fixed(py, o)};
        const std::int64_t o0 = orient(t.v[0], t.v[1], p), o1 = orient(t.v[1], t.v[2], p),
                           o2 = orient(t.v[2], t.v[0], p);
        if ((o0 > 0 && o1 > 0 && o2 > 0) || (o0 < 0 && o1 < 0 && o2 < 0))
          b = {std::min(b.x0, px), std::min(b.y0, py), std::max(b.x1, px + 1),
               std::max(b.y1, py + 1)};
      }
  return b.x0 < b.x1 ? b : PixelBox{};
}

TEST(SampleCull, TestedTrianglesKeepTheBoxOfTheirCoveredSamples) {
  mosaic::SplitMix64 rng{77};
  for (int samples : {1, 4, 8, 16}) {
    const auto pattern = mosaic::raster::sample_pattern(samples);
    const mosaic::front::SampleSpots spots = mosaic::front::SampleSpots::of(samples);
    int shrunk = 0, to_one_pixel = 0, kept = 0;
    for (int k = 0; k < 4000; ++k) {
      const Tri t = make_tri(Kind::kTiny, 0, rng, k % 64, pattern);
      std::array<mosaic::front::ScreenVertex, 3> v;
      for (int i = 0; i < 3; ++i) {
        v[i].x = static_cast<double>(t.v[i][0]) / kPx;
        v[i].y = static_cast<double>(t.v[i][1]) / kPx;
      }
      mosaic::DrawState state;
      state.cull = mosaic::CullMode::kNone;
      mosaic::front::TriangleSetup out;
      const auto reject = mosaic::front::setup_triangle(
          v, state, mosaic::front::DrawArea::whole(kCell * kCellsPerRow, kCell * 8), false, {}, out,
          nullptr, nullptr, &spots);
      if (reject != mosaic::front::SetupReject::kNone) continue;
      const PixelBox got{out.bx0, out.by0, out.bx1, out.by1};
      const PixelBox want = covered_box(t, pattern);
      const bool tested =
          box_pixels(t) * samples <= mosaic::front::kMaxCullCandidates && small_area(t, samples);
      // A sample on an edge is the fill rule's to decide: the box may then hold one more pixel.
      const Expected e = oracle({t}, kCell * kCellsPerRow, kCell * 8, pattern);
      if (e.ambiguous[0]) continue;
      if (tested) {
        EXPECT_EQ(got, want) << samples << "x triangle " << k;
        shrunk += box_pixels(t) != (want.x1 - want.x0) * (want.y1 - want.y0);
        to_one_pixel += (want.x1 - want.x0) * (want.y1 - want.y0) == 1;
      } else {
        // Untested: the box of its vertices, which holds the covered samples' box.
        ++kept;
        EXPECT_EQ((got.x1 - got.x0) * (got.y1 - got.y0), box_pixels(t)) << samples << "x " << k;
      }
    }
    std::printf("%dx: %d boxes shrunk, %d to one pixel, %d untested\n", samples, shrunk,
                to_one_pixel, kept);
    EXPECT_GT(shrunk, 0) << samples << "x";
    EXPECT_GT(to_one_pixel, 0) << samples << "x";
    if (samples <= 4) {
      EXPECT_GT(kept, 0) << samples << "x";
    }
  }
}

}  // namespace
