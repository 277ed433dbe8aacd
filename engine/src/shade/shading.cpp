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
    s.derivatives = s.function && d.shader.uses().derivatives;
    s.discards = s.function && d.shader.uses().discards;
    s.generic = s.function != nullptr || d.state.blend != BlendMode::kNone;
    any = any || s.generic;
    out.push_back(s);
  }
  if (!any) out.clear();
}

Shaded shade_one(const front::TriangleSetup& t, const DrawShading& s, const front::Plane* planes,
                 float x, float y, int lane) {
  if (!s.function) return {front::shade(t, planes, x, y)};
  ShaderInput in{};  // every lane but `lane` inactive, its varyings 0
  in.x[lane] = x;
  in.y[lane] = y;
  in.active = 1u << lane;
  in.front_facing = front_lanes(t) & (1u << lane);
  in.varying_count = s.varyings;
  if (s.varyings > 0) {
    const front::Plane* p = planes + t.planes_base;  // q, then the varyings
    const float q = front::eval_plane(p[0], t.x0, t.y0, x, y);
    for (int k = 0; k < s.varyings; ++k) {
      const float v = varying_at(t, planes, k, q, x, y);
      in.varying[k][lane] = v;
      if (s.derivatives) {
        in.ddx[k][lane] = varying_slope(p[1 + k].ddx, p[0].ddx, v, q);
        in.ddy[k][lane] = varying_slope(p[1 + k].ddy, p[0].ddy, v, q);
      }
    }
  }
  ShaderOutput out{};
  s.function(s.state, in, out);
  const Rgba8 c{output_to_unorm8(out.r[lane]), output_to_unorm8(out.g[lane]),
                output_to_unorm8(out.b[lane]), output_to_unorm8(out.a[lane])};
  return {c, s.discards && ((out.discard >> lane) & 1u)};
}

}  // namespace mosaic::shade
