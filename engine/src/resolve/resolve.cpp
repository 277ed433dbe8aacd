#include "resolve/resolve.hpp"

namespace mosaic::resolve {

void box_resolve(std::span<const Rgba8> in, int samples, std::span<Rgba8> out) {
  const std::uint32_t n = static_cast<std::uint32_t>(samples);
  for (std::size_t p = 0; p < out.size(); ++p) {
    std::uint32_t r = 0, g = 0, b = 0, a = 0;
    for (std::uint32_t s = 0; s < n; ++s) {
      const Rgba8 c = in[p * n + s];
      r += c.r;
      g += c.g;
      b += c.b;
      a += c.a;
    }
    out[p] = {box_mean(r, n), box_mean(g, n), box_mean(b, n), box_mean(a, n)};
  }
}

}  // namespace mosaic::resolve
