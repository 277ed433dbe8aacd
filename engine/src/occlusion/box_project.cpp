// occlusion/box_project.cpp — the scalar reference of the box projection (box_project.hpp).
#include "occlusion/box_project.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mosaic::occlusion {

void project_boxes(const Box* boxes, std::size_t n, const BoxView& v, Projected* out) {
  for (std::size_t i = 0; i < n; ++i) {
    const double lo[3] = {boxes[i].min.x, boxes[i].min.y, boxes[i].min.z};
    const double hi[3] = {boxes[i].max.x, boxes[i].max.y, boxes[i].max.z};
    double base[4], edge[3][4];
    for (int r = 0; r < 4; ++r) {
      base[r] = ((v.m[0][r] * lo[0] + v.m[1][r] * lo[1]) + v.m[2][r] * lo[2]) + v.m[3][r];
      for (int c = 0; c < 3; ++c) edge[c][r] = v.m[c][r] * (hi[c] - lo[c]);
    }
    const double inf = std::numeric_limits<double>::infinity();
    double x0 = inf, y0 = inf, z0 = inf, x1 = -inf, y1 = -inf, z1 = -inf;
    int behind = 0, crossing = 0;
    for (int k = 0; k < 8; ++k) {
      double p[4];
      for (int r = 0; r < 4; ++r) {
        p[r] = base[r];
        for (int c = 0; c < 3; ++c)
          if (k >> c & 1) p[r] += edge[c][r];
      }
      const bool finite =
          std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]) && std::isfinite(p[3]);
      behind += finite && p[2] < 0;
      const double q = 1.0 / p[3];
      const double x = (p[0] + p[3]) * v.half_w * q, y = (p[3] - p[1]) * v.half_h * q;
      const double z = p[2] * q;
      // A w so small that 1/w overflows can make 0 * inf: such a corner is not bounded either.
      if (!finite || !(p[3] > 0) || p[2] < 0 || std::isnan(x) || std::isnan(y) || std::isnan(z)) {
        ++crossing;
        continue;
      }
      x0 = std::min(x0, x), x1 = std::max(x1, x);
      y0 = std::min(y0, y), y1 = std::max(y1, y);
      z0 = std::min(z0, z), z1 = std::max(z1, z);
    }
    out[i] = crossing ? crossing_answer(v, behind)
                      : Projected{false, true, finish_bounds(v, x0, y0, x1, y1, z0, z1)};
  }
}

}  // namespace mosaic::occlusion
