// quality/scenes.cpp — the scenes antialiasing is measured on (besides the built-in star).
//
// Takes: an image size and a seed. Gives: a zone plate of thin triangles, a watertight mesh,
// and an overlapping scene with depth. Every vertex is snapped to 1/256 px with the engine's
// front::snap before it is stored, so the float positions are exactly what the renderer draws.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "front/fixed_point.hpp"
#include "front/setup.hpp"
#include "mosaic/errors.hpp"
#include "quality/quality.hpp"
#include "scenes/rng.hpp"

namespace mosaic::quality {
namespace {

using Rng = mosaic::SplitMix64;

constexpr double kPi = 3.14159265358979323846;
/// Outer radius of the zone plate over the shorter image side: a margin of 2 % each side.
constexpr double kZoneRadius = 0.48;
/// Largest gap between a ring's true circle and its chords, px: well below the 1/4 px scale of
/// the antialiasing errors measured, so the polygonal rings read as circles.
constexpr double kZoneSagitta = 1.0 / 16.0;
/// Fewest segments per ring (the innermost disc).
constexpr int kZoneMinSegments = 16;
/// The mesh covers the middle of the image: this fraction of each side.
constexpr double kMeshCover = 0.8;
/// Mesh cells per shorter side of the covered area: cells of about 20 px at 1080p, small enough
/// that many edges and shared vertices fall in every crop.
constexpr int kMeshCellsShort = 40;
/// Interior vertices move by up to this fraction of a cell: irregular angles, no fold-overs.
constexpr double kMeshJitter = 0.3;
/// Triangles of the overlap scene and their size over the shorter side.
constexpr int kOverlapTriangles = 48;
constexpr double kOverlapSize = 0.3;
/// Alpha of every colour: the renderer does not blend.
constexpr std::uint8_t kOpaque = 255;
/// Grey background of the mesh and overlap scenes: both black and white edges show.
constexpr std::uint8_t kGrey = 128;

/// A position snapped to 1/256 px, as a float that holds it exactly (|x| < 2^15 px).
glm::vec4 snapped(double x, double y, float z = 0.5f) {
  return {static_cast<float>(front::snap(x)) / front::kSubpixelOne,
          static_cast<float>(front::snap(y)) / front::kSubpixelOne, z, 1.0f};
}

Scene empty_scene(const char* name, int width, int height, Rgba8 clear) {
  if (width < 1 || width > kMaxTargetSize || height < 1 || height > kMaxTargetSize)
    throw Error(Errc::kInvalidTargetSize, "quality scene size outside 1..16384");
  Scene s;
  s.name = name;
  s.width = width;
  s.height = height;
  s.clear_color = clear;
  return s;
}

Mesh flat_mesh() {
  Mesh m;
  m.space = Space::kScreen;
  m.color_source = ColorSource::kPerTriangle;
  return m;
}

}  // namespace

ZonePlate zone_plate_for(int width, int height) {
  ZonePlate z;
  z.cx = width / 2.0;
  z.cy = height / 2.0;
  z.radius = kZoneRadius * std::min(width, height);
  // Local frequency k * r reaches 1 cycle/px (twice Nyquist) at the outer radius.
  z.k = 1.0 / z.radius;
  return z;
}

Scene zone_plate_scene(int width, int height) {
  Scene s = empty_scene("zoneplate", width, height, {0, 0, 0, kOpaque});
  const ZonePlate z = zone_plate_for(width, height);
  Mesh m = flat_mesh();
  const Rgba8 white{255, 255, 255, kOpaque};
  // Ring boundaries at r_i = sqrt(i / k): the phase k r² / 2 grows by 1/2 cycle per ring, so
  // white rings [r_i, r_i+1] for even i make a square wave of local frequency k r.
  const int rings = static_cast<int>(std::floor(z.k * z.radius * z.radius));
  for (int i = 0; i + 1 <= rings; i += 2) {
    const double r0 = std::sqrt(i / z.k), r1 = std::sqrt((i + 1) / z.k);
    // Segments so that the chord's sagitta r (1 - cos(pi / n)) ~ r pi² / (2 n²) <= kZoneSagitta.
    const int n = std::max(kZoneMinSegments,
                           static_cast<int>(std::ceil(kPi * std::sqrt(r1 / (2 * kZoneSagitta)))));
    std::vector<glm::vec4> outer(n), inner(n);
    for (int j = 0; j < n; ++j) {
      const double a = 2 * kPi * j / n;
      outer[j] = snapped(z.cx + r1 * std::cos(a), z.cy + r1 * std::sin(a));
      inner[j] = snapped(z.cx + r0 * std::cos(a), z.cy + r0 * std::sin(a));
    }
    const glm::vec4 centre = snapped(z.cx, z.cy);
    for (int j = 0; j < n; ++j) {
      const int j1 = (j + 1) % n;
      if (i == 0) {  // the central disc: a fan
        m.positions.insert(m.positions.end(), {centre, outer[j], outer[j1]});
        m.colors.push_back(white);
        continue;
      }
      m.positions.insert(m.positions.end(), {inner[j], outer[j], outer[j1]});
      m.positions.insert(m.positions.end(), {inner[j], outer[j1], inner[j1]});
      m.colors.push_back(white);
      m.colors.push_back(white);
    }
  }
  s.meshes.push_back(std::move(m));
  return s;
}

Scene mesh_scene(int width, int height, std::uint64_t seed) {
  Scene s = empty_scene("mesh", width, height, {kGrey, kGrey, kGrey, kOpaque});
  Rng rng(seed);
  const double cw = kMeshCover * width, ch = kMeshCover * height;
  const double cell = std::min(cw, ch) / kMeshCellsShort;
  const int nx = std::max(1, static_cast<int>(cw / cell)),
            ny = std::max(1, static_cast<int>(ch / cell));
  const double x0 = (width - nx * cell) / 2, y0 = (height - ny * cell) / 2;
  std::vector<glm::vec4> grid(static_cast<std::size_t>(nx + 1) * (ny + 1));
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const bool border = i == 0 || j == 0 || i == nx || j == ny;
      const double jx = border ? 0 : rng.uniform(-kMeshJitter, kMeshJitter) * cell;
      const double jy = border ? 0 : rng.uniform(-kMeshJitter, kMeshJitter) * cell;
      grid[static_cast<std::size_t>(j) * (nx + 1) + i] =
          snapped(x0 + i * cell + jx, y0 + j * cell + jy);
    }
  }
  Mesh m = flat_mesh();
  auto at = [&](int i, int j) { return grid[static_cast<std::size_t>(j) * (nx + 1) + i]; };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      // Alternate the diagonal so edges run in both directions.
      if ((i + j) % 2 == 0) {
        m.positions.insert(m.positions.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        m.positions.insert(m.positions.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      } else {
        m.positions.insert(m.positions.end(), {at(i, j), at(i + 1, j), at(i, j + 1)});
        m.positions.insert(m.positions.end(), {at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
      m.colors.push_back(rng.color());
      m.colors.push_back(rng.color());
    }
  }
  s.meshes.push_back(std::move(m));
  return s;
}

Scene overlap_scene(int width, int height, std::uint64_t seed) {
  Scene s = empty_scene("overlap", width, height, {kGrey / 2, kGrey / 2, kGrey / 2, kOpaque});
  Rng rng(seed);
  const double size = kOverlapSize * std::min(width, height);
  Mesh m = flat_mesh();
  for (int t = 0; t < kOverlapTriangles; ++t) {
    const double cx = rng.uniform(0, width), cy = rng.uniform(0, height);
    for (int k = 0; k < 3; ++k) {
      // Depth differs per vertex, so triangles cross each other along intersection lines.
      const float z = static_cast<float>(rng.uniform(0.05, 0.95));
      m.positions.push_back(
          snapped(cx + rng.uniform(-size, size), cy + rng.uniform(-size, size), z));
    }
    m.colors.push_back(rng.color());
  }
  s.meshes.push_back(std::move(m));
  return s;
}

}  // namespace mosaic::quality
