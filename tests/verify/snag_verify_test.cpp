// snag-verify run as a user runs it: on a certified scan of frames 26 to 29
// of the sample cache, on copies of that report edited to drop or add one
// event or to name other objects, and on one scene of the CCD query set.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "io/open_cache.hpp"

namespace {

using nlohmann::json;

const std::string kSamples = std::string(SNAG_SOURCE_DIR) + "/samples/cloth_ball/";
const std::string kCache = kSamples + "cloth.pc2 -t " + kSamples + "cloth_rest.obj " + kSamples + "body.pc2 -t " +
                           kSamples + "body_rest.obj";

struct ToolRun {
  int exit_code = -1;
  std::string out, err;
};

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

class SnagVerify : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::filesystem::temp_directory_path() / ("snag_verify_test_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
    const ToolRun scan = run(SNAG_SCAN_EXE, kCache + " --frames 26:29 -q --fail-on 0 -r " + path("report.json"));
    ASSERT_EQ(scan.exit_code, 0) << scan.err;
    report_ = json::parse(read_text(path("report.json")));
  }
  static void TearDownTestSuite() { std::filesystem::remove_all(dir_); }

  static std::string path(const std::string& name) { return (dir_ / name).string(); }

  static ToolRun run(const std::string& exe, const std::string& args) {
    const std::string err_path = path("stderr.txt");
    const std::string command = exe + " " + args + " 2>" + err_path;
    ToolRun result;
    FILE* pipe = popen(command.c_str(), "r");
    if (pipe == nullptr) return result;
    char buffer[4096];
    std::size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) result.out.append(buffer, n);
    const int status = pclose(pipe);
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    result.err = read_text(err_path);
    return result;
  }

  static ToolRun verify(const std::string& args) { return run(SNAG_VERIFY_EXE, args); }

  static std::string write_report(const std::string& name, const json& report) {
    std::ofstream(path(name)) << report.dump(1);
    return path(name);
  }

  static std::filesystem::path dir_;
  static json report_;
};

std::filesystem::path SnagVerify::dir_;
json SnagVerify::report_;

TEST_F(SnagVerify, ConfirmsEveryEventOfACertifiedScan) {
  const std::size_t events = report_.at("events").size();
  ASSERT_GT(events, 0u) << "frames 26 to 29 of the sample should have events";
  const ToolRun r = verify(path("report.json") + " " + kCache + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const json result = json::parse(r.out);
  EXPECT_EQ(result.at("events"), events);
  EXPECT_EQ(result.at("confirmed"), events);
  EXPECT_EQ(result.at("false"), 0);
  EXPECT_EQ(result.at("toi_mismatch"), 0);
  EXPECT_TRUE(result.at("missed").is_null());
}

TEST_F(SnagVerify, ExhaustiveFindsTheOneDroppedEvent) {
  json edited = report_;
  json& events = edited.at("events");
  std::size_t drop = events.size();
  for (std::size_t i = 0; i < events.size(); ++i)
    if (events[i].at("kind") == "collision") drop = i;
  ASSERT_LT(drop, events.size()) << "the scan should have a collision";
  const json dropped = events[drop];
  events.erase(events.begin() + static_cast<std::ptrdiff_t>(drop));
  const ToolRun r = verify(write_report("dropped.json", edited) + " " + kCache + " --exhaustive --json");
  ASSERT_EQ(r.exit_code, 1) << r.out << r.err;
  const json result = json::parse(r.out);
  // Exactly one: the certified scan missed nothing else.
  EXPECT_EQ(result.at("missed"), 1);
  EXPECT_EQ(result.at("false"), 0);
  EXPECT_GT(result.at("exhaustive_tests").at("vf").get<std::size_t>(), 0u);
  EXPECT_GT(result.at("exhaustive_tests").at("ee").get<std::size_t>(), 0u);
  EXPECT_GT(result.at("exhaustive_tests").at("triangle_pairs").get<std::size_t>(), 0u);
  ASSERT_EQ(result.at("missed_events").size(), 1u);
  const json& missed = result.at("missed_events")[0];
  EXPECT_EQ(missed.at("frame"), dropped.at("frame"));
  EXPECT_EQ(missed.at("type"), dropped.at("type"));
  EXPECT_EQ(missed.at("a"), dropped.at("a"));
  EXPECT_EQ(missed.at("b"), dropped.at("b"));
}

TEST_F(SnagVerify, FlagsTheOneAddedFalseEvent) {
  // A cloth vertex and a body face whose boxes over the step 26 -> 27 are far
  // apart along some axis: they cannot touch.
  snag::io::CacheOptions options;
  options.inputs = {{kSamples + "cloth.pc2", kSamples + "cloth_rest.obj", ""},
                    {kSamples + "body.pc2", kSamples + "body_rest.obj", ""}};
  options.frames = snag::io::parse_frame_selection("26:29");
  const auto source = snag::io::open_cache(options);
  const snag::Scene& scene = source->scene();
  std::vector<snag::Vec3> x_t0, x_t1;
  source->read_frame(0, x_t0);
  source->read_frame(1, x_t1);
  auto far_apart = [&](snag::Index v, snag::Index f) {
    for (int axis = 0; axis < 3; ++axis) {
      auto c = [axis](const snag::Vec3& p) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; };
      double lo = 1e300, hi = -1e300;
      for (snag::Index u : scene.triangles()[f]) {
        lo = std::min({lo, c(x_t0[u]), c(x_t1[u])});
        hi = std::max({hi, c(x_t0[u]), c(x_t1[u])});
      }
      const double p_lo = std::min(c(x_t0[v]), c(x_t1[v])), p_hi = std::max(c(x_t0[v]), c(x_t1[v]));
      if (p_lo > hi + 0.1 || p_hi < lo - 0.1) return true;
    }
    return false;
  };
  const snag::Index body_face = scene.triangle_offset(1);
  snag::Index cloth_vertex = 0;
  while (!far_apart(cloth_vertex, body_face)) ++cloth_vertex;
  ASSERT_LT(cloth_vertex, scene.vertex_offset(1));

  json edited = report_;
  const json added{{"kind", "collision"},
                   {"frame", 26},  // reports name frames by the cache's own index
                   {"type", "vf"},
                   {"toi", 26.5},
                   {"toi_interval", {26.5, 26.5}},
                   {"a", {{"object", scene.objects()[0].name}, {"vertex", cloth_vertex}}},
                   {"b", {{"object", scene.objects()[1].name}, {"face", 0}}},
                   {"certainty", "proven"},
                   {"position", {0, 0, 0}}};
  edited.at("events").push_back(added);
  const std::string report = write_report("added.json", edited);
  const ToolRun r = verify(report + " " + kCache + " --json");
  ASSERT_EQ(r.exit_code, 1) << r.out << r.err;
  const json result = json::parse(r.out);
  EXPECT_EQ(result.at("false"), 1);
  EXPECT_EQ(result.at("confirmed"), report_.at("events").size());
  ASSERT_EQ(result.at("false_events").size(), 1u);
  EXPECT_EQ(result.at("false_events")[0].at("a"), added.at("a"));
  EXPECT_EQ(result.at("false_events")[0].at("b"), added.at("b"));

  const ToolRun text = verify(report + " " + kCache);
  EXPECT_EQ(text.exit_code, 1);
  EXPECT_NE(text.out.find("false: 1\n"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find(scene.objects()[0].name + " vertex " + std::to_string(cloth_vertex)), std::string::npos)
      << text.out;
}

TEST_F(SnagVerify, RejectsAReportWhoseObjectNamesDiffer) {
  json edited = report_;
  edited.at("objects")[0].at("name") = "not_the_cloth";
  const ToolRun r = verify(write_report("renamed.json", edited) + " " + kCache);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("not_the_cloth"), std::string::npos) << r.err;
}

TEST_F(SnagVerify, RejectsAnEventWhoseIdIsOutOfRange) {
  json edited = report_;
  json& events = edited.at("events");
  ASSERT_FALSE(events.empty());
  json& a = events[0].at("a");
  if (a.contains("vertex")) {
    a.at("vertex") = 1000000;
  } else if (a.contains("face")) {
    a.at("face") = 1000000;
  } else {
    a.at("edge") = {0, 1000000};
  }
  const ToolRun r = verify(write_report("out_of_range.json", edited) + " " + kCache);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("out of range"), std::string::npos) << r.err;
}

TEST_F(SnagVerify, ScanModeConfirmsItsOwnScan) {
  const ToolRun r = verify("--scan " + kCache + " --frames 26:28 --json");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const json result = json::parse(r.out);
  EXPECT_EQ(result.at("confirmed"), result.at("events"));
}

// Counts queries and positives straight from the CSV rows (8 rows a query,
// truth in the 7th column).
struct Truth {
  std::size_t queries = 0, positives = 0;
};
Truth count_truth(const std::filesystem::path& folder) {
  Truth truth;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    std::ifstream in(entry.path());
    std::string line;
    std::size_t row = 0;
    while (std::getline(in, line)) {
      if (line.empty()) continue;
      if (row % 8 == 0) {
        ++truth.queries;
        truth.positives += line.substr(line.find_last_of(',') + 1) == "1";
      }
      ++row;
    }
  }
  return truth;
}

TEST_F(SnagVerify, QueriesOfOneSceneAgreeWithTheGroundTruth) {
  const std::filesystem::path scene = std::filesystem::path(SNAG_SHARED_DATA_DIR) / "ccd-queries/erleben-sliding-spike";
  const ToolRun r = verify("--queries " + scene.string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const json result = json::parse(r.out);
  const struct {
    const char* kind;
    const char* folder;
  } kinds[] = {{"vf", "vertex-face"}, {"ee", "edge-edge"}};
  for (const auto& k : kinds) {
    const Truth truth = count_truth(scene / k.folder);
    const json& exact = result.at("methods").at("exact").at(k.kind);
    const json& filter = result.at("methods").at("filter").at(k.kind);
    EXPECT_EQ(exact.at("queries"), truth.queries) << k.kind;
    EXPECT_EQ(exact.at("positives"), truth.positives) << k.kind;
    EXPECT_EQ(exact.at("true_positives"), truth.positives) << k.kind;
    EXPECT_EQ(exact.at("false_positives"), 0) << k.kind;
    EXPECT_EQ(exact.at("false_negatives"), 0) << k.kind;
    EXPECT_EQ(filter.at("queries"), truth.queries) << k.kind;
    EXPECT_EQ(filter.at("false_negatives"), 0) << k.kind << ": the filter must be conservative";
    EXPECT_EQ(filter.at("true_positives").get<std::size_t>() + filter.at("uncertain_positives").get<std::size_t>(),
              truth.positives)
        << k.kind;
  }
  EXPECT_TRUE(result.at("disagreements").is_array());
}

TEST_F(SnagVerify, RejectsAQueryFolderWithoutQueries) {
  const ToolRun r = verify("--queries " + path(""));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
}

}  // namespace
