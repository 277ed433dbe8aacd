// mosaic/scene.hpp — owned scene data: built-in scenes, .tris and OBJ files, image output.
//
// A Scene owns its buffers; Scene::frame_draws() views them as Draws for Renderer::render().
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "mosaic/draw.hpp"
#include "mosaic/render_target.hpp"
#include "mosaic/types.hpp"

namespace mosaic {

/// One owned draw: the buffers a Draw points at, plus its state.
struct Mesh {
  Space space = Space::kClip;
  std::vector<glm::vec4> positions;
  std::vector<std::uint32_t> indices;  ///< empty: sequential triangles
  ColorSource color_source = ColorSource::kConstant;
  Rgba8 color{255, 255, 255, 255};
  std::vector<Rgba8> colors;
  DrawState state;

  /// A Draw viewing this mesh's buffers (valid while the mesh lives and is not modified).
  Draw draw() const;
  std::size_t triangle_count() const;
};

/// A scene: a suggested target size and clear values, and meshes drawn in order.
struct Scene {
  std::string name;
  int width = 1920, height = 1080;
  Rgba8 clear_color{0, 0, 0, 255};
  float clear_depth = 1.0f;
  std::vector<Mesh> meshes;

  /// Draws viewing every mesh, in order.
  std::vector<Draw> draws() const;
  std::size_t triangle_count() const;
  /// Sets every mesh's state with `f(DrawState&)`, e.g. to apply command-line options.
  template <class F>
  void for_each_state(F&& f) {
    for (Mesh& m : meshes) f(m.state);
  }
};

/// Names of the built-in scenes: default, random-small, random-large, slivers, star, fan.
std::vector<std::string> builtin_scene_names();

/// A built-in scene at the given size; deterministic for a given name, size and seed.
/// Throws Error{kInvalidArgument} for an unknown name.
Scene builtin_scene(const std::string& name, int width = 1920, int height = 1080,
                    std::uint64_t seed = 1);

/// Reads a screen-space `.tris` file (shared/formats/screen-triangles.md). Throws Error{kParse}
/// naming the file and line of the first malformed line, or Error{kIo}; nothing is returned
/// from a file with errors.
Scene load_tris(const std::filesystem::path& path);
/// The same, from text in memory; `name` stands for the file name in error messages.
Scene parse_tris(const std::string& text, const std::string& name = "<memory>");
/// Writes a scene as `.tris`. Clip-space meshes are projected to pixels with the scene's size;
/// triangles crossing the near plane, or culled by their state, are skipped. Throws Error{kIo}.
void save_tris(const Scene& scene, const std::filesystem::path& path);

/// Camera for OBJ scenes: a perspective view of the mesh.
struct Camera {
  glm::mat4 view_projection{1.0f};
};
/// Loads a Wavefront OBJ mesh (positions and faces; polygons are fanned into triangles) with a
/// camera that frames it. Vertex colours come from the OBJ extension `v x y z r g b` if present,
/// otherwise from the normal so that the shape reads. Throws Error{kParse} or Error{kIo}.
Scene load_obj(const std::filesystem::path& path, int width = 1920, int height = 1080);

/// Writes the target's resolved image as PNG (.png) or binary PPM (.ppm), chosen by extension.
/// Throws Error{kIo} or Error{kInvalidArgument} for another extension.
void write_image(const RenderTarget& target, const std::filesystem::path& path);

}  // namespace mosaic
