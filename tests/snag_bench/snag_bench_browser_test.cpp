// snag-bench's page in headless chromium: every chart drawn, the self-check
// counts equal to the JSON's, no script error; and --png renders each chart
// to a PNG that is not blank. Skipped when chromium is not installed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "tests/tools/run_process.hpp"

namespace snag::test {
namespace {

bool have_chromium() {
  if (std::getenv("SNAG_CHROMIUM")) return true;
  return run_process("/bin/sh", {"-c", "command -v chromium || command -v chromium-browser"}).exit_code == 0;
}

/// The value of attribute `name` of the DOM's <body>, "" when absent.
std::string body_attribute(const std::string& dom, const std::string& name) {
  std::smatch body;
  if (!std::regex_search(dom, body, std::regex("<body[^>]*>"))) return "";
  std::smatch value;
  const std::string tag = body.str();
  return std::regex_search(tag, value, std::regex(name + "=\"([^\"]*)\"")) ? value[1].str() : "";
}

TEST(SnagBenchPage, DrawsEveryChartAndRendersThemToPng) {
  if (!have_chromium()) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
  TemporaryDirectory dir;
  const std::string meshes = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/thick-cloth/";
  ProcessOptions limits;
  limits.timeout_seconds = 300;
  const ProcessResult bench = run_process(
      SNAG_BENCH_EXE,
      {"--quick", "--samples", "2", "--families", "vf-coplanar", "--queries", std::string(SNAG_SHARED_DATA_DIR) + "/ccd-queries/unit-tests",
       "--sequence", meshes + "t0.ply", meshes + "t1.ply", "--json", dir.path("b.json"), "--html",
       dir.path("b.html"), "--png", dir.path("charts"), "-q"},
      limits);
  ASSERT_EQ(bench.exit_code, 0) << bench.err;
  const nlohmann::json results = nlohmann::json::parse(read_file(dir.path("b.json")));
  const std::size_t families = results.at("families").size();
  const std::size_t charts = 2 + families + 2;  // speed (FN, FP), one per family, a scene's tiers and broad phases

  const ProcessResult dom = run_process(
      "/bin/sh", {"-c", "${SNAG_CHROMIUM:-$(command -v chromium || command -v chromium-browser)} --headless "
                        "--no-sandbox --disable-gpu --no-first-run --user-data-dir=" + dir.path("profile") +
                        " --virtual-time-budget=5000 --dump-dom file://" + dir.path("b.html") + " 2>/dev/null"},
      limits);
  ASSERT_EQ(dom.exit_code, 0);
  EXPECT_EQ(body_attribute(dom.out, "data-error"), "");
  EXPECT_EQ(body_attribute(dom.out, "data-ready"), "1");
  EXPECT_EQ(body_attribute(dom.out, "data-charts"), std::to_string(charts));
  EXPECT_EQ(body_attribute(dom.out, "data-families"), std::to_string(families));
  EXPECT_EQ(body_attribute(dom.out, "data-scenes"), "1");

  std::size_t pngs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path("charts"))) pngs += entry.path().extension() == ".png";
  EXPECT_EQ(pngs, charts);
  // The speed-accuracy chart: 900 pixels wide, not blank, coloured points.
  const ProcessResult shot = run_process("/usr/bin/env", {"python3", PNG_COLOURS_PY, dir.path("charts/snag-bench-speed-fn.png")});
  ASSERT_EQ(shot.exit_code, 0) << shot.err;
  std::istringstream described(shot.out);
  int width = 0, height = 0, colours = 0;
  double changed = 0;
  described >> width >> height >> changed >> colours;
  EXPECT_EQ(width, 900);
  EXPECT_GT(changed, 0.02) << "the chart is blank";
  EXPECT_GT(colours, 20) << "the chart has no coloured points";
}

}  // namespace
}  // namespace snag::test
