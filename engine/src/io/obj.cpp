// io/obj.cpp — loading a Wavefront OBJ mesh with a camera that frames it.
//
// Takes: an OBJ file: positions `v x y z [w] [r g b]`, normals `vn`, texture coordinates `vt`
// and polygon faces `f`; every other statement (`o`, `g`, `s`, materials) is ignored. Gives: a
// Scene with one indexed clip-space Mesh, its positions already multiplied by the camera's
// view-projection (so the Mesh needs no transform). Each distinct face corner (position, normal,
// texture coordinate) becomes one vertex, so a smooth mesh shares its vertices; a triangle whose
// corners do not all name a normal gets its face normal, on vertices of its own. The mesh has
// UVs when every corner names one. Its colour is the OBJ vertex colour when every vertex has one,
// otherwise a flat shade of the face normal per triangle, so that the shape reads; Scene::light
// lights the normals as the flat shade is lit.
//
// The file is parsed here in one pass with std::from_chars: every number and index is checked as
// it is read, so every error names its line, and memory is bounded as it grows. Polygons are
// fanned into triangles. A vertex position that is not finite (nan, inf, past float's range) is
// kept as NaN: its triangles are culled when drawn, as a draw's are, and Scene::warnings says
// how many.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <iterator>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
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

/// Albedo of Scene::light: a light grey, so that the lit normals show the shape alone.
constexpr float kAlbedo = 0.85f;

std::uint8_t to_channel(double v01) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(v01, 0.0, 1.0) * kChannelMax));
}

/// An index a face corner does not give (or whose target does not exist).
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// One face corner: 0-based indices of its position, texture coordinate and normal, or kNone.
struct Corner {
  std::uint32_t v, t, n;
};

/// A face of three or more corners: corners [first, first + count) and its line.
struct Face {
  std::uint32_t first, count, line;
};

/// The statements of an OBJ file that make its mesh, as read.
struct ObjFile {
  std::vector<glm::vec3> positions;
  std::vector<Rgba8> colors;  ///< one per position; meaningful when every `v` gave a colour
  std::size_t colored = 0;    ///< `v` lines with a colour
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  std::vector<Corner> corners;
  std::vector<Face> faces;
  std::size_t triangles = 0;  ///< of the faces, fanned
  /// Positions (0-based) with an x, y or z that is not finite, and their lines.
  std::vector<std::size_t> bad_vertices, bad_vertex_lines;

  /// Whether every `v` gave a colour, so that the mesh takes the file's colours.
  bool has_colors() const { return colored == positions.size(); }
};

/// What a triangle may take from reading the file to the finished Mesh: three corners (once as
/// read and once fanned), its share of a face, and the Mesh's indices and per-triangle colour;
/// then at most three vertices (clip position, normal, UV, colour, and the shared-vertex entry
/// of 4 indices that finds it again).
constexpr std::uintmax_t kBytesPerTriangle =
    2 * 3 * sizeof(Corner) + sizeof(Face) + 3 * sizeof(std::uint32_t) + sizeof(Rgba8) +
    3 * (sizeof(glm::vec4) + sizeof(glm::vec3) + sizeof(glm::vec2) + sizeof(Rgba8) +
         4 * sizeof(std::uint32_t));
/// What a `v`, `vn` or `vt` line takes: the largest, a position with its colour, its clip-space
/// copy and the first link of the shared-vertex lookup.
constexpr std::uintmax_t kBytesPerAttribute =
    sizeof(glm::vec3) + sizeof(Rgba8) + sizeof(glm::vec4) + sizeof(std::uint32_t);

/// The words of a line, separated by spaces and tabs.
class Words {
 public:
  explicit Words(std::string_view line) : rest_(line) {}
  bool next(std::string_view& word) {
    std::size_t i = 0;
    while (i < rest_.size() && (rest_[i] == ' ' || rest_[i] == '\t')) ++i;
    if (i == rest_.size()) return false;
    std::size_t j = i;
    while (j < rest_.size() && rest_[j] != ' ' && rest_[j] != '\t') ++j;
    word = rest_.substr(i, j - i);
    rest_.remove_prefix(j);
    return true;
  }

 private:
  std::string_view rest_;
};

/// How one number of a `v`, `vn` or `vt` line reads.
enum class NumberRead : std::uint8_t {
  kFinite,     ///< a number that fits a float (one too small for a float reads as 0)
  kNotFinite,  ///< nan, inf, or past float's range
  kMalformed,  ///< not a number
};

NumberRead read_number(std::string_view w, float& value) {
  if (io::read_short_decimal(w, value)) return NumberRead::kFinite;
  const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), value);
  const bool whole = end == w.data() + w.size();
  if (ec == std::errc::result_out_of_range && whole) {
    value = 0.0f;
    return io::underflows(w) ? NumberRead::kFinite : NumberRead::kNotFinite;
  }
  if (ec != std::errc() || !whole) return NumberRead::kMalformed;
  return std::isfinite(value) ? NumberRead::kFinite : NumberRead::kNotFinite;
}

/// Reads an OBJ file's text in one pass (see the file comment).
class ObjReader {
 public:
  ObjReader(const std::string& text, const std::string& file) : text_(text), file_(file) {}

  ObjFile read() {
    io::LineReader reader(text_, file_);
    for (std::string_view line; reader.next(line);) {
      line_ = reader.line_no();
      Words words(line.substr(0, line.find('#')));  // a comment runs to the end of its line
      std::string_view kw;
      if (!words.next(kw)) continue;
      if (kw == "v") {
        vertex(words);
      } else if (kw == "vn") {
        obj_.normals.push_back(attribute<3>(words, "a normal", "x y z", 3));
      } else if (kw == "vt") {
        const glm::vec3 uvw = attribute<3>(words, "a texture coordinate", "u [v [w]]", 1);
        obj_.uvs.emplace_back(uvw.x, uvw.y);
      } else if (kw == "f") {
        face(words);
      } else {
        continue;
      }
      check_memory();
    }
    return std::move(obj_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(Errc::kParse, file_ + ":" + std::to_string(line_) + ": " + what);
  }

  // `v x y z`, with a w (4 values), an r g b colour (6) or both (7, as some tools write them).
  void vertex(Words& words) {
    constexpr int kMaxValues = 7, kPosition = 3;
    std::array<float, kMaxValues> value{};
    int count = 0;
    bool finite = true;
    for (std::string_view w; words.next(w); ++count) {
      if (count == kMaxValues) fail("a vertex has at most 7 values (x y z [w] [r g b])");
      const NumberRead r = read_number(w, value[count]);
      // A position that is not finite culls the triangles that use the vertex, as a draw's
      // does; w and colours are not positions, and cannot be other than finite.
      if (r == NumberRead::kMalformed || (r == NumberRead::kNotFinite && count >= kPosition))
        fail("vertex value '" + std::string(w) + "' is not a finite number");
      finite = finite && r == NumberRead::kFinite;
    }
    if (count < kPosition || count == 5)
      fail("a vertex needs 3, 4, 6 or 7 values (x y z [w] [r g b]), got " + std::to_string(count));
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    if (!finite) {
      obj_.bad_vertices.push_back(obj_.positions.size());
      obj_.bad_vertex_lines.push_back(line_);
      obj_.positions.emplace_back(kNaN, kNaN, kNaN);
    } else {
      obj_.positions.emplace_back(value[0], value[1], value[2]);
    }
    Rgba8 color{0, 0, 0, kOpaque};
    if (count >= 6) {
      const int c = count - 3;  // the colour is the last three values
      color = {to_channel(value[c]), to_channel(value[c + 1]), to_channel(value[c + 2]), kOpaque};
      ++obj_.colored;
    }
    obj_.colors.push_back(color);
  }

  // `vn x y z` or `vt u [v [w]]`: `least` to N numbers. One that is not finite reads as 0, which
  // a shader takes as no normal (lit by the ambient term) or the texture's origin.
  template <int N>
  glm::vec3 attribute(Words& words, const char* what, const char* form, int least) {
    glm::vec3 out(0.0f);
    int count = 0;
    for (std::string_view w; words.next(w); ++count) {
      float v = 0.0f;
      if (count == N || read_number(w, v) == NumberRead::kMalformed)
        fail(std::string(what) + " is " + form + ", and '" + std::string(w) +
             "' does not fit that");
      out[count] = std::isfinite(v) ? v : 0.0f;
    }
    if (count < least)
      fail(std::string(what) + " is " + form + ", got " + std::to_string(count) + " values");
    return out;
  }

  // One index of a face corner: 1-based from the start, or negative from the last one read so
  // far. `count` is how many have been read; an absolute index past them is checked at the end.
  std::uint32_t index(std::string_view part, std::string_view corner, std::size_t count) const {
    // Digits by hand (from_chars is general and takes twice as long), at most kMaxDigits of them:
    // more cannot name a vertex of a file of at most 2 GiB, and 18 cannot overflow int64.
    constexpr std::size_t kMaxDigits = 18;
    const bool negative = !part.empty() && part[0] == '-';
    const std::string_view digits = part.substr(negative ? 1 : 0);
    const auto not_an_index = [&] {
      fail("face vertex '" + std::string(corner) + "' is not a vertex index");
    };
    if (digits.empty() || digits.size() > kMaxDigits) not_an_index();
    std::int64_t i = 0;
    for (const char ch : digits) {
      if (ch < '0' || ch > '9') not_an_index();
      i = i * 10 + (ch - '0');
    }
    if (i == 0) not_an_index();
    if (negative) i = -i;
    if (i < 0) {
      if (-i > static_cast<std::int64_t>(count))
        fail("face vertex '" + std::string(corner) + "' reaches before the first of " +
             std::to_string(count));
      return static_cast<std::uint32_t>(static_cast<std::int64_t>(count) + i);
    }
    // Past every index a file of at most 2 GiB can define.
    if (i >= static_cast<std::int64_t>(kNone))
      fail("face vertex '" + std::string(corner) + "' is not a vertex index");
    return static_cast<std::uint32_t>(i - 1);
  }

  // `f v[/t][/n] ...`: `v`, `v/t`, `v//n` or `v/t/n` per corner.
  void face(Words& words) {
    const std::size_t first = obj_.corners.size();
    for (std::string_view w; words.next(w);) {
      Corner c{kNone, kNone, kNone};
      const std::size_t s1 = w.find('/');
      c.v = index(w.substr(0, s1), w, obj_.positions.size());
      if (s1 != std::string_view::npos) {
        const std::string_view rest = w.substr(s1 + 1);
        const std::size_t s2 = rest.find('/');
        const std::string_view t = rest.substr(0, s2);
        if (!t.empty()) c.t = index(t, w, obj_.uvs.size());
        if (s2 != std::string_view::npos) {
          const std::string_view n = rest.substr(s2 + 1);
          if (n.empty() && t.empty()) fail("face vertex '" + std::string(w) + "' is malformed");
          if (!n.empty()) c.n = index(n, w, obj_.normals.size());
        }
      }
      obj_.corners.push_back(c);
    }
    const std::size_t count = obj_.corners.size() - first;
    // A point or a line draws nothing.
    if (count < 3) {
      obj_.corners.resize(first);
      return;
    }
    obj_.faces.push_back({static_cast<std::uint32_t>(first), static_cast<std::uint32_t>(count),
                          static_cast<std::uint32_t>(line_)});
    obj_.triangles += count - 2;
  }

  // The mesh read so far, and what its triangles will take once built, within the bound.
  void check_memory() const {
    const std::uintmax_t attributes = obj_.positions.size() + obj_.normals.size() + obj_.uvs.size();
    const std::uintmax_t bytes =
        attributes * kBytesPerAttribute + std::uintmax_t{obj_.triangles} * kBytesPerTriangle;
    if (bytes > io::kMaxSceneMeshBytes)
      fail("the mesh up to this line needs " + std::to_string(bytes) + " bytes, more than the " +
           std::to_string(io::kMaxSceneMeshBytes) + " a scene may take");
  }

  const std::string& text_;
  const std::string& file_;
  std::size_t line_ = 0;
  ObjFile obj_;
};

/// A triangle: three face corners.
using Triangle = std::array<Corner, 3>;

/// What the faces' corners name that does not exist: normals and texture coordinates, which
/// check_corners() drops, counted with the line of the first.
struct CornerCheck {
  std::size_t bad_normals = 0, bad_uvs = 0;
  std::string bad_normal_where, bad_uv_where;
  bool every_uv = true;  ///< every corner names a texture coordinate that exists
};

/// Throws for a corner whose position does not exist (forward references are read before this
/// check); drops, and counts, normals and texture coordinates that do not exist.
CornerCheck check_corners(ObjFile& obj, const std::string& file) {
  const std::size_t positions = obj.positions.size();
  CornerCheck check;
  for (std::size_t f = 0; f < obj.faces.size(); ++f) {
    const Face& face = obj.faces[f];
    const auto where = [&] { return std::string(":").append(std::to_string(face.line)); };
    for (std::uint32_t k = face.first; k < face.first + face.count; ++k) {
      Corner& c = obj.corners[k];
      if (c.v >= positions)
        throw Error(Errc::kParse, file + where() + ": face " + std::to_string(f + 1) +
                                      " names a vertex that does not exist (" +
                                      std::to_string(positions) + " vertices)");
      // A missing normal is not worth refusing a mesh for: the face's own normal stands in.
      if (c.n != kNone && c.n >= obj.normals.size()) {
        if (check.bad_normals++ == 0) check.bad_normal_where = where();
        c.n = kNone;
      }
      if (c.t != kNone && c.t >= obj.uvs.size()) {
        if (check.bad_uvs++ == 0) check.bad_uv_where = where();
        c.t = kNone;
      }
      check.every_uv = check.every_uv && c.t != kNone;
    }
  }
  return check;
}

/// The faces fanned from their first corner, in file order; texture coordinates kept only when
/// every corner has one.
std::vector<Triangle> fan(const ObjFile& obj, bool every_uv) {
  std::vector<Triangle> tris;
  tris.reserve(obj.triangles);
  for (const Face& face : obj.faces)
    for (std::uint32_t k = 1; k + 1 < face.count; ++k) {
      Triangle t{obj.corners[face.first], obj.corners[face.first + k],
                 obj.corners[face.first + k + 1]};
      if (!every_uv)
        for (Corner& c : t) c.t = kNone;
      tris.push_back(t);
    }
  return tris;
}

/// Whether a triangle's positions are all finite, so that it is drawn.
bool drawable(const ObjFile& obj, const Triangle& t) {
  return std::isfinite(obj.positions[t[0].v].x) && std::isfinite(obj.positions[t[1].v].x) &&
         std::isfinite(obj.positions[t[2].v].x);
}

/// The bounding sphere of the positions that drawable triangles use: the centre of their box
/// and the farthest of them. A single point, or an extent that overflows, has no size to frame:
/// its radius is 1.
std::pair<glm::dvec3, double> bounding_sphere(const ObjFile& obj,
                                              const std::vector<Triangle>& tris) {
  std::vector<bool> used(obj.positions.size());
  for (const Triangle& t : tris)
    if (drawable(obj, t))
      for (const Corner& c : t) used[c.v] = true;
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi = -lo;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) {
      lo = glm::min(lo, glm::dvec3(obj.positions[v]));
      hi = glm::max(hi, glm::dvec3(obj.positions[v]));
    }
  const glm::dvec3 centre = (lo + hi) * 0.5;
  double radius = 0;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) radius = std::max(radius, glm::length(glm::dvec3(obj.positions[v]) - centre));
  if (!(radius > 0) || !std::isfinite(radius)) radius = 1.0;
  return {centre, radius};
}

/// The flat shade of a face: its normal in view space gives a hue (its direction) and a
/// brightness (the light); |n·l| shades both windings alike, since OBJ files disagree on winding.
Rgba8 flat_shade(const glm::dvec3& face_normal, const glm::dmat4& view, const glm::dvec3& light) {
  glm::dvec3 n = glm::dvec3(view * glm::dvec4(face_normal, 0.0));
  const double len = glm::length(n);
  n = len > 0 ? n / len : glm::dvec3(0, 0, 1);
  const double shade = kAmbient + kDiffuse * std::fabs(glm::dot(n, light));
  const glm::dvec3 base = glm::abs(n) * 0.5 + 0.5;
  return {to_channel(base.x * shade), to_channel(base.y * shade), to_channel(base.z * shade),
          kOpaque};
}

/// The face normal of a triangle, cross(b - a, c - a): any length, since shaders normalise.
glm::dvec3 face_normal(const ObjFile& obj, const Triangle& t) {
  const glm::dvec3 a(obj.positions[t[0].v]), b(obj.positions[t[1].v]), c(obj.positions[t[2].v]);
  return glm::cross(b - a, c - a);
}

/// The vertices already made from each position for corners with a normal: a chain per
/// position, searched by texture coordinate and normal, so that equal corners share a vertex.
class SharedVertices {
 public:
  explicit SharedVertices(std::size_t positions) : first_(positions, kNone) {}

  /// The vertex made for a corner equal to `c`, or kNone.
  std::uint32_t find(const Corner& c) const {
    for (std::uint32_t e = first_[c.v]; e != kNone; e = entries_[e].next)
      if (entries_[e].t == c.t && entries_[e].n == c.n) return entries_[e].vertex;
    return kNone;
  }
  /// Notes that `vertex` was made for corner `c`.
  void add(const Corner& c, std::uint32_t vertex) {
    entries_.push_back({c.t, c.n, vertex, first_[c.v]});
    first_[c.v] = static_cast<std::uint32_t>(entries_.size() - 1);
  }

 private:
  struct Entry {
    std::uint32_t t, n, vertex, next;
  };
  std::vector<std::uint32_t> first_;
  std::vector<Entry> entries_;
};

/// The indexed Mesh of the triangles: a triangle whose corners all name a normal shares its
/// vertices with every equal corner; any other gets three vertices of its own with its face
/// normal. Colours: the file's per vertex, or the flat shade per triangle.
Mesh build_mesh(const ObjFile& obj, const std::vector<Triangle>& tris, bool every_uv,
                const glm::dmat4& view_projection, const glm::dmat4& view) {
  const bool has_colors = obj.has_colors();
  // Each position in clip space once, however many vertices it makes.
  std::vector<glm::vec4> clip(obj.positions.size());
  for (std::size_t v = 0; v < clip.size(); ++v)
    clip[v] = glm::vec4(view_projection * glm::dvec4(glm::dvec3(obj.positions[v]), 1.0));

  Mesh mesh;
  mesh.space = Space::kClip;
  mesh.color_source = has_colors ? ColorSource::kPerVertex : ColorSource::kPerTriangle;
  mesh.indices.reserve(3 * tris.size());
  // Three vertices per face-normal triangle; the shared ones, as in most meshes, about one per
  // position (more only grow the arrays).
  const auto with_normals =
      static_cast<std::size_t>(std::count_if(tris.begin(), tris.end(), [](const Triangle& t) {
        return t[0].n != kNone && t[1].n != kNone && t[2].n != kNone;
      }));
  const std::size_t expected =
      3 * (tris.size() - with_normals) + std::min(3 * with_normals, obj.positions.size());
  mesh.positions.reserve(expected);
  mesh.normals.reserve(expected);
  if (every_uv) mesh.uvs.reserve(expected);
  if (has_colors) mesh.colors.reserve(expected);
  const auto make = [&](const Corner& c, const glm::vec3& normal) {
    mesh.positions.push_back(clip[c.v]);
    mesh.normals.push_back(normal);
    if (every_uv) mesh.uvs.push_back(obj.uvs[c.t]);
    if (has_colors) mesh.colors.push_back(obj.colors[c.v]);
    return static_cast<std::uint32_t>(mesh.positions.size() - 1);
  };
  SharedVertices shared(obj.positions.size());
  for (const Triangle& t : tris) {
    if (t[0].n != kNone && t[1].n != kNone && t[2].n != kNone) {
      for (const Corner& c : t) {
        std::uint32_t i = shared.find(c);
        if (i == kNone) shared.add(c, i = make(c, obj.normals[c.n]));
        mesh.indices.push_back(i);
      }
    } else {
      const glm::vec3 normal(face_normal(obj, t));
      for (const Corner& c : t) mesh.indices.push_back(make(c, normal));
    }
  }
  // Vertices made in corner order, none shared: the indices would be 0, 1, 2, … .
  if (mesh.positions.size() == mesh.indices.size()) mesh.indices = {};
  if (!has_colors) {
    const glm::dvec3 light = glm::normalize(kLightDirection);
    mesh.colors.reserve(tris.size());
    for (const Triangle& t : tris)
      // A culled triangle's colour is never seen: its NaN positions cull it.
      mesh.colors.push_back(drawable(obj, t) ? flat_shade(face_normal(obj, t), view, light)
                                             : kCulledColor);
  }
  return mesh;
}

/// "<file>:<line>: <count> <one or many> ..." for Scene::warnings.
std::string count_warning(const std::string& file_line, std::size_t count, const char* one,
                          const char* many, const std::string& rest) {
  return printable(file_line + ": " + std::to_string(count) + (count == 1 ? one : many) + rest);
}

}  // namespace

Scene load_obj(const std::filesystem::path& path, int width, int height) {
  const std::string file = path.string();
  if (width < 1 || width > kMaxTargetSize || height < 1 || height > kMaxTargetSize)
    throw Error(Errc::kInvalidArgument, file + ": size " + std::to_string(width) + "x" +
                                            std::to_string(height) + " is outside 1..16384");
  ObjFile obj = ObjReader(io::read_scene_file(path), file).read();
  if (obj.faces.empty()) throw Error(Errc::kParse, file + ": no faces with three or more vertices");
  const CornerCheck check = check_corners(obj, file);
  std::vector<Triangle> tris = fan(obj, check.every_uv);
  obj.corners = {};
  obj.faces = {};
  const auto drawn = static_cast<std::size_t>(
      std::count_if(tris.begin(), tris.end(), [&](const Triangle& t) { return drawable(obj, t); }));
  if (drawn == 0) throw Error(Errc::kParse, file + ": every face uses a vertex that is not finite");

  const auto [centre, radius] = bounding_sphere(obj, tris);
  glm::dmat4 view;
  const glm::dmat4 view_projection = framing_camera(centre, radius, width, height, view);

  Scene scene;
  scene.name = path.stem().string();
  scene.width = width;
  scene.height = height;
  scene.clear_color = kClearColor;
  scene.camera.view_projection = glm::mat4(view_projection);
  // The flat shade's light, taken from view space to model space (the view's rotation is
  // orthonormal: its inverse is its transpose), two-sided as the flat shade is.
  scene.light = {glm::vec3(glm::transpose(glm::dmat3(view)) * glm::normalize(kLightDirection)),
                 glm::vec3(kAlbedo), static_cast<float>(kAmbient), static_cast<float>(kDiffuse),
                 true};
  scene.default_shading = obj.has_colors() ? Shading::kFlat : Shading::kLambert;
  scene.meshes.push_back(build_mesh(obj, tris, check.every_uv, view_projection, view));
  if (!obj.bad_vertices.empty())
    scene.warnings.push_back(count_warning(
        file + ":" + std::to_string(obj.bad_vertex_lines.front()), obj.bad_vertices.size(),
        " vertex has", " vertices have",
        " a position that is not finite (the first on this line); " +
            std::to_string(tris.size() - drawn) + " of " + std::to_string(tris.size()) +
            " triangles use one and are culled when drawn"));
  if (check.bad_normals > 0)
    scene.warnings.push_back(count_warning(
        file + check.bad_normal_where, check.bad_normals, " face corner names",
        " face corners name",
        " a normal that does not exist (the first on this line); their triangles use the face "
        "normal"));
  if (check.bad_uvs > 0)
    scene.warnings.push_back(count_warning(
        file + check.bad_uv_where, check.bad_uvs, " face corner names", " face corners name",
        " a texture coordinate that does not exist (the first on this line); the mesh has no "
        "UVs"));
  return scene;
}

}  // namespace mosaic
