// test_quality_report_cli.cpp — `mosaic report` run as a process on small sizes: it writes
// every file the report promises, and refuses a command line without --out.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

int run(const std::string& args) {
  const std::string cmd = std::string(MOSAIC_CLI_PATH) + " " + args + " >/dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(ReportCli, WritesEveryFile) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("mosaic-report-test-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  ASSERT_EQ(run("report --out " + dir.string() + " --size 160x90 --error-size 96x64 --frames 1"),
            0);
  for (const char* f : {"report.md",
                        "star-pareto.svg",
                        "zoneplate-pareto.svg",
                        "mesh-pareto.svg",
                        "overlap-pareto.svg",
                        "star-crops.png",
                        "zoneplate-crops.png",
                        "zoneplate-spectrum-ground-truth.png",
                        "zoneplate-spectrum-1x.png",
                        "zoneplate-spectrum-4x-msaa.png",
                        "zoneplate-spectrum-16x-msaa.png",
                        "zoneplate-spectrum-fxaa-on-1x.png",
                        "zoneplate-spectrum-16x-gaussian.png",
                        "texture-ground-truth.png",
                        "texture-nearest.png",
                        "texture-trilinear.png",
                        "texture-spectrum-ground-truth.png",
                        "texture-spectrum-nearest.png",
                        "texture-spectrum-bilinear.png",
                        "texture-spectrum-bilinear-mip.png",
                        "texture-spectrum-trilinear.png"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
    if (std::filesystem::exists(dir / f)) {
      EXPECT_GT(std::filesystem::file_size(dir / f), 100u) << f;
    }
  }
  std::ifstream md(dir / "report.md");
  std::stringstream text;
  text << md.rdbuf();
  const std::string s = text.str();
  // One table per scene, each with every mode as a row (a line of its own).
  std::size_t tables = 0, pos = 0;
  while ((pos = s.find("| mode |", pos)) != std::string::npos) ++tables, ++pos;
  EXPECT_EQ(tables, 4u);
  for (const char* mode :
       {"\n| 1x |", "\n| 16x SSAA |", "\n| FXAA on 4x |", "\n| 16x Gaussian |"}) {
    std::size_t count = 0, p = 0;
    while ((p = s.find(mode, p)) != std::string::npos) ++count, ++p;
    EXPECT_EQ(count, 4u) << mode;
  }
  // The texture table: one row per filter.
  EXPECT_NE(s.find("## Texture aliasing"), std::string::npos);
  for (const char* filter : {"\n| nearest, no mipmaps |", "\n| bilinear, no mipmaps |",
                             "\n| bilinear, nearest mip level |", "\n| trilinear |"})
    EXPECT_NE(s.find(filter), std::string::npos) << filter;
  std::ifstream svg(dir / "star-pareto.svg");
  std::stringstream svg_text;
  svg_text << svg.rdbuf();
  EXPECT_NE(svg_text.str().find("<svg"), std::string::npos);
  EXPECT_NE(svg_text.str().find("<polyline"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(ReportCli, NeedsAnOutputFolder) { EXPECT_EQ(run("report --size 160x90"), 2); }

}  // namespace
