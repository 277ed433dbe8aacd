// io/tris.cpp — reading and writing screen-space triangle files (.tris).
//
// Takes: text in the format of shared/formats/screen-triangles.md, or a Scene. Gives: a Scene
// with one screen-space Mesh (positions vec4(x, y, z, 1), no indices, one colour per vertex), or
// a .tris file. Parsing checks every line before it returns anything: the first malformed line
// throws Error{kParse, "<file>:<line>: <problem>"}.
//
// Precision: coordinates are parsed as double. Within the guard band (|x|, |y| <= 2^15 px) x and
// y are snapped to 1/256 px from that double, as the format says, and stored as floats, which
// hold every such step exactly: the renderer's own snapping then changes nothing, and a tie is
// decided by the decimal value, never by a float rounding of it. Beyond the guard band (where
// the renderer clips) x and y, and z everywhere, are rounded to the nearest float (Mesh positions
// are glm::vec4).

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "front/setup.hpp"
#include "io/lines.hpp"
#include "io/numbers.hpp"
#include "io/read_file.hpp"
#include "io/write_file.hpp"
#include "mosaic/errors.hpp"
#include "mosaic/renderer.hpp"
#include "mosaic/scene.hpp"

namespace mosaic {
namespace {

/// Coordinates per `tri` line: three vertices of x, y, z.
constexpr std::size_t kTriCoordinates = 9;
/// Colour values of a flat triangle (r g b a) and of a per-vertex one (three times r g b a).
constexpr std::size_t kFlatColorValues = 4;
constexpr std::size_t kVertexColorValues = 12;
/// Largest colour channel value (8 bits per channel).
constexpr int kMaxChannel = 255;
/// A Draw indexes vertices with uint32, so a file may hold at most this many triangles.
/// What a triangle of the loaded mesh holds: three positions and three colours.
constexpr std::size_t kBytesPerTriangle = 3 * (sizeof(glm::vec4) + sizeof(Rgba8));

/// Splits a line into whitespace-separated tokens, dropping everything from the first '#'.
std::vector<std::string_view> tokenize(std::string_view line) {
  if (const std::size_t hash = line.find('#'); hash != std::string_view::npos)
    line = line.substr(0, hash);
  std::vector<std::string_view> tokens;
  constexpr std::string_view kSpace = " \t\r\v\f";
  std::size_t pos = 0;
  while (true) {
    pos = line.find_first_not_of(kSpace, pos);
    if (pos == std::string_view::npos) break;
    std::size_t end = line.find_first_of(kSpace, pos);
    if (end == std::string_view::npos) end = line.size();
    tokens.push_back(line.substr(pos, end - pos));
    pos = end;
  }
  return tokens;
}

/// Drops one leading '+' (from_chars accepts only '-'), unless a sign follows it.
std::string_view strip_plus(std::string_view t) {
  if (t.size() > 1 && t[0] == '+' && t[1] != '+' && t[1] != '-') t.remove_prefix(1);
  return t;
}

/// The parser's position, for error messages.
struct Where {
  const std::string& file;
  std::size_t line;
  [[noreturn]] void fail(const std::string& problem) const {
    throw Error(Errc::kParse, file + ":" + std::to_string(line) + ": " + problem);
  }
};

std::string quoted(std::string_view t) {
  // Long garbage is cut so that the message stays one readable line.
  constexpr std::size_t kMaxShown = 40;
  std::string s(t.substr(0, kMaxShown));
  if (t.size() > kMaxShown) s += "...";
  return "'" + s + "'";
}

/// Counts the `tri` lines of `text` and reserves the mesh for them, after checking that they fit
/// the scene memory ceiling: a scene too large to hold fails before any of it is parsed. Every
/// line's length is checked here too, so that no line is tokenized before it is known bounded.
void reserve_triangles(std::string_view text, const std::string& name, Mesh& mesh) {
  io::LineReader lines(text, name);
  std::size_t tris = 0;
  for (std::string_view line; lines.next(line);) {
    const std::size_t first = line.find_first_not_of(" \t");
    if (first != std::string_view::npos && line.substr(first, 3) == "tri" &&
        (line.size() == first + 3 || line[first + 3] == ' ' || line[first + 3] == '\t'))
      ++tris;
  }
  io::check_scene_memory(name, tris, kBytesPerTriangle);
  mesh.positions.reserve(3 * tris);
  mesh.colors.reserve(3 * tris);
}

/// A finite decimal number that fits a float (the Mesh stores floats), read exactly as a double.
double parse_coordinate(std::string_view token, const char* what, const Where& where) {
  const std::string_view t = strip_plus(token);
  double v = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  const bool whole = end == t.data() + t.size();
  // A value too small for double is 0 to the renderer (snapped, or as a float): a zero of its
  // sign. One too large is an error.
  if (ec == std::errc::result_out_of_range && whole && io::underflows(t))
    return t[0] == '-' ? -0.0 : 0.0;
  if (ec == std::errc::result_out_of_range)
    where.fail(std::string(what) + " " + quoted(token) + " is out of range");
  if (ec != std::errc() || !whole)
    where.fail(std::string(what) + " " + quoted(token) + " is not a number");
  if (!std::isfinite(v)) where.fail(std::string(what) + " " + quoted(token) + " is not finite");
  if (std::fabs(v) > static_cast<double>(std::numeric_limits<float>::max()))
    where.fail(std::string(what) + " " + quoted(token) + " is out of range");
  return v;
}

/// An x or y coordinate: snapped to 1/256 px from its double within the guard band, where every
/// step is exact in float.
float parse_xy(std::string_view token, const char* what, const Where& where) {
  const double v = parse_coordinate(token, what, where);
  if (std::fabs(v) > front::kGuardBandPx) return static_cast<float>(v);
  return static_cast<float>(front::snap(v)) / static_cast<float>(front::kSubpixelOne);
}

/// A decimal integer in [lo, hi].
int parse_int(std::string_view token, int lo, int hi, const char* what, const Where& where) {
  const std::string_view t = strip_plus(token);
  long long v = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  const std::string range = std::to_string(lo) + ".." + std::to_string(hi);
  if (ec == std::errc::result_out_of_range)
    where.fail(std::string(what) + " " + quoted(token) + " is outside " + range);
  if (ec != std::errc() || end != t.data() + t.size())
    where.fail(std::string(what) + " " + quoted(token) + " is not an integer");
  if (v < lo || v > hi)
    where.fail(std::string(what) + " " + quoted(token) + " is outside " + range);
  return static_cast<int>(v);
}

std::uint8_t parse_channel(std::string_view token, const Where& where) {
  return static_cast<std::uint8_t>(parse_int(token, 0, kMaxChannel, "colour value", where));
}

Rgba8 parse_color(const std::string_view* t, const Where& where) {
  return {parse_channel(t[0], where), parse_channel(t[1], where), parse_channel(t[2], where),
          parse_channel(t[3], where)};
}

// ---- writing ----

/// Shortest decimal text that reads back to the same value.
template <class T>
void append_number(std::string& out, T v) {
  std::array<char, 64> buf;
  const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  (void)ec;  // 64 characters hold any float or double
  out.append(buf.data(), end);
}

void append_color(std::string& out, Rgba8 c) {
  for (const std::uint8_t ch : {c.r, c.g, c.b, c.a}) {
    out += ' ';
    out += std::to_string(ch);
  }
}

/// One vertex ready to write: pixels and depth, as the renderer's front end computes them.
struct OutVertex {
  double x = 0, y = 0;
  float z = 0;
  bool exact_float = true;  ///< x, y are floats of the mesh: write them as floats (shorter)
};

/// Projects vertex `i` of `draw` like front/front_end.cpp (the viewport transform and the
/// perspective divide). False when the vertex lies behind the near plane or is not finite.
bool project(const Draw& draw, std::uint32_t i, double half_w, double half_h, OutVertex& out) {
  const glm::dvec4 p(draw.positions[i]);
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(p.w))
    return false;
  if (!(p.w > 0)) return false;
  const double q = 1.0 / p.w;
  if (draw.space == Space::kScreen) {
    // Screen space is window-homogeneous: divided, as the front end does (types.hpp). A depth
    // below 0 is kept: the renderer clips it the same way when the file is drawn.
    out = {p.x * q, p.y * q, static_cast<float>(p.z * q), p.w == 1.0};
    return std::isfinite(out.x) && std::isfinite(out.y);
  }
  // The triangle must be wholly in front of the near plane (Z >= 0, W > 0): a .tris file
  // has no perspective, so a clipped triangle could not be drawn the same way.
  if (p.z < 0) return false;
  out.x = ((p.x + p.w) * half_w) * q;
  out.y = ((p.w - p.y) * half_h) * q;
  out.z = static_cast<float>(p.z * q);
  out.exact_float = false;
  return std::isfinite(out.x) && std::isfinite(out.y);
}

void append_coordinate(std::string& out, double v, bool exact_float) {
  out += ' ';
  if (exact_float) {
    append_number(out, static_cast<float>(v));
  } else {
    append_number(out, v);
  }
}

}  // namespace

Scene parse_tris(const std::string& text, const std::string& name) {
  Scene scene;
  scene.name = name;
  Mesh mesh;
  mesh.space = Space::kScreen;
  mesh.color_source = ColorSource::kPerVertex;

  bool have_size = false, have_clear = false;
  // A UTF-8 byte order mark (some Windows editors write one) is not part of the first line.
  constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";
  std::string_view body = text;
  if (body.substr(0, kUtf8Bom.size()) == kUtf8Bom) body.remove_prefix(kUtf8Bom.size());
  reserve_triangles(body, name, mesh);
  io::LineReader lines(body, name);
  std::size_t line_no = 0;
  for (std::string_view line; lines.next(line);) {
    line_no = lines.line_no();
    const Where where{name, line_no};
    if (line.find('\0') != std::string_view::npos) where.fail("NUL character in the line");

    const std::vector<std::string_view> t = tokenize(line);
    if (t.empty()) continue;
    const std::string_view kw = t[0];
    const std::size_t args = t.size() - 1;

    if (!have_size && kw != "size")
      where.fail("expected 'size W H' as the first line, found " + quoted(kw));
    if (kw == "size") {
      if (have_size) where.fail("second 'size' line");
      if (args != 2)
        where.fail("'size' needs 2 integers (width height), got " + std::to_string(args));
      scene.width = parse_int(t[1], 1, kMaxTargetSize, "width", where);
      scene.height = parse_int(t[2], 1, kMaxTargetSize, "height", where);
      have_size = true;
    } else if (kw == "clear") {
      if (have_clear) where.fail("second 'clear' line");
      if (args != kFlatColorValues)
        where.fail("'clear' needs 4 colour values (r g b a), got " + std::to_string(args));
      scene.clear_color = parse_color(&t[1], where);
      have_clear = true;
    } else if (kw == "tri") {
      if (args != kTriCoordinates + kFlatColorValues &&
          args != kTriCoordinates + kVertexColorValues)
        where.fail("'tri' needs 9 coordinates and 4 or 12 colour values, got " +
                   std::to_string(args) + " values");
      std::array<glm::vec4, 3> v;
      for (int k = 0; k < 3; ++k) {
        v[k] = {parse_xy(t[1 + 3 * k], "x", where), parse_xy(t[2 + 3 * k], "y", where),
                static_cast<float>(parse_coordinate(t[3 + 3 * k], "z", where)), 1.0f};
      }
      const std::string_view* colors = &t[1 + kTriCoordinates];
      std::array<Rgba8, 3> c;
      c[0] = parse_color(colors, where);
      if (args == kTriCoordinates + kVertexColorValues) {
        c[1] = parse_color(colors + 4, where);
        c[2] = parse_color(colors + 8, where);
      } else {
        c[1] = c[2] = c[0];  // setup sees three equal colours and shades the triangle flat
      }
      mesh.positions.insert(mesh.positions.end(), v.begin(), v.end());
      mesh.colors.insert(mesh.colors.end(), c.begin(), c.end());
    } else {
      where.fail("unknown keyword " + quoted(kw) + " (expected size, clear or tri)");
    }
  }
  if (!have_size) {
    Where{name, std::max<std::size_t>(line_no, 1)}.fail(
        "end of file before the required 'size W H' line");
  }
  scene.meshes.push_back(std::move(mesh));
  return scene;
}

Scene load_tris(const std::filesystem::path& path) {
  const std::string file = path.string();
  Scene scene = parse_tris(io::read_scene_file(path), file);
  scene.name = path.stem().string();
  return scene;
}

void save_tris(const Scene& scene, const std::filesystem::path& path) {
  const std::string file = path.string();
  if (scene.width < 1 || scene.width > kMaxTargetSize || scene.height < 1 ||
      scene.height > kMaxTargetSize) {
    throw Error(Errc::kInvalidArgument, file + ": scene size " + std::to_string(scene.width) + "x" +
                                            std::to_string(scene.height) + " is outside 1..16384");
  }
  // The draws must be consistent before any of their buffers are read. validate() does not
  // look at the target beyond its existence, so a 1x1 one stands in for the scene's size.
  const std::vector<Draw> draws = scene.draws();
  validate(Frame{draws}, RenderTarget(1, 1));

  // The name may hold a line break (it is a file name): printable() keeps the comment one line.
  std::string out = "# written by mosaic from scene '" + printable(scene.name) + "'\n";
  out += "size " + std::to_string(scene.width) + " " + std::to_string(scene.height) + "\n";
  out += "clear";
  append_color(out, scene.clear_color);
  out += '\n';

  const double half_w = scene.width * 0.5, half_h = scene.height * 0.5;
  for (const Draw& draw : draws) {
    const std::size_t tris =
        (draw.indices.empty() ? draw.positions.size() : draw.indices.size()) / 3;
    for (std::size_t t = 0; t < tris; ++t) {
      std::array<std::uint32_t, 3> vi;
      for (std::size_t k = 0; k < 3; ++k)
        vi[k] =
            draw.indices.empty() ? static_cast<std::uint32_t>(3 * t + k) : draw.indices[3 * t + k];
      std::array<OutVertex, 3> v;
      bool ok = true;
      for (int k = 0; k < 3; ++k) ok = ok && project(draw, vi[k], half_w, half_h, v[k]);
      if (!ok) continue;

      // Face culling as setup decides it, on the snapped vertices: the file has no cull state.
      if (draw.state.cull != CullMode::kNone) {
        std::array<std::int64_t, 3> sx, sy;
        bool snappable = true;
        for (int k = 0; k < 3; ++k) {
          // snap() needs |x| within the guard band; larger triangles keep their winding.
          snappable = snappable && std::fabs(v[k].x) <= front::kGuardBandPx &&
                      std::fabs(v[k].y) <= front::kGuardBandPx;
          if (snappable) {
            sx[k] = front::snap(v[k].x);
            sy[k] = front::snap(v[k].y);
          }
        }
        double area2 = 0;
        if (snappable) {
          area2 = static_cast<double>((sx[1] - sx[0]) * (sy[2] - sy[0]) -
                                      (sx[2] - sx[0]) * (sy[1] - sy[0]));
        } else {
          area2 = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
        }
        const bool ccw_on_screen = area2 < 0;
        const bool front_facing =
            (draw.state.front_face == FrontFace::kCounterClockwise) == ccw_on_screen;
        if ((draw.state.cull == CullMode::kBack && !front_facing) ||
            (draw.state.cull == CullMode::kFront && front_facing))
          continue;
      }

      std::array<Rgba8, 3> c;
      switch (draw.color_source) {
        case ColorSource::kConstant:
          c.fill(draw.color);
          break;
        case ColorSource::kPerTriangle:
          c.fill(draw.colors[t]);
          break;
        case ColorSource::kPerVertex:
          for (int k = 0; k < 3; ++k) c[k] = draw.colors[vi[k]];
          break;
      }
      out += "tri";
      for (int k = 0; k < 3; ++k) {
        out += ' ';
        append_coordinate(out, v[k].x, v[k].exact_float);
        append_coordinate(out, v[k].y, v[k].exact_float);
        out += ' ';
        append_number(out, v[k].z);
      }
      out += ' ';
      append_color(out, c[0]);
      if (c[1] != c[0] || c[2] != c[0]) {
        out += ' ';
        append_color(out, c[1]);
        out += ' ';
        append_color(out, c[2]);
      }
      out += '\n';
    }
  }

  io::write_file_replacing(path, out);
}

}  // namespace mosaic
