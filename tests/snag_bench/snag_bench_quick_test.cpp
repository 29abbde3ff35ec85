// snag-bench --quick end to end, as CI runs it: the shared query set with
// exact ground truth and the shared thick-cloth step; its JSON must show the
// exact and the certified methods with no false negative, no false positive
// and no uncertain answer anywhere, the filter alone with no wrong answer
// (only uncertain ones), Provot's float cubic wrong on some handcrafted
// queries, the adaptive scene run equal to the heavy one, and no broad phase
// missing a colliding pair. Bad input exits 2 with one line.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/tools/run_process.hpp"

namespace snag::test {
namespace {

using nlohmann::json;

const std::string kQueries = std::string(SNAG_SHARED_DATA_DIR) + "/ccd-queries";
const std::string kThickCloth = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/thick-cloth/";

std::size_t wrong(const json& counts) { return counts.at("fn").get<std::size_t>() + counts.at("fp").get<std::size_t>(); }

void expect_exact_and_certified_never_err(const json& results) {
  ASSERT_EQ(results.at("query_sets").size(), 16u);  // 8 data sets, VF and EE
  std::size_t queries = 0;
  for (const json& set : results.at("query_sets")) {
    queries += set.at("queries").get<std::size_t>();
    for (const char* method : {"exact", "certified"}) {
      EXPECT_EQ(wrong(set.at("methods").at(method)), 0u) << set.at("name") << " " << method;
      EXPECT_EQ(set.at("methods").at(method).at("uncertain"), 0) << set.at("name") << " " << method;
    }
    EXPECT_EQ(wrong(set.at("methods").at("filter")), 0u) << set.at("name");
  }
  EXPECT_EQ(queries, 3824u);  // every query of the shared set (wc -l / 8)
  for (const json& family : results.at("families")) {
    for (const char* method : {"exact", "certified", "filter"}) {
      for (std::size_t i = 0; i < family.at("knob_values").size(); ++i) {
        const json& m = family.at("methods").at(method);
        EXPECT_EQ(m.at("fn")[i].get<int>() + m.at("fp")[i].get<int>(), 0) << family.at("name") << " " << method;
      }
    }
  }
  EXPECT_TRUE(results.at("exact_methods_agree").get<bool>());
}

void expect_float_cubic_errs(const json& results) {
  std::size_t float_wrong = 0, double_wrong = 0;
  for (const json& total : results.at("query_totals")) {
    float_wrong += wrong(total.at("methods").at("cubic-float"));
    double_wrong += wrong(total.at("methods").at("cubic-double"));
  }
  EXPECT_GT(float_wrong, 0u);
  EXPECT_GT(double_wrong, 0u);
  // Along the families too: the float cubic errs in most of them.
  std::size_t families_with_errors = 0;
  for (const json& family : results.at("families")) {
    int errors = 0;
    for (const json& e : family.at("methods").at("cubic-float").at("fn")) errors += e.get<int>();
    for (const json& e : family.at("methods").at("cubic-float").at("fp")) errors += e.get<int>();
    families_with_errors += errors > 0;
  }
  EXPECT_GE(families_with_errors, results.at("families").size() / 2);
}

void expect_adaptive_scene_run_as_heavy(const json& results) {
  ASSERT_EQ(results.at("scenes").size(), 1u);
  const json& scene = results.at("scenes")[0];
  EXPECT_EQ(scene.at("steps"), 1);
  EXPECT_EQ(scene.at("triangles"), 404);
  EXPECT_TRUE(scene.at("same_answers").get<bool>());
  EXPECT_GT(scene.at("positives").get<int>(), 0);
  std::size_t decided = 0;
  for (const auto& [tier, count] : scene.at("tiers").items()) decided += count.get<std::size_t>();
  EXPECT_EQ(decided, scene.at("adaptive").at("candidates").get<std::size_t>());
  EXPECT_LT(scene.at("adaptive").at("exact_queries").get<std::size_t>(),
            scene.at("heavy").at("exact_queries").get<std::size_t>());
  for (const json& run : scene.at("broad_phases")) {
    EXPECT_FALSE(run.at("skipped").get<bool>()) << run.at("name");  // 404 triangles: brute force runs too
    EXPECT_EQ(run.at("missed"), 0) << run.at("name");
    EXPECT_GT(run.at("tests").get<std::size_t>(), 0u) << run.at("name");
  }
}

// One run for every check: the quick run is the slow part.
TEST(SnagBenchQuick, MeetsTheAccuracyContractAndTheCubicDoesNot) {
  TemporaryDirectory dir;
  ProcessOptions limits;
  limits.timeout_seconds = 600;  // a bound, not a timing: sanitizer builds run it too
  const ProcessResult run =
      run_process(SNAG_BENCH_EXE,
                  // The cache inputs right after --queries DIR: that option takes one value.
                  {"--quick", "--sequence", "--queries", kQueries, kThickCloth + "t0.ply", kThickCloth + "t1.ply",
                   "--threads", "2", "--json", dir.path("q.json")},
                  limits);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json results = json::parse(read_file(dir.path("q.json")));
  EXPECT_TRUE(results.at("quick").get<bool>());
  {
    SCOPED_TRACE("exact and certified methods");
    expect_exact_and_certified_never_err(results);
  }
  {
    SCOPED_TRACE("Provot's cubic");
    expect_float_cubic_errs(results);
  }
  {
    SCOPED_TRACE("scene");
    expect_adaptive_scene_run_as_heavy(results);
  }
  // The table names every data set and the scene.
  EXPECT_NE(run.out.find("erleben-spikes"), std::string::npos);
  EXPECT_NE(run.out.find("same answers: yes"), std::string::npos) << run.out;
}

TEST(SnagBenchInput, BadQueryFolderExitsTwoWithOneLine) {
  const ProcessResult run = run_process(SNAG_BENCH_EXE, {"--no-families", "--queries", "/nonexistent/queries"});
  EXPECT_EQ(run.exit_code, 2);
  ASSERT_EQ(lines_of(run.err).size(), 1u) << run.err;
  EXPECT_NE(run.err.find("/nonexistent/queries"), std::string::npos) << run.err;
}

TEST(SnagBenchInput, UnknownFamilyExitsTwoNamingIt) {
  const ProcessResult run = run_process(SNAG_BENCH_EXE, {"--families", "vf-coplanar,no-such-family"});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("no-such-family"), std::string::npos) << run.err;
}

TEST(SnagBenchInput, PngWithoutPageExitsTwo) {
  const ProcessResult run = run_process(SNAG_BENCH_EXE, {"--no-families", "--png", "charts"});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("--png needs --html"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace snag::test
