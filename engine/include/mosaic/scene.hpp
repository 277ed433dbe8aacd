// mosaic/scene.hpp — owned scene data: built-in scenes, .tris and OBJ files, image output.
//
// Takes: a scene name, a .tris or OBJ file, or a rendered RenderTarget. Gives: a Scene that owns
// its buffers (Scene::draws() views them as Draws for Renderer::render()), .tris files and
// PNG/PPM images.
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

#include "mosaic/draw.hpp"
#include "mosaic/render_target.hpp"
#include "mosaic/shader.hpp"
#include "mosaic/types.hpp"

namespace mosaic {

/// How a Scene's meshes are coloured (the CLI's --shade): from their colours, per pixel from
/// their vertex normals, shown as colours or lit, or from their texture coordinates.
enum class Shading { kFlat, kNormals, kLambert, kUv };

/// One owned draw: the buffers a Draw points at, plus its state. The fields mean what the
/// Draw fields of the same names mean.
struct Mesh {
  Space space = Space::kClip;          ///< coordinate space of `positions`
  std::vector<glm::vec4> positions;    ///< xyzw, in `space`
  std::vector<std::uint32_t> indices;  ///< three per triangle; empty: vertices 0,1,2, 3,4,5, …
  ColorSource color_source = ColorSource::kConstant;  ///< where the colour comes from
  Rgba8 color{255, 255, 255, 255};                    ///< for ColorSource::kConstant
  std::vector<Rgba8> colors;  ///< one per triangle (kPerTriangle) or per vertex (kPerVertex)
  /// One per position, or empty: vertex normals (any length) in the space of the scene's light
  /// (Scene::light), which for a clip-space mesh is the space before Camera::view_projection.
  std::vector<glm::vec3> normals;
  /// One per position, or empty: texture coordinates (u, v), as Shading::kUv shows them.
  std::vector<glm::vec2> uvs;
  DrawState state;  ///< depth test and write, culling, fill rule

  /// A Draw viewing this mesh's buffers (valid while the mesh lives and is not modified),
  /// coloured from color_source.
  Draw draw() const;
  /// The same Draw coloured by `shading`: kFlat is draw(); kNormals and kLambert read `normals`
  /// as varyings 0..2 through normal_color_shader() or lambert_shader(light), and kUv reads
  /// `uvs` as varyings 0..1 through uv_color_shader(). Throws Error{kInvalidArgument} when the
  /// mesh lacks the normals or UVs the shading reads.
  Draw draw(Shading shading, const Lambert& light) const;
  /// Triangles the mesh submits: indices / 3, or positions / 3 without indices.
  std::size_t triangle_count() const;
};

/// The camera a scene's clip-space meshes were projected with.
struct Camera {
  /// World (or OBJ model) space to clip space, depth z/w in [0, 1]. Identity for scenes that
  /// have no camera (screen-space scenes: .tris files and the 2-D built-in scenes).
  glm::mat4 view_projection{1.0f};
};

/// A scene: a suggested target size and clear values, and meshes drawn in order.
struct Scene {
  std::string name;                 ///< the built-in scene's name, or the file's stem
  int width = 1920, height = 1080;  ///< the target size the scene was made for
  Rgba8 clear_color{0, 0, 0, 255};  ///< for RenderTarget::set_clear()
  float clear_depth = 1.0f;         ///< for RenderTarget::set_clear()
  std::vector<Mesh> meshes;         ///< drawn in this order
  /// How the clip-space meshes were projected: `inverse(camera.view_projection) * position`
  /// gives a vertex back in world space (OBJ: model space), e.g. to view it from elsewhere.
  Camera camera;
  /// What a loader read but cannot draw, one line each ("<file>:<line>: ..."): today an OBJ
  /// vertex whose position is not finite (its triangles stay in the mesh and are culled when
  /// drawn, as a draw's are). Empty for built-in scenes and .tris files.
  std::vector<std::string> warnings;

  /// The light of Shading::kLambert: a direction in the normals' space and a surface colour.
  Lambert light;
  /// How the scene's maker suggests it be shaded (the CLI's default): kFlat, except kLambert for
  /// an OBJ file without vertex colours.
  Shading default_shading = Shading::kFlat;
  /// Draws viewing every mesh, in order (valid while the scene lives and is not modified).
  std::vector<Draw> draws() const;
  /// The same, coloured by `shading` with `light` (Mesh::draw(Shading, const Lambert&)).
  std::vector<Draw> draws(Shading shading) const;
  /// Whether every mesh has normals, so that draws(kNormals or kLambert) succeeds.
  bool has_normals() const;
  /// Whether every mesh has UVs, so that draws(kUv) succeeds.
  bool has_uvs() const;
  /// Triangles submitted by all meshes.
  std::size_t triangle_count() const;
  /// Sets every mesh's state with `f(DrawState&)`, e.g. to apply command-line options.
  template <class F>
  void for_each_state(F&& f) {
    for (Mesh& m : meshes) f(m.state);
  }
};

/// Names of the built-in scenes: default, random-small, random-large, slivers, star, fan, knot,
/// knot-100px, knot-30px, knot-65k, knot-2m. The knot scenes are one closed, indexed torus knot
/// in perspective, centred: `knot` (1,048,576 triangles) fills 90 % of the target's width or
/// height (whichever binds first), `knot-100px` and `knot-30px` are the same mesh that many
/// pixels wide on any target size, `knot-65k` (65,536 triangles, a scanned model's size) fills
/// 72 % (its box is a third of a 16:9 frame's area), and `knot-2m` (2,097,152) fills 90 %.
std::vector<std::string> builtin_scene_names();

/// A built-in scene made for a width × height target; deterministic for a given name, size and
/// seed (only the random scenes use the seed). Throws Error{kInvalidTargetSize} unless
/// 1 <= width, height <= kMaxTargetSize, and Error{kInvalidArgument} for an unknown name.
Scene builtin_scene(const std::string& name, int width = 1920, int height = 1080,
                    std::uint64_t seed = 1);

/// Reads a screen-space `.tris` file (shared/formats/screen-triangles.md) into a Scene with one
/// screen-space Mesh of per-vertex colours. Throws Error{kParse} naming the file and line of
/// the first malformed line, or Error{kIo} if the file cannot be read; nothing is returned
/// from a file with errors.
Scene load_tris(const std::filesystem::path& path);
/// The same, from text in memory; `name` stands for the file name in error messages.
/// Throws Error{kParse}.
Scene parse_tris(const std::string& text, const std::string& name = "<memory>");
/// Writes a scene as `.tris`. Clip-space meshes are projected to pixels with the scene's size;
/// triangles crossing the near plane, or culled by their state, are skipped. The file is
/// written whole or not at all. Throws Error{kInvalidArgument} for a scene size outside
/// 1..kMaxTargetSize, Error{kIndexOutOfRange} or Error{kInvalidDraw} for a mesh that
/// Renderer::render() would reject, and Error{kIo} if the file cannot be written.
void save_tris(const Scene& scene, const std::filesystem::path& path);

/// Loads a Wavefront OBJ mesh (positions, normals `vn`, texture coordinates `vt` and faces;
/// polygons are fanned into triangles; materials and groups are ignored) into a Scene with one
/// indexed clip-space Mesh, seen by a camera that frames the mesh's bounding sphere in a
/// width × height target (Scene::camera). Each distinct face corner (position, `vt`, `vn`) is one
/// vertex; a triangle whose corners do not all name a normal gets its face normal on three
/// vertices of its own, and the mesh has UVs when every corner names one. Vertex colours come
/// from the OBJ extension `v x y z r g b` if every vertex has one (Scene::default_shading
/// kFlat), otherwise each triangle gets a lit shade of its face normal so that the shape reads
/// (default kLambert, Scene::light in model space). A vertex whose x, y or z is nan, inf or past
/// float's range is kept as NaN, so that its triangles are culled when drawn
/// (FrameStats::triangles_nonfinite), exactly as the same draw through the API; the camera
/// frames the other triangles, and Scene::warnings names the first such vertex's line. Throws
/// Error{kInvalidArgument} for a size outside 1..kMaxTargetSize, Error{kParse} for a malformed
/// file (naming its line; a non-finite w or colour is malformed, and so is a file whose every
/// face uses a non-finite vertex), or Error{kIo} (also for a file that is too large, not a
/// regular file, or a device).
Scene load_obj(const std::filesystem::path& path, int width = 1920, int height = 1080);

/// Writes the target's resolved image as PNG (.png, RGBA) or binary PPM (.ppm, RGB), chosen by
/// the extension in any case. The file is written whole or not at all. Throws Error{kIo} if it
/// cannot be written, or Error{kInvalidArgument} for another extension.
void write_image(const RenderTarget& target, const std::filesystem::path& path);

}  // namespace mosaic
