// Scene::camera (mosaic/scene.hpp): the camera a scene's clip-space meshes were projected with.
// load_obj's clip positions taken back through inverse(camera.view_projection) must give the
// OBJ's own vertices in face order, which is what lets a program (engine/examples/orbit) view a
// loaded mesh from another camera. Screen-space scenes have the identity camera.
#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <filesystem>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

#include "mosaic/mosaic.hpp"

namespace mosaic {
namespace {

/// Largest error of a recovered model-space coordinate. The tetrahedron spans 1 unit and its
/// clip positions are floats (24-bit mantissa) through a float matrix inverted in double: a
/// few float steps of the unit size each, far below this.
constexpr double kModelTolerance = 1e-4;

/// The vertices of tests/data/cli_tetra.obj, and its faces (1-based, as in the file).
constexpr std::array<glm::dvec3, 4> kTetraVertices{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
constexpr std::array<std::array<int, 3>, 4> kTetraFaces{
    {{1, 3, 2}, {1, 2, 4}, {1, 4, 3}, {2, 3, 4}}};

TEST(SceneCamera, ObjClipPositionsInvertToModelVertices) {
  const Scene scene =
      load_obj(std::filesystem::path(MOSAIC_TEST_DATA_DIR) / "cli_tetra.obj", 640, 360);
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  ASSERT_EQ(mesh.space, Space::kClip);
  ASSERT_TRUE(mesh.indices.empty());
  ASSERT_EQ(mesh.positions.size(), 3 * kTetraFaces.size());
  const glm::dmat4 to_model = glm::inverse(glm::dmat4(scene.camera.view_projection));
  for (std::size_t f = 0; f < kTetraFaces.size(); ++f) {
    for (std::size_t k = 0; k < 3; ++k) {
      const glm::dvec4 p = to_model * glm::dvec4(mesh.positions[3 * f + k]);
      const glm::dvec3 expected = kTetraVertices[kTetraFaces[f][k] - 1];
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(p[c] / p.w, expected[c], kModelTolerance)
            << "face " << f + 1 << " vertex " << k << " axis " << c;
    }
  }
}

TEST(SceneCamera, ScreenScenesHaveTheIdentityCamera) {
  const Scene tris = parse_tris("size 8 8\ntri 0 0 0 8 0 0 0 8 0 255 0 0 255\n");
  EXPECT_EQ(tris.camera.view_projection, glm::mat4(1.0f));
  const Scene star = builtin_scene("star", 64, 64);
  EXPECT_EQ(star.camera.view_projection, glm::mat4(1.0f));
}

TEST(SceneCamera, DefaultSceneRecordsItsPerspective) {
  // The default scene is seen in perspective: its camera's clip w depends on depth.
  const Scene scene = builtin_scene("default", 320, 180);
  EXPECT_NE(scene.camera.view_projection, glm::mat4(1.0f));
  EXPECT_NE(scene.camera.view_projection[2][3], 0.0f);
}

}  // namespace
}  // namespace mosaic
