// skidsim bench report: the speed-against-error page is written from one
// command, its numbers from that run: tables with a row per rung, a plot
// per case.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/app_support.h"

namespace {

namespace fs = std::filesystem;

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}

TEST(SkidsimBenchReport, WritesThePageAndItsPlots) {
  const fs::path dir = fs::temp_directory_path() / "skidsim_perf_report";
  fs::remove_all(dir);
  const auto r = skidsim::testing::run_skidsim("bench report --quick --out " + (dir / "perf.md").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(dir / "perf.md");
  std::stringstream page;
  page << in.rdbuf();
  const std::string md = page.str();
  EXPECT_NE(md.find("# Speed against error"), std::string::npos);
  EXPECT_EQ(count(md, "| 20 cm |"), 2u) << "flank and roundness tables";
  EXPECT_EQ(count(md, "| 10 cm |"), 2u);
  EXPECT_EQ(count(md, "| 5/m |"), 1u);
  EXPECT_EQ(count(md, "| 10/m |"), 1u);
  for (const char* svg : {"perf_repose_slope.svg", "perf_repose_roundness.svg", "perf_push.svg"}) {
    EXPECT_NE(md.find(svg), std::string::npos) << svg;
    std::ifstream plot(dir / svg);
    std::stringstream text;
    text << plot.rdbuf();
    EXPECT_EQ(count(text.str(), "<circle"), 2u) << svg << ": a point per rung";
  }
  // The coarse cone is far less round than the finer one: the numbers are measured.
  EXPECT_NE(md.find("flank 30."), std::string::npos);
}

}  // namespace
