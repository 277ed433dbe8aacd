// scenes/scene.cpp — views of owned scene data as Draws.
//
// Takes: a Mesh or Scene (owned buffers). Gives: Draws that point into those buffers, and the
// number of triangles they submit. Nothing is copied or validated here: Renderer::render()
// validates every draw it is given.
#include "mosaic/scene.hpp"

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

std::size_t Mesh::triangle_count() const {
  return (indices.empty() ? positions.size() : indices.size()) / 3;
}

std::vector<Draw> Scene::draws() const {
  std::vector<Draw> out;
  out.reserve(meshes.size());
  for (const Mesh& m : meshes) out.push_back(m.draw());
  return out;
}

std::size_t Scene::triangle_count() const {
  std::size_t n = 0;
  for (const Mesh& m : meshes) n += m.triangle_count();
  return n;
}

}  // namespace mosaic
