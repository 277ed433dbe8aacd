// shade/builtin_shaders.cpp — the built-in shaders of mosaic/shader.hpp: flat colour, vertex
// colour and a Lambert-lit normal, each a per-pixel callable through make_shader() like any
// user's shader.
#include <algorithm>
#include <cmath>

#include "mosaic/shader.hpp"

namespace mosaic {

Shader flat_color_shader(glm::vec4 color) {
  return make_shader([color](const Fragment&) { return color; }, 0);
}

Shader vertex_color_shader() {
  return make_shader([](const Fragment& f) { return f.varying4(0); }, 4);
}

Shader normal_color_shader() {
  return make_shader(
      [](const Fragment& f) {
        const float nx = f.varying(0), ny = f.varying(1), nz = f.varying(2);
        const float len2 = nx * nx + ny * ny + nz * nz;
        // Divided whatever len2 is, then chosen: a loop without branches vectorises.
        const float inv = 0.5f / std::sqrt(len2);
        const float s = len2 > 0.0f ? inv : 0.0f;
        return glm::vec4(0.5f + nx * s, 0.5f + ny * s, 0.5f + nz * s, 1.0f);
      },
      3);
}

Shader uv_color_shader() {
  return make_shader(
      [](const Fragment& f) {
        const float u = f.varying(0), v = f.varying(1);
        return glm::vec4(u - std::floor(u), v - std::floor(v), 0.0f, 1.0f);
      },
      2);
}

Shader lambert_shader(const Lambert& params) {
  // The light is normalised once, in double, so that every pixel divides nothing but the normal.
  const double lx = params.light_dir.x, ly = params.light_dir.y, lz = params.light_dir.z;
  const double len = std::sqrt(lx * lx + ly * ly + lz * lz);
  const glm::vec3 l = len > 0
                          ? glm::vec3(static_cast<float>(lx / len), static_cast<float>(ly / len),
                                      static_cast<float>(lz / len))
                          : glm::vec3(0.0f);
  const glm::vec3 albedo = params.albedo;
  const float ambient = params.ambient, diffuse = params.diffuse;
  const bool two_sided = params.two_sided;
  return make_shader(
      [=](const Fragment& f) {
        const float nx = f.varying(0), ny = f.varying(1), nz = f.varying(2);
        const float len2 = nx * nx + ny * ny + nz * nz;
        // n·l / |n|; a zero (or non-finite) normal gets no diffuse light. Divided whatever len2
        // is, then chosen: a loop without branches vectorises.
        const float cosine = (nx * l.x + ny * l.y + nz * l.z) / std::sqrt(len2);
        float ndl = len2 > 0.0f ? cosine : 0.0f;
        ndl = two_sided ? std::fabs(ndl) : std::max(ndl, 0.0f);
        const float k = ambient + diffuse * ndl;
        return glm::vec4(albedo.x * k, albedo.y * k, albedo.z * k, 1.0f);
      },
      3);
}

}  // namespace mosaic
