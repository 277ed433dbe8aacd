// scenes/scene.cpp — views of owned scene data as Draws.
//
// Takes: a Mesh or Scene (owned buffers). Gives: Draws that point into those buffers, and the
// number of triangles they submit. Nothing is copied or validated here: Renderer::render()
// validates every draw it is given.
#include "mosaic/scene.hpp"

#include <string>

#include "mosaic/errors.hpp"

namespace mosaic {

Draw Mesh::draw() const {
  Draw d;
  d.space = space;
  d.positions = positions;
  d.indices = indices;
  d.color_source = color_source;
  d.color = color;
  d.colors = colors;
  d.state = state;
  return d;
}

Draw Mesh::draw(Shading shading, const Lambert& light) const {
  Draw d = draw();
  if (shading == Shading::kFlat) return d;
  if (shading == Shading::kUv) {
    if (uvs.empty())
      throw Error(Errc::kInvalidArgument, "a mesh without UVs cannot be shaded by them");
    static_assert(sizeof(glm::vec2) == 2 * sizeof(float), "UVs are read as 2 floats each");
    static constexpr std::uint32_t kUvVaryings[] = {0, 1};
    d.attributes = {&uvs[0].x, 2 * uvs.size()};
    d.attribute_count = 2;
    d.varyings = kUvVaryings;
    d.shader = uv_color_shader();
    return d;
  }
  if (normals.empty())
    throw Error(Errc::kInvalidArgument, "a mesh without normals cannot be shaded by them");
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "normals are read as 3 floats each");
  static constexpr std::uint32_t kNormalVaryings[] = {0, 1, 2};
  d.attributes = {&normals[0].x, 3 * normals.size()};
  d.attribute_count = 3;
  d.varyings = kNormalVaryings;
  d.shader = shading == Shading::kNormals ? normal_color_shader() : lambert_shader(light);
  return d;
}

std::size_t Mesh::triangle_count() const {
  return (indices.empty() ? positions.size() : indices.size()) / 3;
}

std::vector<Draw> Scene::draws() const {
  std::vector<Draw> out;
  out.reserve(meshes.size());
  for (const Mesh& m : meshes) out.push_back(m.draw());
  return out;
}

std::vector<Draw> Scene::draws(Shading shading) const {
  std::vector<Draw> out;
  out.reserve(meshes.size());
  for (const Mesh& m : meshes) out.push_back(m.draw(shading, light));
  return out;
}

bool Scene::has_normals() const {
  for (const Mesh& m : meshes)
    if (m.normals.empty()) return false;
  return true;
}

bool Scene::has_uvs() const {
  for (const Mesh& m : meshes)
    if (m.uvs.empty()) return false;
  return true;
}

std::size_t Scene::triangle_count() const {
  std::size_t n = 0;
  for (const Mesh& m : meshes) n += m.triangle_count();
  return n;
}

}  // namespace mosaic
