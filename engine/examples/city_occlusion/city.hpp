// city.hpp — a generated city for the occlusion workflow: buildings that occlude, objects to
// test against them, and a street-level camera.
//
// Takes: blocks per side, objects, the target's aspect and a seed. Gives: the buildings as one
// indexed world-space mesh (the occluders; each a box without its bottom, 10 triangles, wound
// counter-clockwise seen from outside), the objects as world-space boxes (the occludees: cars on
// the streets and units on the roofs) and the camera's view-projection (clip space with depth in
// [0, 1], as mosaic draws it). Deterministic for given arguments. Uses only glm and the public
// mosaic API, so that the example and the tests share it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <mosaic/mosaic.hpp>
#include <vector>

namespace city {

/// A block's side and a street's width, in metres: a block pitch of 74 m, as in a dense grid.
inline constexpr float kBlock = 60.0f, kStreet = 14.0f;
/// Each block holds kLots × kLots buildings, each inset from its lot by up to kInset metres.
inline constexpr int kLots = 2;
inline constexpr float kInset = 4.0f;
/// Building heights: kMinHeight to kMaxHeight metres, taller towards the centre of the city.
inline constexpr float kMinHeight = 8.0f, kMaxHeight = 90.0f;
/// A car's size (length, height, width) and a roof unit's (side, height), in metres.
inline constexpr glm::vec3 kCar{4.5f, 1.5f, 1.8f};
inline constexpr float kUnitSide = 3.0f, kUnitHeight = 2.0f;
/// The camera: eye height, vertical field of view, near plane, and its heading against the
/// street it stands in (enough to look past the first corner into the blocks).
inline constexpr float kEyeHeight = 1.7f;
inline constexpr float kFovY = 1.0471976f;  // 60 degrees
inline constexpr float kNear = 0.5f;
inline constexpr float kHeading = 0.35f;  // radians off the street's axis
/// Triangles of one building: four walls and a roof, two each (no bottom: never seen).
inline constexpr int kBuildingTriangles = 10;

struct City {
  std::vector<glm::vec3> positions;    ///< the buildings' corners, world space (y up)
  std::vector<std::uint32_t> indices;  ///< their triangles
  std::vector<mosaic::Rgba8> colors;   ///< one per triangle: facade or roof, lit by its side
  std::vector<mosaic::Box> objects;    ///< the occludees, world space
  glm::mat4 view_proj{1.0f};           ///< world to clip space
  int buildings = 0;
};

/// A small deterministic generator (SplitMix64): the same city on every platform.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  /// Uniform in [lo, hi).
  float uniform(float lo, float hi) {
    return lo + (hi - lo) * static_cast<float>(static_cast<double>(next() >> 11) * 0x1.0p-53);
  }

 private:
  std::uint64_t state_;
};

/// The lit colour of a face of `base` whose outward normal is `n` (axis-aligned).
inline mosaic::Rgba8 shade(mosaic::Rgba8 base, const glm::vec3& n) {
  // Sun from up, left and in front: each side of a box gets its own brightness.
  const float light =
      n.y > 0 ? 1.0f : (n.x != 0 ? (n.x > 0 ? 0.8f : 0.55f) : (n.z > 0 ? 0.7f : 0.45f));
  auto ch = [&](std::uint8_t v) {
    return static_cast<std::uint8_t>(std::lround(static_cast<float>(v) * light));
  };
  return {ch(base.r), ch(base.g), ch(base.b), 255};
}

/// Appends a box without its bottom: 8 corners, 10 triangles counter-clockwise seen from
/// outside, and their colours.
inline void append_box(const mosaic::Box& b, mosaic::Rgba8 base, std::vector<glm::vec3>& pos,
                       std::vector<std::uint32_t>& idx, std::vector<mosaic::Rgba8>& colors) {
  const auto o = static_cast<std::uint32_t>(pos.size());
  for (int k = 0; k < 8; ++k)
    pos.emplace_back((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
                     (k & 4) ? b.max.z : b.min.z);
  // Corner k has x from bit 0, y from bit 1, z from bit 2. Each face: its four corners in
  // counter-clockwise order seen from outside, and its normal.
  struct Face {
    std::array<std::uint32_t, 4> c;
    glm::vec3 n;
  };
  static constexpr std::array<Face, 5> kFaces{{
      {{1, 3, 7, 5}, {1, 0, 0}},   // +x
      {{0, 4, 6, 2}, {-1, 0, 0}},  // -x
      {{4, 5, 7, 6}, {0, 0, 1}},   // +z
      {{0, 2, 3, 1}, {0, 0, -1}},  // -z
      {{2, 6, 7, 3}, {0, 1, 0}},   // +y, the roof
  }};
  for (const Face& f : kFaces) {
    idx.insert(idx.end(), {o + f.c[0], o + f.c[1], o + f.c[2], o + f.c[0], o + f.c[2], o + f.c[3]});
    colors.insert(colors.end(), 2, shade(base, f.n));
  }
}

/// The city of `blocks` × `blocks` blocks with `objects` occludees, for a target of the given
/// width / height, from `seed`.
inline City make_city(int blocks, int objects, float aspect, std::uint64_t seed = 1) {
  static constexpr std::array<mosaic::Rgba8, 4> kFacades{
      {{178, 160, 140, 255}, {140, 150, 165, 255}, {190, 185, 175, 255}, {120, 115, 125, 255}}};
  City c;
  Random rng(seed);
  const float pitch = kBlock + kStreet, extent = static_cast<float>(blocks) * pitch;
  const float centre = extent / 2;
  std::vector<mosaic::Box> roofs;
  for (int bz = 0; bz < blocks; ++bz)
    for (int bx = 0; bx < blocks; ++bx)
      for (int lz = 0; lz < kLots; ++lz)
        for (int lx = 0; lx < kLots; ++lx) {
          const float lot = kBlock / static_cast<float>(kLots);
          const float x0 = kStreet + static_cast<float>(bx) * pitch + static_cast<float>(lx) * lot;
          const float z0 = kStreet + static_cast<float>(bz) * pitch + static_cast<float>(lz) * lot;
          // Taller near the centre: the height's range shrinks with distance from it.
          const float d = std::hypot(x0 - centre, z0 - centre) / centre;
          const float top = kMinHeight + (kMaxHeight - kMinHeight) * std::max(0.15f, 1 - d);
          mosaic::Box b;
          b.min = {x0 + rng.uniform(0, kInset), 0, z0 + rng.uniform(0, kInset)};
          b.max = {x0 + lot - rng.uniform(0, kInset), rng.uniform(kMinHeight, top),
                   z0 + lot - rng.uniform(0, kInset)};
          append_box(b, kFacades[rng.next() % kFacades.size()], c.positions, c.indices, c.colors);
          roofs.push_back(b);
          ++c.buildings;
        }
  // Objects: half cars in the streets (either direction), half units on random roofs.
  for (int i = 0; i < objects; ++i) {
    mosaic::Box o;
    if (i % 2 == 0) {
      const bool along_x = rng.next() % 2 == 0;
      const float street = static_cast<float>(rng.next() % static_cast<std::uint64_t>(blocks + 1));
      const float across = street * pitch + rng.uniform(1, kStreet - 1 - kCar.z);
      const float along = rng.uniform(0, extent - kCar.x);
      const glm::vec3 size = along_x ? kCar : glm::vec3(kCar.z, kCar.y, kCar.x);
      o.min = along_x ? glm::vec3(along, 0, across) : glm::vec3(across, 0, along);
      o.max = o.min + size;
    } else {
      const mosaic::Box& r = roofs[rng.next() % roofs.size()];
      const float x = rng.uniform(r.min.x, std::max(r.min.x, r.max.x - kUnitSide));
      const float z = rng.uniform(r.min.z, std::max(r.min.z, r.max.z - kUnitSide));
      o.min = {x, r.max.y, z};
      o.max = {x + kUnitSide, r.max.y + kUnitHeight, z + kUnitSide};
    }
    c.objects.push_back(o);
  }
  // The eye stands in the second street, a block into the city, and looks along it, turned
  // towards the centre.
  const glm::vec3 eye{pitch + kStreet / 2, kEyeHeight, pitch * 0.5f};
  const glm::vec3 ahead{std::sin(kHeading), 0, std::cos(kHeading)};
  const float far_plane = 1.5f * extent;
  c.view_proj = glm::perspectiveRH_ZO(kFovY, aspect, kNear, far_plane) *
                glm::lookAtRH(eye, eye + ahead, glm::vec3(0, 1, 0));
  return c;
}

/// The objects as triangles (boxes without bottoms, like the buildings), for drawing some of
/// them: those whose `pick` is set, or all when `pick` is empty.
inline void object_mesh(const City& c, const std::vector<std::uint8_t>& pick,
                        std::vector<glm::vec3>& pos, std::vector<std::uint32_t>& idx,
                        std::vector<mosaic::Rgba8>& colors) {
  static constexpr std::array<mosaic::Rgba8, 4> kPaints{
      {{200, 40, 40, 255}, {230, 190, 40, 255}, {40, 90, 200, 255}, {225, 225, 225, 255}}};
  for (std::size_t i = 0; i < c.objects.size(); ++i)
    if (pick.empty() || pick[i])
      append_box(c.objects[i], kPaints[i % kPaints.size()], pos, idx, colors);
}

}  // namespace city
