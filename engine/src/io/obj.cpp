// io/obj.cpp — loading a Wavefront OBJ mesh with a camera that frames it.
//
// Takes: an OBJ file (positions `v x y z [r g b]`, normals `vn` and faces `f`; texture
// coordinates and materials are ignored). Gives: a Scene with one clip-space Mesh. Its positions
// are already multiplied by the camera's view-projection (so the Mesh needs no transform), three
// vertices per triangle, no indices, one colour per vertex: the OBJ vertex colour when every
// vertex has one, otherwise a flat shade of the face normal so that the shape reads. Each
// vertex also gets a model-space normal, the file's where a face gives all three, else the
// face's, and Scene::light lights them as the flat shade is lit.
//
// Parsing is tinyobjloader's (Debian's compiled libtinyobjloader). Polygons are fanned into
// triangles here rather than by tinyobjloader, so that every index is checked before use.
// A vertex position that is not finite (nan, inf, past float's range) is kept as NaN: its
// triangles are culled when drawn, as a draw's are, and Scene::warnings says how many.
#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "io/lines.hpp"
#include "io/numbers.hpp"
#include "io/read_file.hpp"
#include "mosaic/errors.hpp"
#include "mosaic/scene.hpp"

namespace mosaic {
namespace {

/// Vertical field of view of the camera, as its focal length 1 / tan(fov / 2): 2 is about 53°,
/// a natural lens that neither flattens nor distorts the model.
constexpr double kFocalLength = 2.0;
/// The bounding sphere fills this fraction of the shorter screen axis (a margin around it).
constexpr double kFrameFill = 0.9;
/// Direction from the model towards the camera: in front, a little right and above, so that
/// three faces of a box-like model show.
constexpr glm::dvec3 kViewDirection{0.45, 0.35, 1.0};
/// Direction towards the light, in view space (upper left, towards the viewer).
constexpr glm::dvec3 kLightDirection{-0.4, 0.6, 0.7};
/// Shade = base colour * (ambient + diffuse * |n·l|): the ambient keeps faces turned away
/// from the light readable.
constexpr double kAmbient = 0.3;
constexpr double kDiffuse = 0.7;
/// Largest channel value of an 8-bit colour.
constexpr double kChannelMax = 255.0;
/// Alpha of every vertex colour: OBJ colours have none.
constexpr std::uint8_t kOpaque = 255;
/// Near and far planes sit this factor of the radius in front of and behind the centre, so no
/// vertex lies exactly on either (float rounding of the positions stays inside).
constexpr double kDepthMargin = 1.05;
/// The near plane never comes closer than this fraction of the camera distance, which bounds
/// the depth precision lost to a near plane at the eye.
constexpr double kMinNearFraction = 1e-3;
/// Background: a dark blue-grey that every shade of the model stands out from.
constexpr Rgba8 kClearColor{32, 32, 40, 255};
/// The colour of a triangle with a vertex that is not finite: any will do, it is culled.
constexpr Rgba8 kCulledColor{0, 0, 0, kOpaque};

/// The camera: the bounding sphere seen from kViewDirection, depth z/w in [0, 1] over the
/// sphere's depth range (near plane at z = 0, the front of the sphere with a margin).
glm::dmat4 framing_camera(const glm::dvec3& centre, double radius, int width, int height,
                          glm::dmat4& view) {
  const double aspect = static_cast<double>(width) / height;
  // The sphere must fit the narrower of the two fields of view.
  const double focal = aspect < 1.0 ? kFocalLength * aspect : kFocalLength;
  // A sphere of radius r at distance d subtends half-angle asin(r / d); its tangent must be at
  // most kFrameFill / focal: d = r * sqrt(1 + (focal / fill)^2).
  const double f = focal / kFrameFill;
  const double dist = radius * std::sqrt(1.0 + f * f);
  const glm::dvec3 dir = glm::normalize(kViewDirection);
  const glm::dvec3 eye = centre + dir * dist;
  // Right-handed view looking at the centre, y up.
  const glm::dvec3 fwd = -dir;
  const glm::dvec3 right = glm::normalize(glm::cross(fwd, glm::dvec3(0, 1, 0)));
  const glm::dvec3 up = glm::cross(right, fwd);
  view = glm::dmat4(1.0);
  for (int i = 0; i < 3; ++i) {
    view[i][0] = right[i];
    view[i][1] = up[i];
    view[i][2] = -fwd[i];
  }
  view[3][0] = -glm::dot(right, eye);
  view[3][1] = -glm::dot(up, eye);
  view[3][2] = glm::dot(fwd, eye);
  // Near and far planes around the sphere, with a margin so nothing touches them.
  const double near_plane = std::max(dist - kDepthMargin * radius, dist * kMinNearFraction);
  const double far_plane = dist + kDepthMargin * radius;
  // Perspective with depth in [0, 1] (as glm::perspectiveRH_ZO): z_clip = A * z_view + B,
  // w = -z_view, so z/w = 0 at the near plane and 1 at the far plane.
  glm::dmat4 proj(0.0);
  proj[0][0] = focal / aspect;
  proj[1][1] = focal;
  proj[2][2] = far_plane / (near_plane - far_plane);
  proj[2][3] = -1.0;
  proj[3][2] = -(far_plane * near_plane) / (far_plane - near_plane);
  return proj * view;
}

/// Largest face index magnitude: what tinyobjloader's int holds.
constexpr std::int64_t kMaxFaceIndex = std::numeric_limits<int>::max();
/// Most vertices of one face: tinyobjloader counts them in an unsigned char.
constexpr int kMaxFaceVertices = std::numeric_limits<unsigned char>::max();

/// What a fanned triangle costs while it loads: tinyobjloader's three indices, vertex count and
/// material, then the mesh's three positions and colours.
constexpr std::uintmax_t kBytesPerTriangle =
    3 * sizeof(tinyobj::index_t) + 1 + sizeof(int) +
    3 * (sizeof(glm::vec4) + sizeof(Rgba8) + sizeof(glm::vec3));
/// Albedo of Scene::light: a light grey, so that the lit normals show the shape alone.
constexpr float kAlbedo = 0.85f;

std::uint8_t to_channel(double v01) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(v01, 0.0, 1.0) * kChannelMax));
}

/// How one value of a `v` line reads.
enum class VertexValue : std::uint8_t {
  kFinite,     ///< a number that fits a float (one too small for a double reads as 0)
  kNotFinite,  ///< nan, inf, or past float's range
  kMalformed,  ///< not a number
};

VertexValue read_vertex_value(std::string_view w) {
  double v = 0;
  const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
  const bool whole = end == w.data() + w.size();
  if (ec == std::errc::result_out_of_range && whole)
    return io::underflows(w) ? VertexValue::kFinite : VertexValue::kNotFinite;
  if (ec != std::errc() || !whole) return VertexValue::kMalformed;
  if (!std::isfinite(v) || std::fabs(v) > static_cast<double>(std::numeric_limits<float>::max()))
    return VertexValue::kNotFinite;
  return VertexValue::kFinite;
}

/// What scan_obj() learns before tinyobjloader parses the file.
struct ObjScan {
  /// The line of each face tinyobjloader keeps (three or more vertices), in file order, so
  /// that an error about face k can name its line.
  std::vector<std::size_t> face_lines;
  /// Vertices (0-based, in file order) with an x, y or z that is not finite, and their lines.
  std::vector<std::size_t> bad_vertices, bad_vertex_lines;
};

/// Checks every vertex line (tinyobjloader reads a malformed number as 0 without a word), notes
/// the vertices whose position is not finite, and the lines of the faces.
ObjScan scan_obj(const std::string& text, const std::string& file) {
  // `v x y z`, optionally with w (4 values) or an r g b colour (6), or both as some tools
  // write them (7).
  constexpr int kMinVertexValues = 3, kMaxVertexValues = 7;
  constexpr int kPositionValues = 3;
  ObjScan scan;
  std::vector<std::size_t>& lines = scan.face_lines;
  std::size_t vertices = 0;
  std::uintmax_t triangles = 0;
  io::LineReader reader(text, file);
  for (std::string_view line; reader.next(line);) {
    const std::size_t n = reader.line_no();
    std::istringstream words{std::string(line)};
    std::string kw;
    if (!(words >> kw)) continue;
    if (kw == "f") {
      int count = 0;
      for (std::string w; words >> w;) {
        // tinyobjloader converts an index with atoi, whose overflow is undefined: an index past
        // int's range could come back as an existing vertex. Refuse it here, naming the line.
        const std::string_view index = std::string_view(w).substr(0, w.find('/'));
        std::int64_t v = 0;
        const auto [end, ec] = std::from_chars(index.data(), index.data() + index.size(), v);
        if (ec != std::errc() || end != index.data() + index.size() || v == 0 ||
            v > kMaxFaceIndex || v < -kMaxFaceIndex)
          throw Error(Errc::kParse, file + ":" + std::to_string(n) + ": face vertex '" + w +
                                        "' is not a vertex index");
        ++count;
      }
      // tinyobjloader counts a face's vertices in a byte.
      if (count > kMaxFaceVertices)
        throw Error(Errc::kParse, file + ":" + std::to_string(n) + ": a face of " +
                                      std::to_string(count) + " vertices; at most " +
                                      std::to_string(kMaxFaceVertices) + " are read");
      if (count >= 3) {
        lines.push_back(n);
        triangles += static_cast<std::uintmax_t>(count - 2);
      }
    } else if (kw == "v") {
      int count = 0;
      bool finite = true;
      for (std::string w; words >> w;) {
        const VertexValue v = read_vertex_value(w);
        // A position that is not finite culls the triangles that use the vertex, as a draw's
        // does; w and colours are not positions, and cannot be other than finite.
        if (v == VertexValue::kMalformed ||
            (v == VertexValue::kNotFinite && count >= kPositionValues))
          throw Error(Errc::kParse, file + ":" + std::to_string(n) + ": vertex value '" + w +
                                        "' is not a finite number");
        finite = finite && v == VertexValue::kFinite;
        ++count;
      }
      if (count < kMinVertexValues || count > kMaxVertexValues)
        throw Error(Errc::kParse, file + ":" + std::to_string(n) +
                                      ": a vertex needs 3 to 7 "
                                      "values (x y z [w] [r g b]), got " +
                                      std::to_string(count));
      if (!finite) {
        scan.bad_vertices.push_back(vertices);
        scan.bad_vertex_lines.push_back(n);
      }
      ++vertices;
    }
  }
  io::check_scene_memory(file, triangles, kBytesPerTriangle);
  return scan;
}

/// tinyobjloader's error text, reworded as "<file>:<line>: <problem>" when it names a line.
std::string tinyobj_error(const std::string& file, std::string msg) {
  std::replace(msg.begin(), msg.end(), '\n', ' ');
  while (!msg.empty() && msg.back() == ' ') msg.pop_back();
  if (msg.empty()) msg = "malformed OBJ";
  const std::size_t at = msg.find("line ");
  if (at != std::string::npos) {
    std::size_t line = 0;
    const char* first = msg.data() + at + 5;
    const auto [end, ec] = std::from_chars(first, msg.data() + msg.size(), line);
    if (ec == std::errc() && end != first) return file + ":" + std::to_string(line) + ": " + msg;
  }
  return file + ": " + msg;
}

}  // namespace

Scene load_obj(const std::filesystem::path& path, int width, int height) {
  const std::string file = path.string();
  if (width < 1 || width > kMaxTargetSize || height < 1 || height > kMaxTargetSize)
    throw Error(Errc::kInvalidArgument, file + ": size " + std::to_string(width) + "x" +
                                            std::to_string(height) + " is outside 1..16384");
  const std::string text = io::read_scene_file(path);

  const ObjScan scan = scan_obj(text, file);
  const std::vector<std::size_t>& lines = scan.face_lines;

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  std::istringstream obj_stream(text);
  // No material reader: materials do not affect the render. No triangulation (fanned below,
  // after the indices are checked); no default vertex colours, so that attrib.colors is
  // filled only when the file gives every vertex one.
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &obj_stream, nullptr,
                                   /*triangulate=*/false,
                                   /*default_vcols_fallback=*/false);
  if (!ok) throw Error(Errc::kParse, tinyobj_error(file, err));

  const std::size_t vertex_count = attrib.vertices.size() / 3;
  // tinyobjloader reads "nan" and "inf" as 0: the vertices the scan found get NaN, so that
  // their triangles are culled when drawn.
  for (const std::size_t v : scan.bad_vertices)
    if (v < vertex_count)
      for (int k = 0; k < 3; ++k)
        attrib.vertices[3 * v + k] = std::numeric_limits<tinyobj::real_t>::quiet_NaN();
  std::vector<bool> finite(vertex_count);
  for (std::size_t v = 0; v < vertex_count; ++v)
    finite[v] = std::isfinite(attrib.vertices[3 * v]) &&
                std::isfinite(attrib.vertices[3 * v + 1]) &&
                std::isfinite(attrib.vertices[3 * v + 2]);
  const bool has_colors = attrib.colors.size() == attrib.vertices.size() && vertex_count > 0;

  // Triangles as vertex-index triples, checked against the vertex count, and their corners'
  // normal indices (-1 where a corner has none).
  const std::size_t normal_count = attrib.normals.size() / 3;
  std::vector<std::array<std::size_t, 3>> tris;
  std::vector<std::array<int, 3>> tri_normals;
  std::size_t bad_normals = 0;  // face corners that name a normal that does not exist
  std::string bad_normal_where;
  std::size_t face = 0;
  for (const tinyobj::shape_t& shape : shapes) {
    std::size_t base = 0;
    for (const unsigned char n : shape.mesh.num_face_vertices) {
      if (base + n > shape.mesh.indices.size())
        throw Error(Errc::kParse, file + ": inconsistent face data");
      const auto where = [&] {
        return lines.size() > face ? std::string(":").append(std::to_string(lines[face]))
                                   : std::string();
      };
      bool face_normals_bad = false;
      for (std::size_t k = 0; k < n; ++k) {
        const tinyobj::index_t& idx = shape.mesh.indices[base + k];
        // tinyobjloader turns index i into i - 1 and a negative one into count + i; a corner
        // without a normal has normal_index -1.
        if (idx.vertex_index < 0 || static_cast<std::size_t>(idx.vertex_index) >= vertex_count)
          throw Error(Errc::kParse, file + where() + ": face " + std::to_string(face + 1) +
                                        " names a vertex that does not exist (" +
                                        std::to_string(vertex_count) + " vertices)");
        // A missing normal is not worth refusing a mesh for: the face's own normal stands in.
        const int ni = idx.normal_index;
        if (ni < -1 || (ni >= 0 && static_cast<std::size_t>(ni) >= normal_count)) {
          if (bad_normals++ == 0) bad_normal_where = where();
          face_normals_bad = true;
        }
      }
      for (std::size_t k = 1; k + 1 < n; ++k) {
        const tinyobj::index_t& i0 = shape.mesh.indices[base];
        const tinyobj::index_t& i1 = shape.mesh.indices[base + k];
        const tinyobj::index_t& i2 = shape.mesh.indices[base + k + 1];
        tris.push_back({static_cast<std::size_t>(i0.vertex_index),
                        static_cast<std::size_t>(i1.vertex_index),
                        static_cast<std::size_t>(i2.vertex_index)});
        tri_normals.push_back(
            face_normals_bad
                ? std::array<int, 3>{-1, -1, -1}
                : std::array<int, 3>{i0.normal_index, i1.normal_index, i2.normal_index});
      }
      base += n;
      ++face;
    }
    // tinyobjloader counts a face's vertices in a byte: a longer polygon desynchronises them.
    if (base != shape.mesh.indices.size())
      throw Error(Errc::kParse, file + ": a face has more than 255 vertices");
  }
  if (tris.empty()) throw Error(Errc::kParse, file + ": no faces with three or more vertices");
  auto drawable = [&](const std::array<std::size_t, 3>& t) {
    return finite[t[0]] && finite[t[1]] && finite[t[2]];
  };
  const auto drawn = static_cast<std::size_t>(std::count_if(tris.begin(), tris.end(), drawable));
  if (drawn == 0) throw Error(Errc::kParse, file + ": every face uses a vertex that is not finite");

  // Bounding sphere of the finite vertices the faces use (centre of the box, farthest vertex).
  auto vertex = [&](std::size_t i) {
    return glm::dvec3(attrib.vertices[3 * i], attrib.vertices[3 * i + 1],
                      attrib.vertices[3 * i + 2]);
  };
  const auto first = std::find_if(tris.begin(), tris.end(), drawable);
  glm::dvec3 lo = vertex((*first)[0]), hi = lo;
  for (const auto& t : tris)
    if (drawable(t))
      for (const std::size_t i : t) {
        lo = glm::min(lo, vertex(i));
        hi = glm::max(hi, vertex(i));
      }
  const glm::dvec3 centre = (lo + hi) * 0.5;
  double radius = 0;
  for (const auto& t : tris)
    if (drawable(t))
      for (const std::size_t i : t) radius = std::max(radius, glm::length(vertex(i) - centre));
  if (!(radius > 0) || !std::isfinite(radius)) {
    // A single point (or an overflowing extent) has no size to frame; a unit sphere will do.
    radius = 1.0;
  }

  glm::dmat4 view;
  const glm::dmat4 view_projection = framing_camera(centre, radius, width, height, view);
  const glm::dvec3 light = glm::normalize(kLightDirection);

  Mesh mesh;
  mesh.space = Space::kClip;
  mesh.color_source = ColorSource::kPerVertex;
  mesh.positions.reserve(3 * tris.size());
  mesh.colors.reserve(3 * tris.size());
  mesh.normals.reserve(3 * tris.size());
  for (std::size_t ti = 0; ti < tris.size(); ++ti) {
    const auto& t = tris[ti];
    const glm::dvec3 a = vertex(t[0]), b = vertex(t[1]), c = vertex(t[2]);
    const std::array<int, 3>& ni = tri_normals[ti];
    if (ni[0] >= 0 && ni[1] >= 0 && ni[2] >= 0) {
      for (const int i : ni)
        mesh.normals.emplace_back(attrib.normals[3 * static_cast<std::size_t>(i)],
                                  attrib.normals[3 * static_cast<std::size_t>(i) + 1],
                                  attrib.normals[3 * static_cast<std::size_t>(i) + 2]);
    } else {
      const glm::vec3 face_normal(glm::cross(b - a, c - a));  // any length: shaders normalise
      mesh.normals.insert(mesh.normals.end(), {face_normal, face_normal, face_normal});
    }
    std::array<Rgba8, 3> col;
    if (!drawable(t)) {
      col.fill(kCulledColor);  // never seen: the NaN positions cull the triangle
    } else if (has_colors) {
      for (int k = 0; k < 3; ++k) {
        const std::size_t i = t[k];
        col[k] = {to_channel(attrib.colors[3 * i]), to_channel(attrib.colors[3 * i + 1]),
                  to_channel(attrib.colors[3 * i + 2]), kOpaque};
      }
    } else {
      // The face normal in view space gives a hue (its direction) and a brightness (the
      // light); |n·l| shades both windings alike, since OBJ files disagree on winding.
      glm::dvec3 n = glm::dvec3(view * glm::dvec4(glm::cross(b - a, c - a), 0.0));
      const double len = glm::length(n);
      n = len > 0 ? n / len : glm::dvec3(0, 0, 1);
      const double shade = kAmbient + kDiffuse * std::fabs(glm::dot(n, light));
      const glm::dvec3 base = glm::abs(n) * 0.5 + 0.5;
      const Rgba8 flat{to_channel(base.x * shade), to_channel(base.y * shade),
                       to_channel(base.z * shade), kOpaque};
      col = {flat, flat, flat};
    }
    for (const glm::dvec3& p : {a, b, c})
      mesh.positions.push_back(glm::vec4(view_projection * glm::dvec4(p, 1.0)));
    mesh.colors.insert(mesh.colors.end(), col.begin(), col.end());
  }

  Scene scene;
  scene.name = path.stem().string();
  scene.width = width;
  scene.height = height;
  scene.clear_color = kClearColor;
  scene.camera.view_projection = glm::mat4(view_projection);
  // The flat shade's light, taken from view space to model space (the view's rotation is
  // orthonormal: its inverse is its transpose), two-sided as the flat shade is.
  scene.light = {glm::vec3(glm::transpose(glm::dmat3(view)) * light), glm::vec3(kAlbedo),
                 static_cast<float>(kAmbient), static_cast<float>(kDiffuse), true};
  scene.default_shading = has_colors ? Shading::kFlat : Shading::kLambert;
  scene.meshes.push_back(std::move(mesh));
  if (!scan.bad_vertices.empty()) {
    const std::size_t bad = scan.bad_vertices.size(), culled = tris.size() - drawn;
    scene.warnings.push_back(printable(
        file + ":" + std::to_string(scan.bad_vertex_lines.front()) + ": " + std::to_string(bad) +
        (bad == 1 ? " vertex has" : " vertices have") +
        " a position that is not finite (the first on this line); " + std::to_string(culled) +
        " of " + std::to_string(tris.size()) + " triangles use one and are culled when drawn"));
  }
  if (bad_normals > 0)
    scene.warnings.push_back(printable(
        file + bad_normal_where + ": " + std::to_string(bad_normals) +
        (bad_normals == 1 ? " face corner names" : " face corners name") +
        " a normal that does not exist (the first on this line); their faces use the face "
        "normal"));
  return scene;
}

}  // namespace mosaic
