// Scene and image I/O (io/tris.cpp, io/obj.cpp, io/image.cpp): the .tris grammar of
// shared/formats/screen-triangles.md and every way a line can break it, save/parse round
// trips, OBJ loading and its errors, and PNG / PPM files read back with stb_image.
#include <gtest/gtest.h>
#include <stb/stb_image.h>  // libstb-dev; tests do not get its pkg-config include path
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "io/lines.hpp"
#include "io/numbers.hpp"
#include "io/read_file.hpp"
#include "mosaic/mosaic.hpp"

namespace mosaic {
namespace {

namespace fs = std::filesystem;

/// A fresh directory per test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("mosaic_test_io_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }
  fs::path operator/(const std::string& name) const { return path_ / name; }
  /// Names of the files in the directory, sorted.
  std::vector<std::string> files() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path_)) names.push_back(e.path().filename());
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  fs::path path_;
};

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string data_file(const std::string& name) {
  return std::string(MOSAIC_TEST_DATA_DIR) + "/" + name;
}

/// Renders a scene with the reference rasterizer at its own size.
RenderTarget render(const Scene& s, int samples = 1, TargetOptions options = {}) {
  Renderer renderer({1, Isa::kReference});
  RenderTarget target(s.width, s.height, samples, options);
  target.set_clear(s.clear_color, s.clear_depth);
  const std::vector<Draw> draws = s.draws();
  renderer.render(Frame{draws}, target);
  return target;
}

// ---- parse_tris: accepted input ----

TEST(TrisParse, ReadsSizeClearFlatAndPerVertexTriangles) {
  const std::string text =
      "# a comment line\n"
      "\n"
      "   \t  \n"
      "size 640 480   # trailing comment\n"
      "clear 10 20 30 40\n"
      "tri 1 2 0.5  3.25 4 0.25  -5 6e1 1   100 110 120 255\n"
      "tri\t0 0 0 10 0 0 0 10 0  255 0 0 255  0 255 0 128  0 0 255 0\r\n"
      "#tri 1 1 1 1 1 1 1 1 1 1 1 1 1\n";
  const Scene s = parse_tris(text, "t.tris");
  EXPECT_EQ(s.name, "t.tris");
  EXPECT_EQ(s.width, 640);
  EXPECT_EQ(s.height, 480);
  EXPECT_EQ(s.clear_color, (Rgba8{10, 20, 30, 40}));
  EXPECT_EQ(s.clear_depth, 1.0f);
  ASSERT_EQ(s.meshes.size(), 1u);
  const Mesh& m = s.meshes[0];
  EXPECT_EQ(m.space, Space::kScreen);
  EXPECT_EQ(m.color_source, ColorSource::kPerVertex);
  EXPECT_TRUE(m.indices.empty());
  EXPECT_EQ(m.state.depth_test, DepthTest::kLess);
  EXPECT_EQ(m.state.cull, CullMode::kNone);
  ASSERT_EQ(m.positions.size(), 6u);
  EXPECT_EQ(m.positions[0], glm::vec4(1, 2, 0.5f, 1));
  EXPECT_EQ(m.positions[1], glm::vec4(3.25f, 4, 0.25f, 1));
  EXPECT_EQ(m.positions[2], glm::vec4(-5, 60, 1, 1));
  EXPECT_EQ(m.positions[5], glm::vec4(0, 10, 0, 1));
  ASSERT_EQ(m.colors.size(), 6u);
  // A flat triangle gets its colour three times; a per-vertex one its three colours.
  for (int k = 0; k < 3; ++k) EXPECT_EQ(m.colors[k], (Rgba8{100, 110, 120, 255}));
  EXPECT_EQ(m.colors[3], (Rgba8{255, 0, 0, 255}));
  EXPECT_EQ(m.colors[4], (Rgba8{0, 255, 0, 128}));
  EXPECT_EQ(m.colors[5], (Rgba8{0, 0, 255, 0}));
}

TEST(TrisParse, DefaultsWithoutClearAndAcceptsNoTriangles) {
  const Scene s = parse_tris("size 1 16384\n");
  EXPECT_EQ(s.width, 1);
  EXPECT_EQ(s.height, 16384);
  EXPECT_EQ(s.clear_color, (Rgba8{0, 0, 0, 255}));
  EXPECT_EQ(s.triangle_count(), 0u);
  // A UTF-8 byte order mark before the first line is skipped.
  EXPECT_EQ(parse_tris("\xEF\xBB\xBFsize 2 3\n").height, 3);
  // The file need not end with a newline.
  EXPECT_EQ(parse_tris("size 4 4\ntri 0 0 0 4 0 0 0 4 0 1 2 3 4").triangle_count(), 1u);
}

TEST(TrisParse, ExtremeButFiniteCoordinatesAreAccepted) {
  const Scene s =
      parse_tris("size 8 8\ntri -1e30 0 0  3.4e38 0.000001 0  1e-300 -0 -2.5  0 0 0 255\n");
  const Mesh& m = s.meshes[0];
  EXPECT_EQ(m.positions[0].x, -1e30f);
  EXPECT_EQ(m.positions[1].x, 3.4e38f);
  EXPECT_EQ(m.positions[2].x, 0.0f);   // below float's range: rounds to zero, still finite
  EXPECT_EQ(m.positions[2].z, -2.5f);  // depth outside [0, 1] is clipped when drawn, not here
}

TEST(TrisParse, XAndYSnapFromTheirDecimalValueWithTiesToEven) {
  // 10.501953125 is 2688.5 steps of 1/256 px, a tie: it goes to the even step, 2688 (10.5).
  // 10.50195313 lies just above that tie, and rounds up to 2689 (10.50390625), though its
  // nearest float is the tie itself. 10.505859375 is the tie 2689.5, which goes to 2690.
  // Past the guard band (2^15 px) a coordinate is only rounded to float; z is never snapped.
  const Scene s = parse_tris(
      "size 8 8\n"
      "tri 10.501953125 10.50195313 10.501953125  10.505859375 -10.505859375 0  "
      "40000.3 -0.001953125 0  0 0 0 255\n");
  const Mesh& m = s.meshes[0];
  EXPECT_EQ(m.positions[0].x, 10.5f);
  EXPECT_EQ(m.positions[0].y, 10.50390625f);
  EXPECT_EQ(m.positions[0].z, 10.501953125f);
  EXPECT_EQ(m.positions[1].x, 10.5078125f);
  EXPECT_EQ(m.positions[1].y, -10.5078125f);
  EXPECT_EQ(m.positions[2].x, 40000.3f);
  EXPECT_EQ(m.positions[2].y, 0.0f);  // -1/512 is the tie -0.5, which goes to 0
}

// Values too small for double are valid coordinates that round to zero, however they are
// written (a long run of zeros, or an exponent); too large ones stay errors.
TEST(TrisParse, NumbersTooSmallForDoubleReadAsZero) {
  const std::string tiny = "0." + std::string(100000, '0') + "1";
  const Scene s = parse_tris("size 8 8\ntri " + tiny + " 1e-400 -1e-99999999999999999999  8 -" +
                             tiny + " 0.5  0 8 0  0 0 0 255\n");
  const Mesh& m = s.meshes[0];
  EXPECT_EQ(m.positions[0], glm::vec4(0, 0, 0, 1));
  EXPECT_EQ(m.positions[1], glm::vec4(8, 0, 0.5f, 1));
  EXPECT_TRUE(std::signbit(m.positions[0].z)) << "a zero of its sign";
  for (const std::string& big :
       std::vector<std::string>{"1e999", "-1e400", "1" + std::string(400, '0')}) {
    try {
      parse_tris("size 8 8\ntri " + big + " 0 0  8 0 0  0 8 0  0 0 0 255\n", "b.tris");
      ADD_FAILURE() << big << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("b.tris:2: x"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
    }
  }
}

// A line ends at LF, CR LF or a lone CR (old Mac files), in any mix: line numbers count them.
TEST(TrisParse, EveryLineEndCountsAsOne) {
  const std::string tri = "tri 0 0 0  8 0 0  0 8 0  0 0 0 255";
  const Scene s = parse_tris("size 8 8\r" + tri + "\r\n" + tri + "\n" + tri + "\r");
  EXPECT_EQ(s.triangle_count(), 3u);
  try {
    parse_tris("size 8 8\r# two\r\n\rtri 1 2\n", "cr.tris");
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("cr.tris:4: ", 0), 0u) << e.what();
  }
}

TEST(TrisParse, FlatTriangleRendersLikeItsThreeEqualColours) {
  // The parser stores a flat triangle as three equal vertex colours; setup must shade it with
  // exactly that colour (no interpolation rounding), over every covered pixel.
  const Scene s = parse_tris("size 16 16\ntri 0 0 0.5 16 0 0.5 0 16 0.5 37 201 99 255\n");
  const RenderTarget t = render(s);
  int painted = 0;
  for (const Rgba8 c : t.color()) {
    if (c == Rgba8{0, 0, 0, 255}) continue;
    EXPECT_EQ(c, (Rgba8{37, 201, 99, 255}));
    ++painted;
  }
  // Pixel centres (x + 0.5, y + 0.5) with x + y < 15 are inside: 1 + 2 + ... + 15 = 120. The
  // 16 centres with x + y = 15 lie on the hypotenuse, a right edge under either fill rule.
  EXPECT_EQ(painted, 120);
}

// ---- parse_tris: every malformed line ----

struct BadCase {
  const char* what;
  std::string text;
  int line;  ///< the line the error must name
};

std::vector<BadCase> bad_cases() {
  const std::string ok_tri = "tri 0 0 0 1 0 0 0 1 0 1 2 3 4\n";
  return {
      {"empty file", "", 1},
      {"only comments", "# nothing\n\n# here\n", 3},
      {"tri before size", "# c\ntri 0 0 0 1 0 0 0 1 0 1 2 3 4\nsize 4 4\n", 2},
      {"clear before size", "clear 0 0 0 255\nsize 4 4\n", 1},
      {"second size", "size 4 4\n" + ok_tri + "size 4 4\n", 3},
      {"size with one value", "size 4\n", 1},
      {"size with three values", "size 4 4 4\n", 1},
      {"size zero", "size 0 4\n", 1},
      {"size too large", "size 4 16385\n", 1},
      {"size negative", "size -4 4\n", 1},
      {"size not an integer", "size 4.0 4\n", 1},
      {"size garbage", "size 4x 4\n", 1},
      {"size overflowing", "size 99999999999999999999999 4\n", 1},
      {"clear with three values", "size 4 4\nclear 0 0 0\n", 2},
      {"clear with five values", "size 4 4\nclear 0 0 0 0 0\n", 2},
      {"clear 256", "size 4 4\nclear 0 256 0 0\n", 2},
      {"clear -1", "size 4 4\nclear 0 0 -1 0\n", 2},
      {"clear 1.5", "size 4 4\nclear 1.5 0 0 0\n", 2},
      {"second clear", "size 4 4\nclear 0 0 0 0\nclear 0 0 0 0\n", 3},
      {"truncated tri", "size 4 4\n" + ok_tri + "tri 0 0 0 1 0\n", 3},
      {"tri without colour", "size 4 4\ntri 0 0 0 1 0 0 0 1 0\n", 2},
      {"tri with 3 colour values", "size 4 4\ntri 0 0 0 1 0 0 0 1 0 1 2 3\n", 2},
      {"tri with 5 colour values", "size 4 4\ntri 0 0 0 1 0 0 0 1 0 1 2 3 4 5\n", 2},
      {"tri with 11 colour values", "size 4 4\ntri 0 0 0 1 0 0 0 1 0 1 2 3 4 5 6 7 8 9 10 11\n", 2},
      {"tri with 13 colour values",
       "size 4 4\ntri 0 0 0 1 0 0 0 1 0 1 2 3 4 5 6 7 8 9 10 11 12 13\n", 2},
      {"coordinate nan", "size 4 4\ntri nan 0 0 1 0 0 0 1 0 1 2 3 4\n", 2},
      {"coordinate inf", "size 4 4\ntri 0 inf 0 1 0 0 0 1 0 1 2 3 4\n", 2},
      {"coordinate -infinity", "size 4 4\ntri 0 0 -infinity 1 0 0 0 1 0 1 2 3 4\n", 2},
      {"coordinate out of double range", "size 4 4\ntri 0 0 0 1e999 0 0 0 1 0 1 2 3 4\n", 2},
      {"coordinate out of float range", "size 4 4\ntri 0 0 0 1 -1e39 0 0 1 0 1 2 3 4\n", 2},
      {"coordinate garbage", "size 4 4\ntri 0 0 0 1 0 0 0 1 abc 1 2 3 4\n", 2},
      {"coordinate with trailing junk", "size 4 4\ntri 0 0 0 1.5.2 0 0 0 1 0 1 2 3 4\n", 2},
      {"coordinate hexadecimal", "size 4 4\ntri 0x10 0 0 1 0 0 0 1 0 1 2 3 4\n", 2},
      {"coordinate with comma", "size 4 4\ntri 1,5 0 0 1 0 0 0 1 0 1 2 3 4\n", 2},
      {"coordinate double sign", "size 4 4\ntri --1 0 0 1 0 0 0 1 0 1 2 3 4\n", 2},
      {"colour 256", "size 4 4\ntri 0 0 0 1 0 0 0 1 0 1 2 256 4\n", 2},
      {"colour -1", "size 4 4\ntri 0 0 0 1 0 0 0 1 0 1 -1 3 4\n", 2},
      {"colour 1.5", "size 4 4\ntri 0 0 0 1 0 0 0 1 0 1.5 2 3 4\n", 2},
      {"colour 1e2", "size 4 4\ntri 0 0 0 1 0 0 0 1 0 1e2 2 3 4\n", 2},
      {"last per-vertex colour 256",
       "size 4 4\ntri 0 0 0 1 0 0 0 1 0 1 2 3 4 5 6 7 8 9 10 11 256\n", 2},
      {"unknown keyword", "size 4 4\n" + ok_tri + ok_tri + "triangle 0 0 0 1 0 0 0 1 0 1 2 3 4\n",
       4},
      {"keyword in upper case", "size 4 4\nTRI 0 0 0 1 0 0 0 1 0 1 2 3 4\n", 2},
      {"NUL byte", std::string("size 4 4\n") + ok_tri + std::string("tri 0 0\0 0", 11) + "\n", 3},
      {"error after many good lines",
       "size 4 4\n" + ok_tri + ok_tri + ok_tri + ok_tri + ok_tri + "tri 0 0 0 1 0 0 0 1 0 1 2 3\n",
       7},
  };
}

TEST(TrisParse, EveryMalformedLineIsAParseErrorNamingFileAndLine) {
  for (const BadCase& c : bad_cases()) {
    try {
      parse_tris(c.text, "bad.tris");
      ADD_FAILURE() << c.what << ": accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), Errc::kParse) << c.what;
      const std::string msg = e.what();
      const std::string where = "bad.tris:" + std::to_string(c.line) + ": ";
      EXPECT_EQ(msg.rfind(where, 0), 0u) << c.what << ": " << msg;
      EXPECT_GT(msg.size(), where.size() + 5) << c.what << ": the problem is named";
      EXPECT_EQ(msg.find('\n'), std::string::npos) << c.what << ": one line";
    }
  }
}

TEST(TrisParse, MessagesNameTheProblem) {
  auto message = [](const std::string& text) {
    try {
      parse_tris(text, "m.tris");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("size 4 4\ntri 0 0 0 1 0 0 0 1 0 1 2 256 4\n").find("'256'"),
            std::string::npos);
  EXPECT_NE(message("size 4 4\ntri nan 0 0 1 0 0 0 1 0 1 2 3 4\n").find("'nan'"),
            std::string::npos);
  EXPECT_NE(message("size 4 4\nsize 4 4\n").find("second 'size'"), std::string::npos);
  EXPECT_NE(message("size 4 4\nquad 1\n").find("unknown keyword 'quad'"), std::string::npos);
  EXPECT_NE(message("size 4 4\ntri 1 2\n").find("got 2 values"), std::string::npos);
}

// ---- load_tris ----

TEST(TrisLoad, ReadsAFileAndNamesItInErrors) {
  TempDir dir;
  write_text(dir / "good.tris", "size 3 2\ntri 0 0 0 3 0 0 0 2 0 9 9 9 9\n");
  const Scene s = load_tris(dir / "good.tris");
  EXPECT_EQ(s.name, "good");
  EXPECT_EQ(s.width, 3);
  EXPECT_EQ(s.triangle_count(), 1u);

  write_text(dir / "bad.tris", "size 3 2\n\ntri 0 0 0 3 0 0 0 2 0 9 9 9\n");
  try {
    load_tris(dir / "bad.tris");
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), Errc::kParse);
    EXPECT_EQ(std::string(e.what()).rfind((dir / "bad.tris").string() + ":3: ", 0), 0u) << e.what();
  }
}

TEST(TrisLoad, MissingFileOrDirectoryIsAnIoError) {
  TempDir dir;
  for (const fs::path& p : {dir / "missing.tris", dir.path()}) {
    try {
      load_tris(p);
      FAIL() << p << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), Errc::kIo);
      EXPECT_EQ(std::string(e.what()).rfind(p.string() + ": cannot open", 0), 0u) << e.what();
    }
  }
}

// What is not a regular file may never end (a symlink to /dev/zero, a pipe): both loaders refuse
// it before reading a byte, as they refuse a file past the size bound (a sparse file here).
TEST(SceneFiles, DevicesPipesAndHugeFilesAreIoErrorsBeforeAnyRead) {
  TempDir dir;
  fs::create_symlink("/dev/zero", dir / "zero.tris");
  fs::create_symlink("/dev/zero", dir / "zero.obj");
  ASSERT_EQ(mkfifo((dir / "pipe.tris").c_str(), 0600), 0);
  const fs::path huge = dir / "huge.obj";
  std::ofstream(huge) << "v 0 0 0\n";
  fs::resize_file(huge, (std::uintmax_t{1} << 31) + 1);  // sparse: no disk is used
  const auto expect_io = [](auto&& load, const fs::path& p, const std::string& why) {
    try {
      load(p);
      ADD_FAILURE() << p << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), Errc::kIo) << p;
      EXPECT_EQ(std::string(e.what()).rfind(p.string() + ": ", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  const auto tris = [](const fs::path& p) { return load_tris(p); };
  const auto obj = [](const fs::path& p) { return load_obj(p); };
  expect_io(tris, dir / "zero.tris", "not a regular file");
  expect_io(obj, dir / "zero.obj", "not a regular file");
  expect_io(tris, dir / "pipe.tris", "not a regular file");
  expect_io(obj, huge, "2147483649 bytes, more than the 2147483648");
}

TEST(SceneFiles, LinesPastOneMebibyteAreParseErrorsNamingTheLine) {
  // A line of exactly kMaxLineBytes is read; one byte more fails, naming the line, before the
  // line is split: a 'tri' line of 10^7 triangles' values took 25 s and 2.4 GiB to reject.
  TempDir dir;
  const std::string at_limit(io::kMaxLineBytes, ' ');
  const std::string tri = "tri 0 0 0 8 0 0 0 8 0 1 2 3 255\n";
  EXPECT_EQ(parse_tris("size 8 8\n" + tri + "#" + at_limit.substr(1) + "\n" + tri, "ok.tris")
                .triangle_count(),
            2u);
  std::string values = "size 8 8\n" + tri + "tri";
  while (values.size() < 40 * io::kMaxLineBytes) values += " 0.5 0.5 0.5 0.5";
  const std::string one_over = "size 8 8\r\n\r\n" + at_limit + "x\r\n" + tri;
  std::ofstream(dir / "long.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3" << at_limit << "\n";
  const struct {
    std::function<Scene()> load;
    std::string where;
  } cases[] = {
      {[&] { return parse_tris(values + "\n", "values.tris"); }, "values.tris:3: a line of "},
      {[&] { return parse_tris(one_over, "over.tris"); },
       "over.tris:3: a line of 1048577 bytes, longer than the 1048576"},
      {[&] { return load_obj(dir / "long.obj"); }, "long.obj:4: a line of 1048583 bytes"},
  };
  for (const auto& c : cases) {
    const auto t0 = std::chrono::steady_clock::now();
    try {
      c.load();
      ADD_FAILURE() << c.where << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), Errc::kParse) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.where), std::string::npos) << e.what();
    }
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(20)) << c.where;
  }
}

TEST(SceneFiles, AMeshPastTheMemoryCeilingFailsBeforeItIsParsed) {
  // The loaders count triangles first and check them against kMaxSceneMeshBytes.
  constexpr std::uintmax_t kPerTriangle = 60;
  EXPECT_NO_THROW(io::check_scene_memory("m.tris", io::kMaxSceneMeshBytes / kPerTriangle, 60));
  try {
    io::check_scene_memory("m.tris", io::kMaxSceneMeshBytes / kPerTriangle + 1, kPerTriangle);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), Errc::kParse);
    EXPECT_EQ(std::string(e.what()).rfind("m.tris: 71582789 triangles need ", 0), 0u) << e.what();
  }
  // More than a Mesh's 32-bit vertex indices reach, however small each triangle.
  EXPECT_THROW(io::check_scene_memory("m.tris", std::uintmax_t{1} << 31, 1), Error);
}

TEST(TrisLoad, SharedEdgesFixtureCoversEverySampleExactlyOnce) {
  const Scene s = load_tris(data_file("shared_edges.tris"));
  ASSERT_EQ(s.width, 64);
  ASSERT_EQ(s.height, 48);
  const Mesh& m = s.meshes[0];
  ASSERT_EQ(s.triangle_count(), 40u);
  // Count, per sample, the triangles that cover it, drawing each one alone in white.
  constexpr int kSamples = 4;
  std::vector<int> count(std::size_t{64} * 48 * kSamples, 0);
  Renderer renderer({1, Isa::kReference});
  for (std::size_t t = 0; t < s.triangle_count(); ++t) {
    Mesh one = m;
    one.positions.assign(m.positions.begin() + 3 * t, m.positions.begin() + 3 * t + 3);
    one.colors.assign(3, Rgba8{255, 255, 255, 255});
    const std::vector<Draw> draws{one.draw()};
    RenderTarget target(64, 48, kSamples, {.keep_sample_depth = false, .keep_sample_color = true});
    target.set_clear({0, 0, 0, 255});
    renderer.render(Frame{draws}, target);
    for (std::size_t i = 0; i < count.size(); ++i) count[i] += target.sample_color()[i].r == 255;
  }
  EXPECT_EQ(*std::min_element(count.begin(), count.end()), 1);
  EXPECT_EQ(*std::max_element(count.begin(), count.end()), 1);
  // The per-vertex-colour cell interpolates: more than three distinct colours there.
  const RenderTarget whole = render(s);
  std::vector<std::uint32_t> corner;
  for (int y = 40; y < 48; ++y)
    for (int x = 56; x < 64; ++x) {
      const Rgba8 c = whole.pixel(x, y);
      corner.push_back(std::uint32_t{c.r} << 16 | c.g << 8 | c.b);
    }
  std::sort(corner.begin(), corner.end());
  EXPECT_GT(std::unique(corner.begin(), corner.end()) - corner.begin(), 10);
}

// ---- save_tris ----

/// Every vertex colour of a mesh, expanded to one per vertex of its triangles.
std::vector<Rgba8> vertex_colors(const Mesh& m) {
  std::vector<Rgba8> out;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t v = m.indices.empty() ? 3 * t + k : m.indices[3 * t + k];
      switch (m.color_source) {
        case ColorSource::kConstant:
          out.push_back(m.color);
          break;
        case ColorSource::kPerTriangle:
          out.push_back(m.colors[t]);
          break;
        case ColorSource::kPerVertex:
          out.push_back(m.colors[v]);
          break;
      }
    }
  }
  return out;
}

TEST(TrisSave, ScreenScenesRoundTripBitForBit) {
  TempDir dir;
  for (const std::string name : {"random-large", "slivers", "fan", "star"}) {
    const Scene s = builtin_scene(name, 320, 180, 9);
    const fs::path p = dir / (name + ".tris");
    save_tris(s, p);
    const Scene r = load_tris(p);
    EXPECT_EQ(r.width, s.width);
    EXPECT_EQ(r.height, s.height);
    EXPECT_EQ(r.clear_color, s.clear_color);
    ASSERT_EQ(r.meshes.size(), 1u);
    EXPECT_EQ(r.meshes[0].positions, s.meshes[0].positions) << name;
    EXPECT_EQ(r.meshes[0].colors, vertex_colors(s.meshes[0])) << name;
    // Per-triangle colours became three equal vertex colours: the image is the same.
    if (name != "slivers") {
      EXPECT_EQ(render(r, 4).image_hash(), render(s, 4).image_hash()) << name;
    }
  }
  // Nothing but the files themselves is left in the folder.
  EXPECT_EQ(dir.files(), (std::vector<std::string>{"fan.tris", "random-large.tris", "slivers.tris",
                                                   "star.tris"}));
}

TEST(TrisSave, WritesFourColoursForFlatAndTwelveForShadedTriangles) {
  Scene s;
  s.width = 10;
  s.height = 20;
  s.clear_color = {1, 2, 3, 4};
  Mesh m;
  m.space = Space::kScreen;
  m.color_source = ColorSource::kPerVertex;
  m.positions = {{0.1f, 0.2f, 0.3f, 1}, {1e-7f, -3.5f, 0, 1}, {1e30f, 7, 1, 1},
                 {0, 0, 0, 1},          {1, 0, 0, 1},         {0, 1, 0, 1}};
  m.colors = {{9, 9, 9, 9}, {9, 9, 9, 9}, {9, 9, 9, 9}, {1, 2, 3, 4}, {5, 6, 7, 8}, {1, 2, 3, 4}};
  s.meshes.push_back(m);
  TempDir dir;
  save_tris(s, dir / "t.tris");
  const std::string text = read_text(dir / "t.tris");
  std::vector<std::vector<std::string>> tris;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::vector<std::string> w{std::istream_iterator<std::string>(words), {}};
    if (w.empty()) continue;
    if (w[0] == "tri") tris.push_back(w);
    if (w[0] == "size") {
      EXPECT_EQ(line, "size 10 20");
    }
    if (w[0] == "clear") {
      EXPECT_EQ(w, (std::vector<std::string>{"clear", "1", "2", "3", "4"}));
    }
  }
  ASSERT_EQ(tris.size(), 2u);
  EXPECT_EQ(tris[0].size(), 1u + 9 + 4);
  EXPECT_EQ(tris[1].size(), 1u + 9 + 12);
  // Shortest round-trip text: 0.1f is written "0.1", not 0.10000000149011612.
  EXPECT_EQ(tris[0][1], "0.1");
  // Read back, x and y within the guard band come snapped to 1/256 px (0.1 is 25.6 steps, 0.2 is
  // 51.2, 1e-7 is 0); 1e30 lies past it and z is never snapped.
  const Scene r = parse_tris(text);
  const std::vector<glm::vec4> snapped{{26 / 256.0f, 51 / 256.0f, 0.3f, 1},
                                       {0, -3.5f, 0, 1},
                                       {1e30f, 7, 1, 1},
                                       {0, 0, 0, 1},
                                       {1, 0, 0, 1},
                                       {0, 1, 0, 1}};
  EXPECT_EQ(r.meshes[0].positions, snapped);
  EXPECT_EQ(r.meshes[0].colors, m.colors);
}

TEST(TrisSave, ClipSpaceIsProjectedWithTheViewportTransform) {
  Scene s;
  s.width = 100;
  s.height = 50;
  Mesh m;
  m.space = Space::kClip;
  m.color_source = ColorSource::kConstant;
  m.color = {7, 8, 9, 10};
  // Worked by hand: x_px = (x/w + 1) * 50, y_px = (1 - y/w) * 25, z = z/w.
  m.positions = {{0, 0, 0.5f, 1},  // -> (50, 25, 0.5)
                 {1, -1, 1, 2},    // -> (75, 37.5, 0.5)
                 {-4, 4, 0, 4},    // -> (0, 0, 0)
                 // Skipped: a vertex behind the eye (w < 0)...
                 {0, 0, 0.5f, 1},
                 {1, 0, 0.5f, 1},
                 {0, 0, 0.5f, -1},
                 // ...or before the near plane (z < 0)...
                 {0, 0, 0.5f, 1},
                 {1, 0, 0.5f, 1},
                 {0, 1, -0.1f, 1},
                 // ...or with a non-finite coordinate.
                 {0, 0, 0.5f, 1},
                 {1, 0, 0.5f, 1},
                 {0, std::numeric_limits<float>::quiet_NaN(), 0.5f, 1}};
  s.meshes.push_back(m);
  TempDir dir;
  save_tris(s, dir / "c.tris");
  const Scene r = load_tris(dir / "c.tris");
  ASSERT_EQ(r.triangle_count(), 1u);
  const std::vector<glm::vec4> expected{{50, 25, 0.5f, 1}, {75, 37.5f, 0.5f, 1}, {0, 0, 0, 1}};
  EXPECT_EQ(r.meshes[0].positions, expected);
  EXPECT_EQ(r.meshes[0].colors, std::vector<Rgba8>(3, Rgba8{7, 8, 9, 10}));
}

// A clip-space mesh, exported and read back, draws the same image bit for bit: the export writes
// each projected coordinate as the double the front end computes, and the loader snaps that
// double, ties to even, as the front end does. With w other than a power of two most projected
// coordinates are not floats, and some lie within a float rounding of a tie. Flat colours:
// per-vertex colour is interpolated with perspective in clip space and linearly in a .tris file.
TEST(TrisSave, ClipSpaceMeshRoundTripsBitForBit) {
  constexpr int kTriangles = 20000;
  Scene s;
  s.width = 96;
  s.height = 64;
  Mesh m;
  m.space = Space::kClip;
  m.color_source = ColorSource::kPerTriangle;
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> ndc(-1.1f, 1.1f), zdist(0.05f, 0.95f), w(0.3f, 3.0f);
  for (int t = 0; t < kTriangles; ++t) {
    const float cx = ndc(rng), cy = ndc(rng);
    for (int k = 0; k < 3; ++k) {
      const float x = cx + ndc(rng) * 0.05f, y = cy + ndc(rng) * 0.05f, wk = w(rng);
      m.positions.emplace_back(x * wk, y * wk, zdist(rng) * wk, wk);
    }
    m.colors.push_back({static_cast<std::uint8_t>(t), static_cast<std::uint8_t>(t >> 8), 90, 255});
  }
  s.meshes.push_back(m);
  TempDir dir;
  save_tris(s, dir / "m.tris");
  const Scene r = load_tris(dir / "m.tris");
  for (const int samples : {1, 4}) {
    const RenderTarget a = render(s, samples, {.keep_sample_depth = true}),
                       b = render(r, samples, {.keep_sample_depth = true});
    EXPECT_EQ(a.image_hash(), b.image_hash()) << samples;
    EXPECT_TRUE(std::ranges::equal(a.sample_depth(), b.sample_depth(), [](float x, float y) {
      return std::memcmp(&x, &y, sizeof x) == 0;
    })) << samples;
  }
}

TEST(TrisSave, CulledTrianglesAreSkipped) {
  // One triangle of each winding; on screen (y down) the first is clockwise.
  Scene s;
  s.width = s.height = 10;
  Mesh m;
  m.space = Space::kScreen;
  m.color_source = ColorSource::kConstant;
  m.positions = {{0, 0, 0, 1}, {10, 0, 0, 1}, {0, 10, 0, 1},
                 {0, 0, 0, 1}, {0, 10, 0, 1}, {10, 0, 0, 1}};
  s.meshes.push_back(m);
  TempDir dir;
  for (const CullMode cull : {CullMode::kNone, CullMode::kBack, CullMode::kFront}) {
    s.for_each_state([cull](DrawState& st) { st.cull = cull; });
    save_tris(s, dir / "w.tris");
    const Scene r = load_tris(dir / "w.tris");
    ASSERT_EQ(r.triangle_count(), cull == CullMode::kNone ? 2u : 1u);
    if (cull == CullMode::kNone) continue;
    // Counter-clockwise on screen is the default front face: culling back keeps the second.
    const glm::vec4 second = r.meshes[0].positions[1];
    EXPECT_EQ(second, cull == CullMode::kBack ? glm::vec4(0, 10, 0, 1) : glm::vec4(10, 0, 0, 1));
  }
}

TEST(TrisSave, DefaultSceneSurvivesTheTripThroughScreenSpace) {
  // The clip-space showcase saved as .tris and read back draws nearly the same image: only
  // the perspective-correct colour interpolation (there is no w in a .tris) and the float
  // rounding of projected vertices differ.
  const Scene s = builtin_scene("default", 160, 90);
  TempDir dir;
  save_tris(s, dir / "d.tris");
  const Scene r = load_tris(dir / "d.tris");
  EXPECT_GT(r.triangle_count(), s.triangle_count() / 2);
  const RenderTarget a = render(s), b = render(r);
  int close = 0;
  for (std::size_t i = 0; i < a.color().size(); ++i) {
    const Rgba8 p = a.color()[i], q = b.color()[i];
    const int d = std::max({std::abs(p.r - q.r), std::abs(p.g - q.g), std::abs(p.b - q.b)});
    close += d <= 8;
  }
  EXPECT_GT(close, static_cast<int>(a.color().size() * 97 / 100));
}

TEST(TrisSave, BadSceneOrPathIsRejectedWithoutLeftovers) {
  TempDir dir;
  Scene s = builtin_scene("fan", 32, 32);
  try {
    save_tris(s, dir / "no" / "such" / "dir.tris");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), Errc::kIo);
  }
  // The target is a directory: rename fails, the temporary file is removed.
  fs::create_directory(dir / "taken.tris");
  EXPECT_THROW(save_tris(s, dir / "taken.tris"), Error);
  EXPECT_EQ(dir.files(), std::vector<std::string>{"taken.tris"});
  // An inconsistent mesh is rejected as render() would reject it.
  s.meshes[0].colors.pop_back();
  try {
    save_tris(s, dir / "x.tris");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), Errc::kInvalidDraw);
  }
  s = builtin_scene("fan", 32, 32);
  s.width = 0;
  EXPECT_THROW(save_tris(s, dir / "x.tris"), Error);
  EXPECT_EQ(dir.files(), std::vector<std::string>{"taken.tris"});
}

// The OBJ reader's short-decimal path gives exactly what std::from_chars gives, and declines
// what it cannot read exactly: more than 2^24 in its digits, or more than 10 after the point.
TEST(Numbers, ShortDecimalsReadAsFromCharsDoes) {
  const auto from_chars = [](const std::string& w) {
    float v = 0;
    const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
    EXPECT_TRUE(ec == std::errc() && end == w.data() + w.size()) << w;
    return v;
  };
  const auto bits = [](float v) {
    std::uint32_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
  };
  // m / 10^k written out with k digits after the point (k = 0: no point).
  const auto decimal = [](bool negative, std::uint32_t m, int k) {
    std::string d = std::to_string(m);
    if (k > 0) {
      if (d.size() <= static_cast<std::size_t>(k))
        d.insert(0, static_cast<std::size_t>(k) + 1 - d.size(), '0');
      d.insert(d.size() - static_cast<std::size_t>(k), 1, '.');
    }
    std::string out(negative ? 1 : 0, '-');
    return out.append(d);
  };
  std::mt19937 rng(20261203);
  constexpr std::uint32_t kMaxExact = 1u << 24;
  int read = 0;
  for (int i = 0; i < 200000; ++i) {
    const std::uint32_t m = i < 8 ? kMaxExact - 4 + static_cast<std::uint32_t>(i)
                                  : static_cast<std::uint32_t>(rng() % (kMaxExact + 2));
    const int k = static_cast<int>(rng() % 12);
    const std::string w = decimal(rng() % 2 == 0, m, k);
    float v = 0;
    const bool fast = io::read_short_decimal(w, v);
    EXPECT_EQ(fast, m <= kMaxExact && k <= 10) << w;
    if (fast) {
      ASSERT_EQ(bits(v), bits(from_chars(w))) << w;
      ++read;
    }
  }
  EXPECT_GT(read, 100000);
  // Forms it leaves to from_chars, and the edges it takes.
  float v = 0;
  for (const char* w : {"", "-", ".", "1e5", "+1", "1.2.3", "0x1", "nan", "inf", "1,5", "--1"})
    EXPECT_FALSE(io::read_short_decimal(w, v)) << w;
  ASSERT_TRUE(io::read_short_decimal("-0.000000", v));
  EXPECT_EQ(bits(v), bits(-0.0f));
  ASSERT_TRUE(io::read_short_decimal("16777216", v));
  EXPECT_EQ(v, 16777216.0f);
  EXPECT_FALSE(io::read_short_decimal("16777217", v));
  ASSERT_TRUE(io::read_short_decimal("0.0000000001", v));
  EXPECT_EQ(bits(v), bits(from_chars("0.0000000001")));
  EXPECT_FALSE(io::read_short_decimal("0.00000000001", v));
}

// ---- OBJ ----

TEST(Obj, CubeFixtureIsFannedFramedAndShaded) {
  const Scene s = load_obj(data_file("cube.obj"), 320, 180);
  EXPECT_EQ(s.name, "cube");
  EXPECT_EQ(s.width, 320);
  EXPECT_EQ(s.height, 180);
  ASSERT_EQ(s.meshes.size(), 1u);
  const Mesh& m = s.meshes[0];
  EXPECT_EQ(m.space, Space::kClip);
  EXPECT_EQ(m.color_source, ColorSource::kPerTriangle);
  EXPECT_EQ(s.triangle_count(), 12u);  // six quads, two triangles each
  // No normals in the file: each triangle has its face normal on three vertices of its own, in
  // order, so the mesh needs no indices.
  ASSERT_EQ(m.positions.size(), 36u);
  EXPECT_TRUE(m.indices.empty());
  EXPECT_TRUE(m.uvs.empty());
  // Framed: every vertex in the view volume, depth in [0, 1], and the cube is not tiny.
  float reach = 0;
  for (const glm::vec4& p : m.positions) {
    ASSERT_GT(p.w, 0);
    EXPECT_LE(std::fabs(p.x), p.w);
    EXPECT_LE(std::fabs(p.y), p.w);
    EXPECT_GT(p.z / p.w, 0.0f);
    EXPECT_LT(p.z / p.w, 1.0f);
    reach = std::max({reach, std::fabs(p.x / p.w), std::fabs(p.y / p.w)});
  }
  EXPECT_GT(reach, 0.4f);
  // Normal shading: one colour per triangle, the two triangles of a face agree; faces differ.
  ASSERT_EQ(m.colors.size(), 12u);
  std::vector<std::uint32_t> face_colors;
  for (std::size_t t = 0; t < 12; ++t) {
    const Rgba8 c = m.colors[t];
    face_colors.push_back(std::uint32_t{c.r} << 16 | c.g << 8 | c.b);
    if (t % 2 == 1) {
      EXPECT_EQ(m.colors[t], m.colors[t - 1]) << "face " << t / 2;
    }
  }
  std::sort(face_colors.begin(), face_colors.end());
  EXPECT_GE(std::unique(face_colors.begin(), face_colors.end()) - face_colors.begin(), 3);
  // Rendered: all 12 triangles pass setup, and the cube covers a fair part of the image.
  Renderer renderer({1, Isa::kReference});
  RenderTarget target(320, 180);
  target.set_clear(s.clear_color);
  const std::vector<Draw> draws = s.draws();
  const FrameStats st = renderer.render(Frame{draws}, target);
  EXPECT_EQ(st.triangles_drawn, 12u);
  const auto covered = std::count_if(target.color().begin(), target.color().end(),
                                     [&](Rgba8 c) { return c != s.clear_color; });
  EXPECT_GT(covered, 320 * 180 / 10);
}

TEST(Obj, VertexColoursAndRelativeIndicesAreUsed) {
  TempDir dir;
  write_text(dir / "c.obj",
             "# one coloured triangle, faces with relative indices and a texture index\n"
             "v 0 0 0 1 0 0\n"
             "v 1 0 0 0 1 0\n"
             "v 0 1 0 0 0 0.5\n"
             "vt 0 0\n"
             "f -3/1 -2/1 -1/1\n");
  const Scene s = load_obj(dir / "c.obj", 64, 64);
  ASSERT_EQ(s.triangle_count(), 1u);
  const std::vector<Rgba8> expected{{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 128, 255}};
  EXPECT_EQ(s.meshes[0].colors, expected);
}

TEST(Obj, NormalsAreTheFilesOrTheFacesAndLightTheSceneByDefault) {
  TempDir dir;
  // Two faces: one whose corners all name a normal (one of them not unit length), one without.
  write_text(dir / "n.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
             "vn 0 0 1\nvn 0 0.6 0.8\nvn 2 0 0\n"
             "f 1//1 2//2 3//3\n"
             "f 2 4 3\n");
  const Scene s = load_obj(dir / "n.obj", 64, 64);
  EXPECT_EQ(s.default_shading, Shading::kLambert);
  EXPECT_TRUE(s.has_normals());
  EXPECT_TRUE(s.warnings.empty());
  const std::vector<glm::vec3> want{{0, 0, 1}, {0, 0.6f, 0.8f}, {2, 0, 0},
                                    {0, 0, 1}, {0, 0, 1},       {0, 0, 1}};
  EXPECT_EQ(s.meshes[0].normals, want);  // the face normal: cross(b - a, c - a), unit here
  // The light is the flat shade's, in model space: unit length and two-sided.
  EXPECT_NEAR(glm::length(s.light.light_dir), 1.0f, 1e-6f);
  EXPECT_TRUE(s.light.two_sided);

  // A corner naming a normal that does not exist: its face uses the face normal, with a warning.
  write_text(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1 0 0\nf 1//1 2//1 3//4\n");
  const Scene b = load_obj(dir / "bad.obj", 64, 64);
  EXPECT_EQ(b.meshes[0].normals, std::vector<glm::vec3>(3, glm::vec3(0, 0, 1)));
  ASSERT_EQ(b.warnings.size(), 1u);
  EXPECT_NE(b.warnings[0].find("bad.obj:5: 1 face corner names a normal that does not exist"),
            std::string::npos)
      << b.warnings[0];

  // A file with vertex colours keeps them by default.
  write_text(dir / "c.obj", "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n");
  EXPECT_EQ(load_obj(dir / "c.obj", 64, 64).default_shading, Shading::kFlat);
}

TEST(Obj, ShadingByNormalsDrawsThemPerPixel) {
  TempDir dir;
  // A quad facing the camera's general direction, every normal +z: the normal colour is the
  // same everywhere, 0.5 + 0.5 * (0, 0, 1).
  write_text(dir / "q.obj",
             "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n");
  const Scene s = load_obj(dir / "q.obj", 64, 64);
  for (const Isa isa : {Isa::kReference, Isa::kAuto}) {
    Renderer renderer({1, isa});
    RenderTarget target(64, 64);
    target.set_clear(s.clear_color);
    const std::vector<Draw> draws = s.draws(Shading::kNormals);
    ASSERT_EQ(draws.size(), 1u);
    EXPECT_EQ(draws[0].varyings.size(), 3u);
    renderer.render(Frame{draws}, target);
    EXPECT_EQ(target.pixel(32, 32), (Rgba8{128, 128, 255, 255}));
  }
  // Lit, the image differs from the flat one, and both are drawn.
  const auto image = [&](Shading shading) {
    Renderer renderer({1, Isa::kAuto});
    RenderTarget target(64, 64);
    const std::vector<Draw> draws = s.draws(shading);
    const FrameStats st = renderer.render(Frame{draws}, target);
    EXPECT_EQ(st.triangles_drawn, 2u);
    return target.image_hash();
  };
  EXPECT_NE(image(Shading::kLambert), image(Shading::kFlat));
  // A mesh without normals cannot be shaded by them.
  Mesh bare = s.meshes[0];
  bare.normals.clear();
  EXPECT_THROW(bare.draw(Shading::kLambert, s.light), Error);
  EXPECT_NO_THROW(bare.draw(Shading::kFlat, s.light));
}

// The same mesh without indices: every triangle's corners copied out, attributes too.
Mesh expanded(const Mesh& m) {
  Mesh out = m;
  out.indices.clear();
  out.positions.clear();
  out.normals.clear();
  out.uvs.clear();
  if (m.color_source == ColorSource::kPerVertex) out.colors.clear();
  for (const std::uint32_t i : m.indices) {
    out.positions.push_back(m.positions[i]);
    out.normals.push_back(m.normals[i]);
    if (!m.uvs.empty()) out.uvs.push_back(m.uvs[i]);
    if (m.color_source == ColorSource::kPerVertex) out.colors.push_back(m.colors[i]);
  }
  return out;
}

// An n x n grid of vertices on a bumpy sheet with a normal and a UV each, its quads as faces
// v/t/n, and `extra` appended.
std::string smooth_grid(int n, const std::string& extra = "") {
  std::string t;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      t += "v " + std::to_string(i) + " " + std::to_string(j) + " " +
           std::to_string((i * j) % 3 * 0.25) + "\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      t += "vn " + std::to_string(0.1 * i) + " " + std::to_string(0.1 * j) + " 1\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      t += "vt " + std::to_string(i / double(n - 1)) + " " + std::to_string(j / double(n - 1)) +
           "\n";
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i + 1;
      t += "f";
      for (const int v : {a, a + 1, a + n + 1, a + n})
        t.append(" ")
            .append(std::to_string(v))
            .append("/")
            .append(std::to_string(v))
            .append("/")
            .append(std::to_string(v));
      t += "\n";
    }
  return t + extra;
}

TEST(Obj, SmoothMeshesAreIndexedOneVertexPerDistinctCorner) {
  TempDir dir;
  constexpr int kN = 12;
  write_text(dir / "g.obj", smooth_grid(kN));
  const Scene s = load_obj(dir / "g.obj", 96, 64);
  ASSERT_EQ(s.meshes.size(), 1u);
  const Mesh& m = s.meshes[0];
  EXPECT_TRUE(s.warnings.empty());
  EXPECT_EQ(s.triangle_count(), 2u * (kN - 1) * (kN - 1));
  // Every file vertex is one mesh vertex: its corners all name the same normal and UV.
  EXPECT_EQ(m.positions.size(), std::size_t{kN * kN});
  EXPECT_EQ(m.indices.size(), 6u * (kN - 1) * (kN - 1));
  EXPECT_EQ(m.normals.size(), m.positions.size());
  ASSERT_EQ(m.uvs.size(), m.positions.size());
  EXPECT_EQ(m.color_source, ColorSource::kPerTriangle);
  EXPECT_EQ(m.colors.size(), s.triangle_count());
  // The first face's corners, in file order: vertices 1, 2, 2 + n of the file.
  EXPECT_EQ(m.uvs[m.indices[0]], glm::vec2(0, 0));
  EXPECT_NEAR(m.uvs[m.indices[1]].x, 1.0 / (kN - 1), 1e-6);  // printed with six decimals
  EXPECT_EQ(m.uvs[m.indices[1]].y, 0.0f);
  EXPECT_EQ(m.normals[m.indices[1]], glm::vec3(0.1f, 0, 1));

  // Drawn indexed (through the vertex stage where it applies) or expanded, lit or by UV, the
  // image is the same on every path.
  const Mesh flat = expanded(m);
  for (const Shading shading : {Shading::kLambert, Shading::kUv, Shading::kFlat})
    for (const Isa isa : {Isa::kReference, Isa::kAuto}) {
      std::uint64_t hashes[2];
      FrameStats stats[2];
      for (int k = 0; k < 2; ++k) {
        Renderer renderer({2, isa});
        RenderTarget target(96, 64, 4);
        target.set_clear(s.clear_color, s.clear_depth);
        const Draw d = (k == 0 ? m : flat).draw(shading, s.light);
        stats[k] = renderer.render(Frame{{&d, 1}}, target);
        hashes[k] = target.image_hash();
      }
      EXPECT_EQ(hashes[0], hashes[1]) << int(shading) << " " << int(isa);
      EXPECT_GT(stats[0].samples_written, 1000u);
      EXPECT_EQ(stats[0].samples_written, stats[1].samples_written);
    }

  // A position whose corners name two normals is two vertices; a face without normals has its
  // face normal on three of its own, and corners without UVs leave the mesh without them.
  write_text(dir / "mixed.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nvn 0 1 0\nvt 0 0\n"
             "f 1//1 2//1 3//1\nf 2//2 4//2 3//1\nf 1 3/1 4\n");
  const Scene mixed = load_obj(dir / "mixed.obj", 64, 64);
  const Mesh& x = mixed.meshes[0];
  EXPECT_EQ(x.indices, (std::vector<std::uint32_t>{0, 1, 2, 3, 4, 2, 5, 6, 7}));
  ASSERT_EQ(x.positions.size(), 8u);
  EXPECT_EQ(x.positions[3], x.positions[1]);  // file vertex 2, with normal 1 and with normal 2
  EXPECT_EQ(x.normals[1], glm::vec3(0, 0, 1));
  EXPECT_EQ(x.normals[3], glm::vec3(0, 1, 0));
  EXPECT_TRUE(x.uvs.empty());
  // The face normal cross(b - a, c - a) of (0,0,0), (0,1,0), (1,1,0).
  EXPECT_EQ(x.normals[5], glm::vec3(0, 0, -1));
  EXPECT_EQ(x.normals[7], glm::vec3(0, 0, -1));
}

TEST(Obj, LargePolygonsCommentsAndOtherStatementsAreRead) {
  TempDir dir;
  // A 300-gon (a regular polygon, fanned into 298 triangles), with comments and statements the
  // loader ignores.
  std::string t = "# a polygon\no poly\ng group\ns 1\nmtllib none.mtl\nusemtl none\n";
  constexpr int kSides = 300;
  for (int i = 0; i < kSides; ++i) {
    const double a = 2 * 3.14159265358979 * i / kSides;
    t += "v " + std::to_string(std::cos(a)) + " " + std::to_string(std::sin(a)) + " 0  # corner\n";
  }
  t += "f";
  for (int i = 1; i <= kSides; ++i) t.append("\t").append(std::to_string(i));
  write_text(dir / "p.obj", t + "\r\n");
  const Scene s = load_obj(dir / "p.obj", 64, 64);
  EXPECT_EQ(s.triangle_count(), std::size_t{kSides - 2});
  EXPECT_TRUE(s.warnings.empty());
  Renderer renderer({1, Isa::kReference});
  RenderTarget target(64, 64);
  const std::vector<Draw> draws = s.draws(Shading::kFlat);
  const FrameStats stats = renderer.render(Frame{draws}, target);
  EXPECT_EQ(stats.triangles_in, std::size_t{kSides - 2});
  EXPECT_GT(stats.samples_written, 64u * 64u / 3);  // the disc, less its thinnest fan slices
}

TEST(Obj, UvsAreShownByTheUvShading) {
  TempDir dir;
  // A quad facing the camera's general direction with u across and v up.
  write_text(dir / "q.obj",
             "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
             "f 1/1 2/2 3/3 4/4\n");
  const Scene s = load_obj(dir / "q.obj", 64, 64);
  ASSERT_TRUE(s.has_uvs());
  EXPECT_EQ(s.meshes[0].uvs.size(), s.meshes[0].positions.size());
  for (const Isa isa : {Isa::kReference, Isa::kAuto}) {
    Renderer renderer({1, isa});
    RenderTarget target(64, 64);
    target.set_clear(s.clear_color);
    const std::vector<Draw> draws = s.draws(Shading::kUv);
    ASSERT_EQ(draws[0].varyings.size(), 2u);
    renderer.render(Frame{draws}, target);
    // The centre of the quad is u = v = 0.5; blue is 0 everywhere on it.
    const Rgba8 c = target.pixel(32, 32);
    EXPECT_NEAR(c.r, 128, 24);
    EXPECT_NEAR(c.g, 128, 24);
    EXPECT_EQ(c.b, 0);
  }
  // A corner naming a texture coordinate that does not exist: no UVs, with a warning.
  write_text(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/2\n");
  const Scene b = load_obj(dir / "bad.obj", 64, 64);
  EXPECT_FALSE(b.has_uvs());
  ASSERT_EQ(b.warnings.size(), 1u);
  EXPECT_NE(b.warnings[0].find("bad.obj:5: 1 face corner names a texture coordinate"),
            std::string::npos)
      << b.warnings[0];
  EXPECT_THROW(b.meshes[0].draw(Shading::kUv, b.light), Error);
}

TEST(Obj, ErrorsNameTheFileAndLine) {
  TempDir dir;
  struct Case {
    const char* what;
    std::string text;
    Errc code;
    std::string starts;  ///< the message begins with the path and this
  };
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const std::vector<Case> cases{
      {"index beyond the vertices", tri + "f 1 2 3\nf 1 2 9\n", Errc::kParse, ":5: "},
      {"relative index before the first vertex", tri + "f -1 -2 -4\n", Errc::kParse, ":4: "},
      {"index zero", tri + "f 0 1 2\n", Errc::kParse, ":4: "},
      {"garbage index", tri + "f a b c\n", Errc::kParse, ":4: "},
      {"garbage coordinate", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n", Errc::kParse, ":2: "},
      {"every face uses a non-finite vertex", "v 0 0 0\nv 1 0 0\nv 0 1e999 0\nf 1 2 3\n",
       Errc::kParse, ": every face uses a vertex that is not finite"},
      {"non-finite w", "v 0 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", Errc::kParse, ":1: "},
      {"non-finite colour", "v 0 0 0\nv 1 0 0 0 inf 0\nv 0 1 0\nf 1 2 3\n", Errc::kParse, ":2: "},
      {"vertex with two values", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", Errc::kParse, ":1: "},
      {"no faces", tri, Errc::kParse, ": "},
      {"only a two-vertex face", tri + "f 1 2\n", Errc::kParse, ": "},
      {"empty file", "", Errc::kParse, ": "},
      {"a vertex with five values", "v 0 0 0 1 1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", Errc::kParse,
       ":1: a vertex needs 3, 4, 6 or 7 values"},
      {"a vertex with eight values", tri + "v 0 0 0 1 1 1 1 1\nf 1 2 3\n", Errc::kParse,
       ":4: a vertex has at most 7 values"},
      {"a normal with two values", tri + "vn 0 1\nf 1//1 2//1 3//1\n", Errc::kParse, ":4: "},
      {"a malformed normal", tri + "vn 0 1 x\n" + "f 1 2 3\n", Errc::kParse, ":4: "},
      {"a texture coordinate with four values", tri + "vt 0 0 0 0\nf 1/1 2/1 3/1\n", Errc::kParse,
       ":4: "},
      {"a corner with an empty normal", tri + "f 1// 2 3\n", Errc::kParse, ":4: "},
      {"a relative normal before the first", tri + "vn 0 0 1\nf 1//-2 2//1 3//1\n", Errc::kParse,
       ":5: "},
  };
  for (const Case& c : cases) {
    const fs::path p = dir / "bad.obj";
    write_text(p, c.text);
    try {
      load_obj(p);
      ADD_FAILURE() << c.what << ": accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), c.code) << c.what;
      EXPECT_EQ(std::string(e.what()).rfind(p.string() + c.starts, 0), 0u)
          << c.what << ": " << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << c.what;
    }
  }
  try {
    load_obj(dir / "missing.obj");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), Errc::kIo);
    EXPECT_NE(std::string(e.what()).find("missing.obj"), std::string::npos);
  }
  EXPECT_THROW(load_obj(data_file("cube.obj"), 0, 10), Error);
}

// A vertex whose position is nan, inf or past float's range culls the triangles that use it, as
// the same draw through the API does (FrameStats::triangles_nonfinite), and nothing else: the
// file renders bit for bit as the file without those faces, which also frames the same.
TEST(Obj, NonFiniteVerticesCullTheirTrianglesAsADrawDoes) {
  TempDir dir;
  // A 5 x 5 grid of vertices on a bumpy sheet (quads fanned to two triangles each), then four
  // bad vertices: three used by faces, one unused.
  std::string verts;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 5; ++i)
      verts += "v " + std::to_string(i) + " " + std::to_string(j) + " " +
               std::to_string((i * j) % 3 * 0.25) + "\n";
  std::string faces;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const int a = j * 5 + i + 1;
      faces += "f " + std::to_string(a) + " " + std::to_string(a + 1) + " " +
               std::to_string(a + 6) + " " + std::to_string(a + 5) + "\n";
    }
  const std::string bad_faces = "f 1 2 26\nf 27 3 4\nf 5 28 10\n";
  const std::string bad = "v nan 0 0\nv 0 -inf 1\nv 1e39 2 0\nv nan nan nan\n";
  const std::string good = "v 0 0 0\nv 0 0 0\nv 0 0 0\nv 0 0 0\n";
  write_text(dir / "with.obj", verts + bad + faces + bad_faces);
  write_text(dir / "without.obj", verts + good + faces);
  const Scene with = load_obj(dir / "with.obj", 96, 64);
  const Scene without = load_obj(dir / "without.obj", 96, 64);
  ASSERT_EQ(with.warnings.size(), 1u);
  EXPECT_EQ(with.warnings[0].rfind((dir / "with.obj").string() + ":26: 4 vertices have", 0), 0u)
      << with.warnings[0];
  EXPECT_NE(with.warnings[0].find("; 3 of 35 triangles use one"), std::string::npos)
      << with.warnings[0];
  EXPECT_TRUE(without.warnings.empty());
  EXPECT_EQ(with.camera.view_projection, without.camera.view_projection);

  auto render = [](const Scene& s, FrameStats& stats) {
    RenderTarget t(s.width, s.height, 4);
    t.set_clear(s.clear_color, s.clear_depth);
    const std::vector<Draw> draws = s.draws();
    Frame f;
    f.draws = draws;
    Renderer r(RendererOptions{2});
    stats = r.render(f, t);
    return std::vector<Rgba8>(t.color().begin(), t.color().end());
  };
  FrameStats a, b;
  const std::vector<Rgba8> image_with = render(with, a), image_without = render(without, b);
  EXPECT_EQ(a.triangles_in, b.triangles_in + 3);
  EXPECT_EQ(a.triangles_nonfinite, 3u);
  EXPECT_EQ(b.triangles_nonfinite, 0u);
  EXPECT_GT(b.samples_written, 1000u);
  EXPECT_EQ(a.samples_written, b.samples_written);
  EXPECT_TRUE(image_with == image_without);
}

// ---- images ----

/// A small target with a different colour in every pixel (and alpha), written directly.
RenderTarget pattern_target(int w, int h) {
  RenderTarget t(w, h);
  auto& px = t.color_storage();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      px[static_cast<std::size_t>(y) * w + x] = {
          static_cast<std::uint8_t>(x * 40), static_cast<std::uint8_t>(y * 60),
          static_cast<std::uint8_t>(x * y + 7), static_cast<std::uint8_t>(255 - x - y)};
  return t;
}

/// Reads an image with stb_image; `channels` 4 for RGBA, 3 for RGB.
std::vector<std::uint8_t> read_image(const fs::path& p, int channels, int& w, int& h) {
  int n = 0;
  unsigned char* data = stbi_load(p.c_str(), &w, &h, &n, channels);
  if (data == nullptr) return {};
  std::vector<std::uint8_t> out(data, data + static_cast<std::size_t>(w) * h * channels);
  stbi_image_free(data);
  return out;
}

TEST(Image, PngAndPpmReadBackExactly) {
  TempDir dir;
  const RenderTarget t = pattern_target(5, 3);
  write_image(t, dir / "a.png");
  write_image(t, dir / "b.PPM");  // the extension is case-insensitive
  int w = 0, h = 0;
  const std::vector<std::uint8_t> png = read_image(dir / "a.png", 4, w, h);
  ASSERT_EQ(w, 5);
  ASSERT_EQ(h, 3);
  const std::vector<std::uint8_t> ppm = read_image(dir / "b.PPM", 3, w, h);
  ASSERT_EQ(w, 5);
  ASSERT_EQ(h, 3);
  for (std::size_t i = 0; i < t.color().size(); ++i) {
    const Rgba8 c = t.color()[i];
    EXPECT_EQ(png[4 * i + 0], c.r);
    EXPECT_EQ(png[4 * i + 1], c.g);
    EXPECT_EQ(png[4 * i + 2], c.b);
    EXPECT_EQ(png[4 * i + 3], c.a);  // PNG keeps alpha
    EXPECT_EQ(ppm[3 * i + 0], c.r);
    EXPECT_EQ(ppm[3 * i + 1], c.g);
    EXPECT_EQ(ppm[3 * i + 2], c.b);
  }
  // The PPM is binary P6: a text header, then exactly width * height * 3 bytes.
  const std::string bytes = read_text(dir / "b.PPM");
  const std::string header = "P6\n5 3\n255\n";
  EXPECT_EQ(bytes.substr(0, header.size()), header);
  EXPECT_EQ(bytes.size(), header.size() + 5 * 3 * 3);
  EXPECT_EQ(dir.files(), (std::vector<std::string>{"a.png", "b.PPM"}));
}

TEST(Image, RenderedSceneWritesAndOverwrites) {
  TempDir dir;
  const RenderTarget a = render(builtin_scene("fan", 64, 48));
  write_image(a, dir / "f.png");
  const RenderTarget b = render(builtin_scene("star", 64, 48));
  write_image(b, dir / "f.png");
  int w = 0, h = 0;
  const std::vector<std::uint8_t> png = read_image(dir / "f.png", 4, w, h);
  ASSERT_EQ(png.size(), b.color().size() * 4);
  EXPECT_TRUE(
      std::equal(png.begin(), png.end(), reinterpret_cast<const std::uint8_t*>(b.color().data())));
}

TEST(Image, BadExtensionOrPathFailsWithoutLeavingFiles) {
  TempDir dir;
  const RenderTarget t = pattern_target(2, 2);
  for (const char* name : {"x.jpg", "x", "x.png.txt", ".png"}) {
    try {
      write_image(t, dir / name);
      ADD_FAILURE() << name << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), Errc::kInvalidArgument) << name;
    }
  }
  try {
    write_image(t, dir / "missing" / "x.png");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), Errc::kIo);
    EXPECT_NE(std::string(e.what()).find("x.png"), std::string::npos);
  }
  // A directory where the image should go: the write fails and leaves no temporary behind.
  fs::create_directory(dir / "d.ppm");
  try {
    write_image(t, dir / "d.ppm");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), Errc::kIo);
  }
  EXPECT_EQ(dir.files(), std::vector<std::string>{"d.ppm"});
}

}  // namespace
}  // namespace mosaic
