// The occlusion workflow of engine/examples/city_occlusion on its generated city, on the
// reference and every SIMD path: a depth-only occluder pass that keeps the hierarchical z, one
// batch of box queries, and a final frame of the visible objects only.
//
// The guarantee checked: at the occluder pass's own size and sample count, an object reported
// hidden writes no sample when it is drawn after the occluders, so the final frame with the
// visible objects only is bit-identical to the one with every object. And the queries are
// useful: most of the city's objects are hidden from the street, and the answers are the same
// on every path.
//
// What breaks it: a box projection that is not conservative (a corner rounded away from the
// box, a nearest depth rounded far), a hierarchical z whose far bound is too near, a query that
// reads the wrong block, or an occluder pass that differs between paths.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "city.hpp"
#include "mosaic/mosaic.hpp"

namespace mosaic {
namespace {

// A small city at a small size: 8 × 8 blocks (256 buildings), 1,200 objects, 320 × 180.
constexpr int kBlocks = 8, kObjects = 1200, kW = 320, kH = 180;

const city::City& small_city() {
  static const city::City c =
      city::make_city(kBlocks, kObjects, static_cast<float>(kW) / static_cast<float>(kH));
  return c;
}

Draw world_draw(const std::vector<glm::vec3>& pos, const std::vector<std::uint32_t>& idx,
                const std::vector<Rgba8>& colors, const glm::mat4& view_proj,
                CullMode cull = CullMode::kBack) {
  Draw d;
  d.positions_xyz = pos;
  d.indices = idx;
  d.transform = view_proj;
  d.color_source = ColorSource::kPerTriangle;
  d.colors = colors;
  d.state.cull = cull;
  return d;
}

// One frame's image, sample depths and counters.
struct Shot {
  std::vector<Rgba8> color;
  std::vector<float> depth;
  FrameStats stats;
};

Shot render(Renderer& r, std::span<const Draw> draws) {
  RenderTarget t(kW, kH, 1, TargetOptions{true, false});
  Frame f;
  f.draws = draws;
  Shot s;
  s.stats = r.render(f, t);
  s.color.assign(t.color().begin(), t.color().end());
  s.depth.assign(t.sample_depth().begin(), t.sample_depth().end());
  return s;
}

bool same(const Shot& a, const Shot& b) {
  return a.color == b.color && a.depth.size() == b.depth.size() &&
         std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)) == 0;
}

// The occluder pass and the queries on `isa`: the visibility of every object.
std::vector<std::uint8_t> query(Renderer& r) {
  const city::City& c = small_city();
  Draw occluders = world_draw(c.positions, c.indices, c.colors, c.view_proj);
  occluders.state.color_write = false;
  Frame f;
  f.draws = std::span<const Draw>(&occluders, 1);
  f.keep_hierarchical_z = true;
  RenderTarget t(kW, kH, 1);
  r.render(f, t);
  std::vector<std::uint8_t> visible(c.objects.size());
  r.hierarchical_z().boxes_visible(c.objects, c.view_proj, visible);
  return visible;
}

TEST(CityOcclusion, HiddenObjectsWriteNoSampleAndTheVisibleOnesMakeTheSameFrame) {
  const city::City& c = small_city();
  std::vector<std::uint8_t> first;
  for (Isa isa : available_isas()) {
    SCOPED_TRACE(to_string(isa));
    Renderer r(RendererOptions{2, isa});
    const std::vector<std::uint8_t> visible = query(r);
    const auto shown = static_cast<std::size_t>(std::count(visible.begin(), visible.end(), 1));
    // Useful: most objects are hidden from the street, and some are seen.
    EXPECT_GT(c.objects.size() - shown, c.objects.size() / 2);
    EXPECT_GT(shown, 10u);
    if (first.empty()) first = visible;
    EXPECT_TRUE(visible == first) << "the answers differ from the reference's";

    std::vector<std::uint8_t> hidden(visible.size());
    for (std::size_t i = 0; i < visible.size(); ++i) hidden[i] = visible[i] ? 0 : 1;
    std::vector<glm::vec3> pos[3];
    std::vector<std::uint32_t> idx[3];
    std::vector<Rgba8> col[3];
    city::object_mesh(c, {}, pos[0], idx[0], col[0]);
    city::object_mesh(c, visible, pos[1], idx[1], col[1]);
    city::object_mesh(c, hidden, pos[2], idx[2], col[2]);
    const Draw buildings = world_draw(c.positions, c.indices, c.colors, c.view_proj);
    auto with = [&](int k) {
      const std::vector<Draw> draws{buildings, world_draw(pos[k], idx[k], col[k], c.view_proj)};
      return render(r, draws);
    };
    const Shot alone = render(r, std::span<const Draw>(&buildings, 1));
    const Shot all = with(0), only_visible = with(1), only_hidden = with(2);
    // Not one sample of a hidden object passes the depth test against the buildings.
    EXPECT_EQ(only_hidden.stats.samples_written, alone.stats.samples_written);
    EXPECT_GT(only_hidden.stats.triangles_drawn, alone.stats.triangles_drawn);
    EXPECT_TRUE(same(only_hidden, alone));
    EXPECT_TRUE(same(all, only_visible));
    EXPECT_GT(all.stats.samples_written, alone.stats.samples_written);  // objects are seen
  }
}

// The buildings face outwards (counter-clockwise seen from outside), so the example may cull
// their back faces: culling back faces leaves the depth as drawing both, culling front faces
// does not.
TEST(CityOcclusion, BuildingsAreWoundOutwards) {
  const city::City& c = small_city();
  Renderer r(RendererOptions{2});
  auto shot = [&](CullMode cull) {
    const Draw d = world_draw(c.positions, c.indices, c.colors, c.view_proj, cull);
    return render(r, std::span<const Draw>(&d, 1));
  };
  const Shot none = shot(CullMode::kNone), back = shot(CullMode::kBack),
             front = shot(CullMode::kFront);
  EXPECT_TRUE(none.depth == back.depth);
  EXPECT_FALSE(none.depth == front.depth);
  EXPECT_GT(back.stats.triangles_culled_face, 0u);
}

}  // namespace
}  // namespace mosaic
