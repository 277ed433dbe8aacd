#include "shade/shading.hpp"

namespace mosaic::shade {

void frame_shading(std::span<const Draw> draws, std::vector<DrawShading>& out) {
  out.clear();
  bool any = false;
  for (const Draw& d : draws) {
    DrawShading s;
    s.function = d.shader.function();
    s.state = d.shader.state();
    s.varyings = s.function ? static_cast<int>(d.varyings.size()) : 0;
    s.generic = s.function != nullptr || d.state.blend != BlendMode::kNone;
    any = any || s.generic;
    out.push_back(s);
  }
  if (!any) out.clear();
}

Rgba8 shade_one(const front::TriangleSetup& t, const DrawShading& s, const front::Plane* planes,
                float x, float y, int lane) {
  if (!s.function) return front::shade(t, planes, x, y);
  ShaderInput in{};  // every lane but `lane` inactive, its varyings 0
  in.x[lane] = x;
  in.y[lane] = y;
  in.active = 1u << lane;
  in.varying_count = s.varyings;
  if (s.varyings > 0) {
    const float q = front::eval_plane(planes[t.planes_base], t.x0, t.y0, x, y);
    for (int k = 0; k < s.varyings; ++k) in.varying[k][lane] = varying_at(t, planes, k, q, x, y);
  }
  ShaderOutput out{};
  s.function(s.state, in, out);
  return {output_to_unorm8(out.r[lane]), output_to_unorm8(out.g[lane]),
          output_to_unorm8(out.b[lane]), output_to_unorm8(out.a[lane])};
}

}  // namespace mosaic::shade
