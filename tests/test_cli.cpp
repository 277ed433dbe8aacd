// test_cli.cpp — the `mosaic` command-line tool, run as a separate process.
//
// Every test runs the built binary (MOSAIC_CLI_PATH) in a fresh temporary directory and checks
// its exit status, its stderr line, the JSON of --stats and the images it writes. Sizes stay
// small (the reference rasterizer may be the one running).
#include <gtest/gtest.h>
#include <stb/stb_image.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "mosaic/renderer.hpp"
#include "mosaic/scene.hpp"

namespace {

namespace fs = std::filesystem;

const std::string kCli = MOSAIC_CLI_PATH;
const std::string kData = MOSAIC_TEST_DATA_DIR;

// The size of tests/data/cli_quad.tris and cli_two_quads.tris.
constexpr int kQuadWidth = 40;
constexpr int kQuadHeight = 30;

std::string quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'')
      out += "'\\''";
    else
      out += c;
  }
  return out + "'";
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

struct CliRun {
  int status = -1;  // exit status; -1 if the process did not exit normally (e.g. crashed)
  std::string out;  // stdout
  std::string err;  // stderr
};

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;
  std::array<std::uint8_t, 4> pixel(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 4;
    return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
  }
};

// FNV-1a over width, height (little-endian 32-bit) and RGBA pixels: the hash that
// RenderTarget::image_hash() documents, recomputed here from the written PNG.
std::uint64_t fnv1a(const Image& image) {
  std::uint64_t h = 14695981039346656037ull;
  auto mix = [&h](std::uint8_t byte) {
    h ^= byte;
    h *= 1099511628211ull;
  };
  for (int shift = 0; shift < 32; shift += 8) mix(static_cast<std::uint8_t>(image.width >> shift));
  for (int shift = 0; shift < 32; shift += 8) mix(static_cast<std::uint8_t>(image.height >> shift));
  for (std::uint8_t byte : image.rgba) mix(byte);
  return h;
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device rd;
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() /
            ("mosaic_cli_" + std::string(info->name()) + "_" + std::to_string(rd()));
    work_ = root_ / "work";
    fs::create_directories(work_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }

  // Runs `mosaic <args>` in work_; args are passed to the shell as written.
  CliRun run(const std::string& args) const {
    const fs::path out = root_ / "stdout.txt";
    const fs::path err = root_ / "stderr.txt";
    const std::string command = "cd " + quote(work_.string()) + " && " + quote(kCli) + " " + args +
                                " > " + quote(out.string()) + " 2> " + quote(err.string());
    const int raw = std::system(command.c_str());
    CliRun r;
    r.status = (raw != -1 && WIFEXITED(raw)) ? WEXITSTATUS(raw) : -1;
    r.out = read_file(out);
    r.err = read_file(err);
    return r;
  }

  // Runs `mosaic <args>`, expects success and returns the --stats JSON it printed.
  nlohmann::json stats(const std::string& args) const {
    const CliRun r = run(args + " --stats");
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    nlohmann::json j = nlohmann::json::parse(r.out, nullptr, /*allow_exceptions=*/false);
    EXPECT_TRUE(j.is_object()) << "not one JSON object: " << r.out;
    // An empty object on failure: operator[] then yields nulls and the checks fail cleanly.
    return j.is_object() ? j : nlohmann::json::object();
  }

  Image load_png(const std::string& name) const {
    Image image;
    int channels = 0;
    const std::string path = (work_ / name).string();
    stbi_uc* data = stbi_load(path.c_str(), &image.width, &image.height, &channels, 4);
    if (data == nullptr) {
      ADD_FAILURE() << "cannot read " << path << ": " << stbi_failure_reason();
      return {};
    }
    image.rgba.assign(data, data + static_cast<std::size_t>(image.width) * image.height * 4);
    stbi_image_free(data);
    return image;
  }

  std::vector<std::string> files_in_work() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(work_))
      names.push_back(entry.path().filename().string());
    return names;
  }

  fs::path root_, work_;
};

std::string data(const std::string& name) { return quote(kData + "/" + name); }

int count_lines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

// A failed run: the expected status, nothing on stdout, one `mosaic: ` line on stderr.
void expect_one_line_error(const CliRun& r, int status, const std::string& args) {
  EXPECT_EQ(r.status, status) << args << "\nstderr: " << r.err;
  EXPECT_EQ(r.out, "") << args;
  EXPECT_EQ(count_lines(r.err), 1) << args << "\nstderr: " << r.err;
  EXPECT_EQ(r.err.rfind("mosaic: ", 0), 0u) << args << "\nstderr: " << r.err;
  EXPECT_EQ(r.err.find("terminate"), std::string::npos) << r.err;
}

TEST_F(CliTest, RenderWritesPngOfRequestedSize) {
  const CliRun r = run("render default --size 160x90 --out x.png");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("default 160x90 4x: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("-> x.png"), std::string::npos) << r.err;
  const Image image = load_png("x.png");
  EXPECT_EQ(image.width, 160);
  EXPECT_EQ(image.height, 90);
  // The default scene draws something: not every pixel is the clear colour.
  bool varied = false;
  for (int y = 0; y < image.height && !varied; ++y)
    for (int x = 0; x < image.width && !varied; ++x)
      varied = image.pixel(x, y) != image.pixel(0, 0);
  EXPECT_TRUE(varied);
}

TEST_F(CliTest, DefaultOutputIsSceneNamePngAndNoOutWritesNothing) {
  ASSERT_EQ(run("render star --size 32x18").status, 0);
  EXPECT_EQ(files_in_work(), std::vector<std::string>{"star.png"});
  EXPECT_EQ(load_png("star.png").width, 32);
  fs::remove(work_ / "star.png");

  ASSERT_EQ(run("render star --size 32x18 --no-out").status, 0);
  ASSERT_EQ(run("render star --size 32x18 --out -").status, 0);
  EXPECT_TRUE(files_in_work().empty());

  // A file scene is named by its file name without directory and extension.
  ASSERT_EQ(run("render " + data("cli_quad.tris")).status, 0);
  EXPECT_EQ(files_in_work(), std::vector<std::string>{"cli_quad.png"});
}

TEST_F(CliTest, WritesBinaryPpm) {
  ASSERT_EQ(run("render star --size 32x18 --out y.ppm").status, 0);
  const std::string ppm = read_file(work_ / "y.ppm");
  ASSERT_GE(ppm.size(), 2u);
  EXPECT_EQ(ppm.substr(0, 2), "P6");
}

TEST_F(CliTest, StatsPrintsOneJsonObjectWithEveryField) {
  const CliRun r = run("render star --size 64x36 --stats --out s.png");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(count_lines(r.out), 1) << r.out;
  nlohmann::json j = nlohmann::json::parse(r.out, nullptr, /*allow_exceptions=*/false);
  ASSERT_TRUE(j.is_object()) << r.out;
  for (const char* key : {"scene",
                          "width",
                          "height",
                          "samples",
                          "depth_only",
                          "triangles_in",
                          "triangles_nonfinite",
                          "triangles_culled_face",
                          "triangles_degenerate",
                          "triangles_outside",
                          "triangles_clipped",
                          "triangles_no_sample",
                          "triangles_drawn",
                          "triangles_binned",
                          "blocks_hiz_rejected",
                          "blocks_hiz_accepted",
                          "samples_tested",
                          "samples_written",
                          "ms_median",
                          "ms_setup",
                          "ms_binning",
                          "ms_raster",
                          "ms_resolve",
                          "isa",
                          "threads",
                          "image_hash"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["scene"], "star");
  EXPECT_EQ(j["width"], 64);
  EXPECT_EQ(j["height"], 36);
  EXPECT_EQ(j["samples"], 4);
  EXPECT_GT(j["samples_written"].get<std::uint64_t>(), 0u);
  EXPECT_LE(j["samples_written"].get<std::uint64_t>(), j["samples_tested"].get<std::uint64_t>());
  EXPECT_GT(j["triangles_drawn"].get<std::uint64_t>(), 0u);
  EXPECT_GE(j["ms_median"].get<double>(), 0.0);
  EXPECT_TRUE(j["isa"].is_string());
  EXPECT_GE(j["threads"].get<int>(), 1);

  // image_hash is the FNV-1a of the image that was written, as 16 hex digits.
  const std::string hash = j["image_hash"];
  ASSERT_EQ(hash.size(), 16u);
  EXPECT_EQ(hash.find_first_not_of("0123456789abcdef"), std::string::npos) << hash;
  const Image image = load_png("s.png");
  EXPECT_EQ(std::stoull(hash, nullptr, 16), fnv1a(image));
}

TEST_F(CliTest, DepthOnlyWritesTheSameSamplesAndNoColour) {
  const nlohmann::json colour = stats("render star --size 64x36 --out c.png");
  const nlohmann::json depth = stats("render star --size 64x36 --depth-only --out d.png");
  EXPECT_EQ(depth["depth_only"], true);
  EXPECT_EQ(colour["depth_only"], false);
  EXPECT_EQ(depth["samples_written"], colour["samples_written"]);
  EXPECT_GT(depth["samples_written"].get<std::uint64_t>(), 0u);
  const Image c = load_png("c.png"), d = load_png("d.png");
  ASSERT_EQ(d.rgba.size(), c.rgba.size());
  EXPECT_NE(d.rgba, c.rgba);
  for (int y = 0; y < d.height; ++y)
    for (int x = 0; x < d.width; ++x) ASSERT_EQ(d.pixel(x, y), d.pixel(0, 0)) << x << "," << y;
}

TEST_F(CliTest, FullScreenPairWritesEverySampleExactlyOnce) {
  const std::string quad = data("cli_quad.tris");
  const std::uint64_t pixels = kQuadWidth * kQuadHeight;
  for (int samples : {1, 4, 8}) {
    nlohmann::json j =
        stats("render " + quad + " --no-out --depth-test off --msaa " + std::to_string(samples));
    EXPECT_EQ(j["width"], kQuadWidth);
    EXPECT_EQ(j["height"], kQuadHeight);
    EXPECT_EQ(j["triangles_in"], 2);
    EXPECT_EQ(j["triangles_drawn"], 2);
    EXPECT_EQ(j["samples_written"].get<std::uint64_t>(), pixels * samples) << samples;
  }
  // At 16x, sample 15 sits at (-7/16, -8/16) from the pixel centre: exactly on the image's top
  // edge in row 0, and sample 12, (-8/16, 0), exactly on its left edge in column 0. The D3D rule
  // keeps both (top and left edges are inside); the GL rule keeps the left edge and drops the
  // top one, so it loses one sample in each of the kQuadWidth pixels of row 0.
  nlohmann::json d3d = stats("render " + quad + " --no-out --msaa 16 --fill-rule d3d");
  EXPECT_EQ(d3d["samples_written"].get<std::uint64_t>(), pixels * 16);
  nlohmann::json gl = stats("render " + quad + " --no-out --msaa 16 --fill-rule gl");
  EXPECT_EQ(gl["samples_written"].get<std::uint64_t>(), pixels * 16 - kQuadWidth);
}

TEST_F(CliTest, DepthTestAndPainterApplyToEveryDraw) {
  const std::string quads = data("cli_two_quads.tris");
  const std::uint64_t one_layer = kQuadWidth * kQuadHeight * 4;
  struct Case {
    std::string flags;
    std::uint64_t samples_written;
    bool red;  // the near red pair shows (else the far blue one)
  };
  const std::vector<Case> cases = {
      {"", one_layer, true},  // default: less
      {"--depth-test less", one_layer, true},
      {"--depth-test less-equal", one_layer, true},
      {"--depth-test always", 2 * one_layer, false},
      {"--depth-test off", 2 * one_layer, false},
      // Reversed Z clears depth to 0: red (0.25 > 0) and then blue (0.75 > 0.25) both pass.
      {"--depth-test greater", 2 * one_layer, false},
      // Back to front: the far blue pair first, then the near red one over it.
      {"--painter", 2 * one_layer, true},
  };
  for (const Case& c : cases) {
    nlohmann::json j = stats("render " + quads + " --out q.png " + c.flags);
    EXPECT_EQ(j["samples_written"].get<std::uint64_t>(), c.samples_written) << c.flags;
    const Image image = load_png("q.png");
    ASSERT_EQ(image.width, kQuadWidth);
    const auto p = image.pixel(kQuadWidth / 2, kQuadHeight / 2);
    EXPECT_EQ(p[0], c.red ? 255 : 0) << c.flags;
    EXPECT_EQ(p[2], c.red ? 0 : 255) << c.flags;
  }
}

TEST_F(CliTest, CullAppliesToEveryDraw) {
  // Both triangles of cli_quad.tris wind clockwise on screen: back faces (front is CCW).
  const std::string quad = data("cli_quad.tris");
  nlohmann::json none = stats("render " + quad + " --no-out --cull none");
  EXPECT_EQ(none["triangles_culled_face"], 0);
  EXPECT_EQ(none["triangles_drawn"], 2);
  nlohmann::json back = stats("render " + quad + " --no-out --cull back");
  EXPECT_EQ(back["triangles_culled_face"], 2);
  EXPECT_EQ(back["triangles_drawn"], 0);
  EXPECT_EQ(back["samples_written"], 0);
  nlohmann::json front = stats("render " + quad + " --no-out --cull front");
  EXPECT_EQ(front["triangles_culled_face"], 0);
  EXPECT_EQ(front["triangles_drawn"], 2);
}

TEST_F(CliTest, RepeatReportsMedianOfAllRunsWithSameCounters) {
  const CliRun r = run("render fan --size 48x27 --no-out --repeat 3 --stats");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("median of 3"), std::string::npos) << r.err;
  nlohmann::json three = nlohmann::json::parse(r.out, nullptr, /*allow_exceptions=*/false);
  ASSERT_TRUE(three.is_object()) << r.out;
  nlohmann::json one = stats("render fan --size 48x27 --no-out");
  EXPECT_EQ(three["samples_written"], one["samples_written"]);
  EXPECT_EQ(three["image_hash"], one["image_hash"]);
}

TEST_F(CliTest, ThreadsAndIsaDoNotChangeTheImage) {
  const std::string scene = "render random-small --size 160x90 --no-out --seed 7";
  nlohmann::json reference = stats(scene + " --reference");
  EXPECT_EQ(reference["isa"], "reference");
  // Every ISA this build and CPU run is reachable by name and renders the same image.
  for (const mosaic::Isa isa : mosaic::available_isas()) {
    const std::string name = mosaic::to_string(isa);
    nlohmann::json j = stats(scene + " --isa " + name);
    EXPECT_EQ(j["isa"], name);
    EXPECT_EQ(j["image_hash"], reference["image_hash"]) << name;
  }
  // One that is not available is a runtime error (exit 1), not a crash.
  for (const mosaic::Isa isa : {mosaic::Isa::kSse41, mosaic::Isa::kAvx2, mosaic::Isa::kAvx512}) {
    const std::vector<mosaic::Isa> have = mosaic::available_isas();
    if (std::find(have.begin(), have.end(), isa) != have.end()) continue;
    const std::string args =
        "render star --size 16x9 --no-out --isa " + std::string(mosaic::to_string(isa));
    expect_one_line_error(run(args), 1, args);
  }
  // Every tile size, and the one the renderer picks (reported in the statistics): this small
  // image has two tiles of 128 px, fewer than kFewBusyTiles, so its frame is split into 32 px.
  EXPECT_EQ(stats(scene)["tile_size"], 32);
  EXPECT_EQ(stats("render random-small --size 1024x512 --no-out --seed 7")["tile_size"], 128);
  for (int size : {8, 16, 32, 64, 128}) {
    nlohmann::json j = stats(scene + " --tile-size " + std::to_string(size));
    EXPECT_EQ(j["tile_size"], size);
    EXPECT_EQ(j["image_hash"], reference["image_hash"]) << size;
  }
  nlohmann::json one = stats(scene + " --threads 1");
  nlohmann::json two = stats(scene + " --threads 2");
  EXPECT_EQ(one["image_hash"], reference["image_hash"]);
  EXPECT_EQ(two["image_hash"], reference["image_hash"]);
  EXPECT_EQ(two["samples_written"], reference["samples_written"]);
  // A different seed is a different scene.
  nlohmann::json other = stats("render random-small --size 160x90 --no-out --seed 8");
  EXPECT_NE(other["image_hash"], reference["image_hash"]);
}

TEST_F(CliTest, ScenesListsTheBuiltinNames) {
  const CliRun r = run("scenes");
  ASSERT_EQ(r.status, 0) << r.err;
  std::string expected;
  for (const std::string& name : mosaic::builtin_scene_names()) expected += name + "\n";
  EXPECT_EQ(r.out, expected);
}

TEST_F(CliTest, HelpExitsZero) {
  const CliRun r = run("render --help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("--msaa"), std::string::npos);
}

// Exporting a screen-space built-in and rendering the .tris reproduces it bit for bit.
TEST_F(CliTest, ExportedScreenSpaceScenesRenderIdentically) {
  for (const std::string scene : {"star", "fan", "slivers", "random-large"}) {
    const std::string size = " --size 160x90";
    nlohmann::json direct = stats("render " + scene + size + " --no-out");
    const CliRun e = run("export " + scene + size + " --out " + scene + ".tris");
    ASSERT_EQ(e.status, 0) << e.err;
    EXPECT_EQ(count_lines(e.err), 1) << e.err;
    nlohmann::json replay = stats("render " + scene + ".tris --no-out");
    EXPECT_EQ(replay["width"], 160);
    EXPECT_EQ(replay["height"], 90);
    EXPECT_EQ(replay["image_hash"], direct["image_hash"]) << scene;
    EXPECT_EQ(replay["samples_written"], direct["samples_written"]) << scene;
    EXPECT_EQ(replay["triangles_drawn"], direct["triangles_drawn"]) << scene;
  }
}

// The clip-space default scene exported to pixels keeps its coverage (save_tris projects exactly
// as the front end does) but not its pixels: per-vertex colour is interpolated with perspective in
// clip space and linearly in a .tris file, so only the counters are compared.
TEST_F(CliTest, ExportedClipSpaceSceneKeepsItsCoverage) {
  const std::string size = " --size 160x90";
  nlohmann::json direct = stats("render default" + size + " --no-out");
  const CliRun e = run("export default" + size + " --out d.tris");
  ASSERT_EQ(e.status, 0) << e.err;
  nlohmann::json replay = stats("render d.tris --no-out");
  EXPECT_GT(direct["samples_written"].get<std::uint64_t>(), 0u);
  EXPECT_EQ(replay["samples_written"], direct["samples_written"]);
  EXPECT_EQ(replay["samples_tested"], direct["samples_tested"]);
  EXPECT_EQ(replay["triangles_drawn"], direct["triangles_drawn"]);
}

TEST_F(CliTest, ShadeChoosesHowMeshesAreColoured) {
  const std::string obj = data("cli_tetra.obj") + " --size 64x48 --no-out";
  std::set<std::string> hashes;
  for (const char* shade : {"flat", "normals", "lambert"}) {
    nlohmann::json j = stats("render " + obj + " --shade " + shade);
    EXPECT_EQ(j["shade"], shade);
    EXPECT_EQ(j["triangles_drawn"], 4);
    hashes.insert(j["image_hash"].get<std::string>());
  }
  EXPECT_EQ(hashes.size(), 3u);
  // The knot has normals; a scene without them cannot be shaded by them (status 1, one line).
  EXPECT_EQ(stats("render knot-30px --size 64x48 --no-out --shade normals")["shade"], "normals");
  const CliRun r = run("render random-small --size 64x48 --no-out --shade lambert");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("has no vertex normals"), std::string::npos) << r.err;
  EXPECT_EQ(run("render knot --shade shiny --no-out").status, 2);
  // UVs: the tetrahedron's faces name none; a file whose faces do is shaded by them.
  const CliRun no_uv = run("render " + obj + " --shade uv");
  EXPECT_EQ(no_uv.status, 1);
  EXPECT_NE(no_uv.err.find("has no texture coordinates"), std::string::npos) << no_uv.err;
  std::ofstream(work_ / "uv.obj") << "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";
  nlohmann::json uv = stats("render uv.obj --size 64x48 --no-out --shade uv");
  EXPECT_EQ(uv["shade"], "uv");
  EXPECT_EQ(uv["triangles_drawn"], 2);
}

TEST_F(CliTest, ExportAndRenderObj) {
  nlohmann::json j = stats("render " + data("cli_tetra.obj") + " --size 64x48 --out t.png");
  EXPECT_EQ(j["scene"], "cli_tetra");
  EXPECT_EQ(j["shade"], "lambert");  // an OBJ without vertex colours is lit by default
  EXPECT_EQ(j["triangles_in"], 4);
  EXPECT_GT(j["samples_written"].get<std::uint64_t>(), 0u);
  EXPECT_EQ(load_png("t.png").width, 64);
  const CliRun e = run("export " + data("cli_tetra.obj") + " --size 64x48 --out t.tris");
  ASSERT_EQ(e.status, 0) << e.err;
  nlohmann::json replay = stats("render t.tris --no-out");
  EXPECT_EQ(replay["width"], 64);
  EXPECT_EQ(replay["height"], 48);
  EXPECT_GT(replay["samples_written"].get<std::uint64_t>(), 0u);
}

TEST_F(CliTest, UsageErrorsAreOneLineAndExitTwo) {
  const std::vector<std::string> cases = {
      "",  // no command
      "frobnicate",
      "render --bogus",
      "render --msaa 3",
      "render --msaa 0x4",
      "render --threads -1",
      "render --threads two",
      "render --size 0x5",
      "render --size 160x",
      "render --size 160x90x2",
      "render --size 99999x90",
      "render --repeat 0",
      "render --seed -1",
      "render --isa mmx",
      "render --reference --isa auto",
      "render --tile-size 24",
      "render --tile-size 256",
      "render --tile-size big",
      "render --depth-test sometimes",
      "render --fill-rule vulkan",
      "render --cull sideways",
      "render --out",
      "render --out x.jpg",
      "render --out x.png --no-out",
      "render no-such-scene",
      "render star fan",
      "render " + data("cli_quad.tris") + " --size 10x10",
      "render " + data("cli_quad.tris") + " --seed 3",
      "export star",
      "export --out x.tris",
      "export star --out x.png",
      "scenes extra",
  };
  for (const std::string& args : cases) {
    expect_one_line_error(run(args), 2, args);
    EXPECT_TRUE(files_in_work().empty()) << args;
  }
}

// Output that cannot be written is a failure: --stats JSON or the scene list sent to a full
// device exits 1 with an error line, where it once exited 0 with the output lost.
TEST_F(CliTest, StdoutThatCannotBeWrittenExitsOne) {
  for (const std::string args : {"render star --size 16x9 --no-out --stats", "scenes"}) {
    const fs::path err = root_ / "full-stderr.txt";
    const std::string command = quote(kCli) + " " + args + " > /dev/full 2> " + quote(err.string());
    const int raw = std::system(command.c_str());
    ASSERT_TRUE(raw != -1 && WIFEXITED(raw)) << args;
    EXPECT_EQ(WEXITSTATUS(raw), 1) << args;
    // The error is the last line (render prints its timing line first).
    const std::string text = read_file(err);
    const std::size_t at = text.find("mosaic: cannot write to standard output");
    ASSERT_NE(at, std::string::npos) << args << ": " << text;
    EXPECT_EQ(text.find('\n', at), text.size() - 1) << args << ": " << text;
  }
}

TEST_F(CliTest, StderrThatCannotBeWrittenExitsOne) {
  for (const std::string args : {"render star --size 16x9 --no-out",
                                 "export star --size 16x9 "
                                 "--out x.tris"}) {
    const std::string command = "cd " + quote(work_.string()) + " && " + quote(kCli) + " " + args +
                                " > /dev/null 2> /dev/full";
    const int raw = std::system(command.c_str());
    ASSERT_TRUE(raw != -1 && WIFEXITED(raw)) << args;
    EXPECT_EQ(WEXITSTATUS(raw), 1) << args;
  }
}

TEST_F(CliTest, RepeatIsBoundedAtOneHundredThousand) {
  expect_one_line_error(run("render star --size 16x9 --no-out --repeat 100001"), 2, "100001");
  EXPECT_EQ(run("render star --size 16x9 --no-out --repeat 3").status, 0);
}

TEST_F(CliTest, OutReplacesASymlinkAndLeavesItsTargetAlone) {
  std::ofstream(work_ / "target.png") << "keep";
  std::ofstream(work_ / "target.tris") << "keep";
  fs::create_symlink("target.png", work_ / "link.png");
  fs::create_symlink("target.tris", work_ / "link.tris");
  EXPECT_EQ(run("render star --size 16x9 --out link.png").status, 0);
  EXPECT_EQ(run("export star --size 16x9 --out link.tris").status, 0);
  for (const std::string name : {"link.png", "link.tris"}) {
    EXPECT_FALSE(fs::is_symlink(work_ / name)) << name;
    EXPECT_TRUE(fs::is_regular_file(work_ / name)) << name;
  }
  EXPECT_EQ(load_png("link.png").width, 16);
  EXPECT_EQ(read_file(work_ / "target.png"), "keep");
  EXPECT_EQ(read_file(work_ / "target.tris"), "keep");
}

TEST_F(CliTest, InputErrorsAreOneLineAndExitOne) {
  const std::vector<std::string> cases = {
      "render missing.tris",
      "render missing.obj",
      "render " + data("cli_bad_index.obj"),
      "render star --size 16x9 --out no/such/dir/x.png",
      "export missing.obj --out x.tris",
      "export star --size 16x9 --out no/such/dir/x.tris",
  };
  for (const std::string& args : cases) {
    expect_one_line_error(run(args), 1, args);
    EXPECT_TRUE(files_in_work().empty()) << args;
  }
  // A scene file whose name says neither format is bad input, not a malformed command line; the
  // extension is read in any case.
  fs::copy_file(kData + "/cli_tetra.obj", work_ / "model.txt");
  fs::copy_file(kData + "/cli_tetra.obj", work_ / "MODEL.OBJ");
  const CliRun txt = run("render model.txt --no-out");
  expect_one_line_error(txt, 1, "model.txt");
  EXPECT_NE(txt.err.find("must be named *.tris or *.obj"), std::string::npos) << txt.err;
  EXPECT_EQ(run("render MODEL.OBJ --size 32x24 --no-out").status, 0);
  fs::remove(work_ / "model.txt");
  fs::remove(work_ / "MODEL.OBJ");
  // A malformed .tris names the file and the line.
  const CliRun r = run("render " + data("cli_bad_fields.tris"));
  expect_one_line_error(r, 1, "cli_bad_fields.tris");
  EXPECT_NE(r.err.find("cli_bad_fields.tris:7:"), std::string::npos) << r.err;
  EXPECT_TRUE(files_in_work().empty());
}

// What a terminal would act on: a control byte other than the line end, DEL, a C1 control
// (0xc2 0x80-0x9f) or a byte that is not part of well-formed UTF-8.
std::string terminal_hazard(const std::string& text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto b = static_cast<unsigned char>(text[i]);
    const auto next = i + 1 < text.size() ? static_cast<unsigned char>(text[i + 1]) : 0u;
    if ((b < 0x20 && b != '\n') || b == 0x7f) return "control byte at " + std::to_string(i);
    if (b == 0xc2 && next >= 0x80 && next <= 0x9f) return "C1 control at " + std::to_string(i);
    if (b >= 0x80) {
      const int n = b >= 0xf0 && b <= 0xf4 ? 4 : b >= 0xe0 ? 3 : b >= 0xc2 && b <= 0xdf ? 2 : 0;
      if (n == 0 || b > 0xf4 || i + n > text.size()) return "bad UTF-8 at " + std::to_string(i);
      for (int k = 1; k < n; ++k)
        if ((static_cast<unsigned char>(text[i + k]) & 0xc0) != 0x80)
          return "bad UTF-8 at " + std::to_string(i);
      i += n - 1;
    }
  }
  return "";
}

TEST_F(CliTest, HostileBytesInNamesAndFilesAreEscaped) {
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(work_ / name, std::ios::binary) << text;
  };
  const std::string quad = read_file(kData + "/cli_quad.tris");
  const std::string retitle = "\x1b]0;owned\x07", clear = "\x1b[2J";
  // File names and contents that would retitle or clear the terminal, with bytes that are not
  // UTF-8, in errors and in the success line alike.
  write(retitle + ".tris", "size 4 4\n" + clear + " 1 2 3\n");
  write("bad\xff\xfe.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 " + clear + "\xff\n");
  write(clear +
            "\xc2\x9b"
            "31m.tris",
        quad);
  write("caf\xc3\xa9.tris", quad);
  struct Case {
    std::string args;
    int status;
    std::string shown;  // what the message must show for the hostile bytes
  };
  const std::vector<Case> cases = {
      {"render " + quote(retitle + ".tris") + " --no-out", 1, "\\x1b]0;owned\\x07.tris:2:"},
      {"render " + quote("bad\xff\xfe.obj") + " --no-out", 1, "bad\\xff\\xfe.obj:4:"},
      {"render " +
           quote(clear + "\xc2\x9b"
                         "31m.tris") +
           " --no-out --stats",
       0, "\\x1b[2J\\xc2\\x9b31m"},
      {"render " + quote("caf\xc3\xa9.tris") + " --no-out", 0, "caf\xc3\xa9 40x30"},
      {"render missing" + quote(retitle) + ".tris", 1, "missing\\x1b]0;owned\\x07.tris"},
      {"render star --size " + quote(clear), 2, "\\x1b[2J"},
  };
  for (const Case& c : cases) {
    const CliRun r = run(c.args);
    EXPECT_EQ(r.status, c.status) << c.args << ": " << r.err;
    EXPECT_EQ(terminal_hazard(r.err), "") << c.args << ": " << r.err;
    EXPECT_NE(r.err.find(c.shown), std::string::npos) << c.args << ": " << r.err;
    if (c.status == 0 && !r.out.empty()) {
      const nlohmann::json j = nlohmann::json::parse(r.out, nullptr, false);
      EXPECT_TRUE(j.is_object()) << r.out;
    }
  }
}

}  // namespace
