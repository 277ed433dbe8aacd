// Bad input that test_io.cpp, test_api_errors.cpp and test_cli.cpp do not already cover: every
// truncation of a valid .tris and OBJ file (each either parses or is one kParse error naming the
// file and line, never a crash), non-finite and absurdly long numbers in colours and coordinates,
// OBJ face indices past int's range (found here: the OBJ parser once used, whose atoi wrapped
// 99999999999999999999 to an existing vertex and the face was drawn), and the `mosaic` CLI's
// exit status and one-line message for each kind of bad file.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "mosaic/mosaic.hpp"

namespace mosaic {
namespace {

namespace fs = std::filesystem;

// A scratch directory removed at the end of the test.
struct Scratch {
  fs::path dir;
  Scratch() {
    dir = fs::temp_directory_path() /
          ("mosaic_hard_bad_" + std::to_string(reinterpret_cast<std::uintptr_t>(this)));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream out(dir / name, std::ios::binary);
    out << text;
    return dir / name;
  }
};

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs `call`; it must succeed or throw kParse whose one-line message starts with `prefix`.
template <class F>
void parses_or_names_the_line(F&& call, const std::string& prefix, const std::string& what) {
  try {
    call();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), Errc::kParse) << what << ": " << e.what();
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(prefix, 0), 0u) << what << ": " << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << what;
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": not a mosaic::Error: " << e.what();
  }
}

TEST(HardBadInput, EveryTruncationOfATrisFileParsesOrNamesItsLine) {
  const std::string full = read(fs::path(MOSAIC_TEST_DATA_DIR) / "shared_edges.tris");
  ASSERT_GT(full.size(), 1000u);
  std::size_t rejected = 0;
  for (std::size_t n = 0; n < full.size(); ++n) {
    bool threw = false;
    parses_or_names_the_line(
        [&] {
          try {
            parse_tris(full.substr(0, n), "cut.tris");
          } catch (const Error&) {
            threw = true;
            throw;
          }
        },
        "cut.tris:", "prefix " + std::to_string(n));
    rejected += threw ? 1 : 0;
  }
  // Most cuts fall inside a line and leave it short: the parser must notice.
  EXPECT_GT(rejected, full.size() / 2);
}

TEST(HardBadInput, EveryTruncationOfAnObjFileLoadsOrNamesTheFile) {
  Scratch s;
  const std::string full = read(fs::path(MOSAIC_TEST_DATA_DIR) / "cube.obj");
  for (std::size_t n = 0; n < full.size(); ++n) {
    const fs::path p = s.write("cut.obj", full.substr(0, n));
    parses_or_names_the_line([&] { load_obj(p, 32, 32); }, p.string() + ":",
                             "prefix " + std::to_string(n));
  }
}

TEST(HardBadInput, NonFiniteAndAbsurdNumbersInTris) {
  const std::string tri = "size 4 4\ntri 0 0 0 4 0 0 0 4 0 ";
  const std::string long_number = "0." + std::string(5000, '0') + "1";
  const std::vector<std::pair<std::string, std::string>> bad{
      {"colour nan", tri + "nan 0 0 255\n"},
      {"colour inf", tri + "1 inf 0 255\n"},
      {"colour -inf", tri + "1 2 -inf 255\n"},
      {"colour 1e999", tri + "1 2 3 1e999\n"},
      {"colour 99999999999999999999", tri + "1 2 3 99999999999999999999\n"},
      {"per-vertex colour nan", tri + "1 2 3 4 5 6 7 8 9 10 11 nan\n"},
      {"coordinate 1e40", "size 4 4\ntri 0 0 0 1e40 0 0 0 4 0 1 2 3 4\n"},
      {"5000-digit colour", tri + long_number + " 0 0 255\n"},
      {"size 1e3", "size 1e3 4\n"},
  };
  for (const auto& [what, text] : bad) {
    try {
      parse_tris(text, "n.tris");
      ADD_FAILURE() << what << ": accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), Errc::kParse) << what;
      EXPECT_EQ(std::string(e.what()).rfind("n.tris:2: ", 0) == 0 ||
                    std::string(e.what()).rfind("n.tris:1: ", 0) == 0,
                true)
          << what << ": " << e.what();
    }
  }
  // A 5000-digit coordinate (about 1e-5001, below float's range) may be read as 0 or refused as
  // out of range; either way no crash and, if refused, one line naming line 2.
  parses_or_names_the_line(
      [&] { parse_tris("size 4 4\ntri " + long_number + " 0 0 4 0 0 0 4 0 1 2 3 4\n", "n.tris"); },
      "n.tris:2: ", "5000-digit coordinate");
}

TEST(HardBadInput, ObjFaceIndicesBeyondIntAreErrorsNotOtherVertices) {
  // Regression: a parser once used read 99999999999999999999 with atoi (undefined on overflow; here
  // it came back as an existing vertex) and the face was drawn. Each of these must be rejected,
  // naming line 4.
  Scratch s;
  const std::string verts = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  for (const char* face :
       {"f 1 2 99999999999999999999", "f 1 2 -99999999999999999999", "f 1 2 4294967298",
        "f 1 2 2147483648", "f 1/1 2/2 99999999999999999999/3", "f 1 2 3x", "f 1 2 0"}) {
    const fs::path p = s.write("big.obj", verts + face + "\n");
    try {
      load_obj(p, 16, 16);
      ADD_FAILURE() << face << ": accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), Errc::kParse) << face;
      EXPECT_EQ(std::string(e.what()).rfind(p.string() + ":4: ", 0), 0u)
          << face << ": " << e.what();
    }
  }
  // Indices that do fit int and name existing vertices still load, relative ones too.
  EXPECT_NO_THROW(load_obj(s.write("ok.obj", verts + "f 1/5/7 2//3 -1\n"), 16, 16));
}

// ---- The CLI ----

struct CliRun {
  int status = -1;
  std::string err;
};

CliRun run_cli(const std::string& args, const fs::path& dir) {
  const fs::path err = dir / "stderr.txt";
  const std::string cmd = "cd " + dir.string() + " && " + MOSAIC_CLI_PATH + " " + args + " 2> " +
                          err.string() + " > /dev/null";
  const int raw = std::system(cmd.c_str());
  CliRun r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.err = read(err);
  fs::remove(err);
  return r;
}

TEST(HardBadInput, CliRejectsEveryKindOfBadFileWithOneLineAndStatusOne) {
  Scratch s;
  const std::vector<std::pair<std::string, std::string>> files{
      {"truncated.tris", "size 8 8\ntri 0 0 0 8 0 0 0 8 0 1 2"},
      {"zero.tris", "size 0 8\n"},
      {"huge.tris", "size 16385 8\n"},
      {"count.tris", "size 8 8\ntri 0 0 0 8 0 0 0 8 0 1 2 3 4 5\n"},
      {"nancolour.tris", "size 8 8\ntri 0 0 0 8 0 0 0 8 0 nan 2 3 4\n"},
      {"hugecoord.tris", "size 8 8\ntri 0 0 0 1e999 0 0 0 8 0 1 2 3 4\n"},
      {"binary.tris", std::string("size 8 8\n\x01\x02\xff\xfe", 13)},
      {"empty.tris", ""},
      {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"},
      {"overflow.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n"},
      {"truncated.obj", "v 0 0 0\nv 1 0 0\nv 0 1"},
      {"nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"},
  };
  for (const auto& [name, text] : files) {
    s.write(name, text);
    for (const std::string& cmd :
         {"render " + name + " --no-out", "export " + name + " --out x.tris"}) {
      if (cmd.rfind("export", 0) == 0 && name.find(".tris") != std::string::npos) continue;
      const CliRun r = run_cli(cmd, s.dir);
      EXPECT_EQ(r.status, 1) << cmd << ": " << r.err;
      EXPECT_EQ(r.err.rfind("mosaic: ", 0), 0u) << cmd << ": " << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << cmd << ": " << r.err;
      EXPECT_NE(r.err.find(name), std::string::npos) << cmd << ": the file is named: " << r.err;
      EXPECT_FALSE(fs::exists(s.dir / "x.tris")) << cmd << ": no partial output";
    }
  }
}

TEST(HardBadInput, CliWarnsOnceAboutAnObjVertexThatIsNotFiniteAndDrawsTheRest) {
  Scratch s;
  s.write("part.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nf 1 2 3\nf 1 2 4\n");
  for (const std::string& cmd :
       {std::string("render part.obj --no-out"), std::string("export part.obj --out x.tris")}) {
    const CliRun r = run_cli(cmd, s.dir);
    EXPECT_EQ(r.status, 0) << cmd << ": " << r.err;
    EXPECT_EQ(r.err.rfind("mosaic: warning: part.obj:4: 1 vertex has", 0), 0u) << cmd << r.err;
    EXPECT_EQ(r.err.find("warning", 20), std::string::npos) << cmd << ": one warning: " << r.err;
  }
  // The export keeps the one finite triangle.
  const std::string tris = read(s.dir / "x.tris");
  std::size_t count = 0;
  for (std::size_t at = tris.find("\ntri "); at != std::string::npos;
       at = tris.find("\ntri ", at + 1))
    ++count;
  EXPECT_EQ(count, 1u) << tris;
}

}  // namespace
}  // namespace mosaic
