// snag-verify run as a user runs it: on a certified scan of frames 26 to 29
// of the sample cache, on copies of that report (JSON Lines) edited to drop or
// add one event, to name other objects, to contradict its regions or totals,
// to leave events out, and on one scene of the CCD query set.
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
    std::istringstream lines(read_text(path("report.json")));
    for (std::string line; std::getline(lines, line);) records_.push_back(json::parse(line));
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

  static std::string write_report(const std::string& name, const std::vector<json>& records) {
    std::ofstream out(path(name));
    for (const json& record : records) out << record.dump() << "\n";
    return path(name);
  }

  // Indices into records_ of the records of one kind.
  static std::vector<std::size_t> find(const std::string& kind) {
    std::vector<std::size_t> found;
    for (std::size_t i = 0; i < records_.size(); ++i)
      if (records_[i].at("record") == kind) found.push_back(i);
    return found;
  }
  static std::size_t event_count() { return find("event").size(); }

  static std::filesystem::path dir_;
  static std::vector<json> records_;
};

std::filesystem::path SnagVerify::dir_;
std::vector<json> SnagVerify::records_;

TEST_F(SnagVerify, ConfirmsEveryEventOfACertifiedScan) {
  const std::size_t events = event_count();
  ASSERT_GT(events, 0u) << "frames 26 to 29 of the sample should have events";
  const ToolRun r = verify(path("report.json") + " " + kCache + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const json result = json::parse(r.out);
  EXPECT_EQ(result.at("events"), events);
  EXPECT_EQ(result.at("confirmed"), events);
  EXPECT_EQ(result.at("false"), 0);
  EXPECT_EQ(result.at("toi_mismatch"), 0);
  EXPECT_TRUE(result.at("missed").is_null());
  EXPECT_TRUE(result.at("complete").get<bool>());
  EXPECT_EQ(result.at("regions").at("checked"), find("region").size());
  EXPECT_TRUE(result.at("regions").at("mismatched").empty()) << result.at("regions").dump(1);
}

TEST_F(SnagVerify, ExhaustiveFindsTheOneDroppedEvent) {
  std::vector<json> edited = records_;
  std::size_t drop = edited.size();
  for (std::size_t i : find("event"))
    if (edited[i].at("kind") == "collision") drop = i;
  ASSERT_LT(drop, edited.size()) << "the scan should have a collision";
  const json dropped = edited[drop];
  edited.erase(edited.begin() + static_cast<std::ptrdiff_t>(drop));
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
  // Its region, its frame record and the trailer still count it.
  const json& mismatched = result.at("regions").at("mismatched");
  ASSERT_FALSE(mismatched.empty());
  bool region_named = false;
  for (const json& m : mismatched) region_named |= m.at("region") == dropped.at("region");
  EXPECT_TRUE(region_named) << mismatched.dump(1);
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

  std::vector<json> edited = records_;
  const json added{{"record", "event"},
                   {"kind", "collision"},
                   {"frame", 26},  // reports name frames by the cache's own index
                   {"type", "vf"},
                   {"toi", 26.5},
                   {"toi_interval", {26.5, 26.5}},
                   {"a", {{"object", scene.objects()[0].name}, {"vertex", cloth_vertex}}},
                   {"b", {{"object", scene.objects()[1].name}, {"face", 0}}},
                   {"certainty", "proven"},
                   {"position", {0, 0, 0}},
                   {"region", nullptr}};
  // After frame 26's record, among its events.
  edited.insert(edited.begin() + static_cast<std::ptrdiff_t>(find("frame").at(0)) + 1, added);
  const std::string report = write_report("added.json", edited);
  const ToolRun r = verify(report + " " + kCache + " --json");
  ASSERT_EQ(r.exit_code, 1) << r.out << r.err;
  const json result = json::parse(r.out);
  EXPECT_EQ(result.at("false"), 1);
  EXPECT_EQ(result.at("confirmed"), event_count());
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
  std::vector<json> edited = records_;
  edited.at(0).at("objects")[0].at("name") = "not_the_cloth";
  const ToolRun r = verify(write_report("renamed.json", edited) + " " + kCache);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("not_the_cloth"), std::string::npos) << r.err;
}

TEST_F(SnagVerify, RejectsAnEventWhoseIdIsOutOfRange) {
  std::vector<json> edited = records_;
  json& a = edited.at(find("event").at(0)).at("a");
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

TEST_F(SnagVerify, FailsOnARegionThatDisagreesWithItsEvents) {
  // An intersection region without its first face: some listed event touches it.
  std::vector<json> edited = records_;
  std::size_t at = edited.size();
  for (std::size_t i : find("region"))
    if (edited[i].at("kind") == "intersection" && at == edited.size()) at = i;
  ASSERT_LT(at, edited.size()) << "the scan should have an intersection region";
  json& region = edited[at];
  json& ids = region.at("faces")[0].at("ids");
  const std::size_t face = ids[0];
  ids.erase(ids.begin());
  region.at("face_count") = region.at("face_count").get<std::size_t>() - 1;
  const ToolRun r = verify(write_report("region_faces.json", edited) + " " + kCache + " --json");
  ASSERT_EQ(r.exit_code, 1) << r.out << r.err;
  const json result = json::parse(r.out);
  EXPECT_EQ(result.at("false"), 0) << "the events are right; their region is not";
  const json& mismatched = result.at("regions").at("mismatched");
  ASSERT_FALSE(mismatched.empty());
  EXPECT_EQ(mismatched[0].at("region"), region.at("id"));
  EXPECT_LT(mismatched[0].at("line").get<std::size_t>(), at + 1) << "the line of an event naming the region";
  EXPECT_NE(mismatched[0].at("reason").get<std::string>().find("face " + std::to_string(face)), std::string::npos)
      << mismatched.dump(1);

  const ToolRun text = verify(path("region_faces.json") + " " + kCache);
  EXPECT_EQ(text.exit_code, 1);
  EXPECT_NE(text.out.find(", region " + region.at("id").dump() + ": the event on line "), std::string::npos)
      << text.out;
}

TEST_F(SnagVerify, FailsOnARegionEventCountOrATotalThatDisagrees) {
  std::vector<json> edited = records_;
  json& region = edited.at(find("region").at(0));
  region.at("events") = region.at("events").get<std::size_t>() + 1;
  ToolRun r = verify(write_report("region_count.json", edited) + " " + kCache + " --json");
  ASSERT_EQ(r.exit_code, 1) << r.out << r.err;
  json result = json::parse(r.out);
  ASSERT_EQ(result.at("regions").at("mismatched").size(), 1u) << result.at("regions").dump(1);
  EXPECT_NE(result.at("regions").at("mismatched")[0].at("reason").get<std::string>().find("events"), std::string::npos);

  edited = records_;
  json& summary = edited.back().at("summary");
  summary.at("collisions") = summary.at("collisions").get<std::size_t>() + 1;
  r = verify(write_report("total.json", edited) + " " + kCache + " --json");
  ASSERT_EQ(r.exit_code, 1) << r.out << r.err;
  result = json::parse(r.out);
  ASSERT_FALSE(result.at("regions").at("mismatched").empty());
  const json& m = result.at("regions").at("mismatched")[0];
  EXPECT_TRUE(m.at("region").is_null());
  EXPECT_EQ(m.at("line"), edited.size());
  EXPECT_NE(m.at("reason").get<std::string>().find("collisions"), std::string::npos) << m.dump();
}

TEST_F(SnagVerify, CountsEventsLeftOutOfTheListAsUnlistedNotMissed) {
  // As if the list had been capped: one collision not listed, the trailer says so.
  std::vector<json> edited = records_;
  std::size_t drop = edited.size();
  for (std::size_t i : find("event"))
    if (edited[i].at("kind") == "collision") drop = i;
  ASSERT_LT(drop, edited.size());
  edited.erase(edited.begin() + static_cast<std::ptrdiff_t>(drop));
  json& summary = edited.back().at("summary");
  summary.at("listed") = summary.at("listed").get<std::size_t>() - 1;
  summary.at("left_out") = 1;
  ToolRun r = verify(write_report("capped.json", edited) + " " + kCache + " --exhaustive --json");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  json result = json::parse(r.out);
  EXPECT_FALSE(result.at("complete").get<bool>());
  EXPECT_EQ(result.at("missed"), 0);
  EXPECT_EQ(result.at("unlisted"), 1);
  EXPECT_TRUE(result.at("regions").at("mismatched").empty()) << result.at("regions").dump(1);

  const ToolRun text = verify(path("capped.json") + " " + kCache);
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.out.find("cannot be confirmed"), std::string::npos) << text.out;

  // When the frame record counts fewer than exist, the excess is missed for certain.
  for (json& frame : edited) {
    if (frame.at("record") != "frame" || frame.at("index") != records_[drop].at("frame")) continue;
    const char* type = records_[drop].at("type") == "vf" ? "vf" : "ee";
    frame.at(type) = frame.at(type).get<std::size_t>() - 1;
    frame.at("collisions") = frame.at("collisions").get<std::size_t>() - 1;
  }
  summary.at("events") = summary.at("events").get<std::size_t>() - 1;
  summary.at("collisions") = summary.at("collisions").get<std::size_t>() - 1;
  const char* type = records_[drop].at("type") == "vf" ? "vf" : "ee";
  summary.at(type) = summary.at(type).get<std::size_t>() - 1;
  r = verify(write_report("undercounted.json", edited) + " " + kCache + " --exhaustive --json");
  ASSERT_EQ(r.exit_code, 1) << r.out << r.err;
  result = json::parse(r.out);
  EXPECT_EQ(result.at("missed"), 1);
}

TEST_F(SnagVerify, RejectsAVersion1OrIncompleteReport) {
  const std::string v1 = path("v1.json");
  std::ofstream(v1) << "{\n \"version\": 1,\n \"events\": []\n}\n";
  ToolRun r = verify(v1 + " " + kCache);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("version 1 report; scan the cache again"), std::string::npos) << r.err;

  std::vector<json> edited = records_;
  edited.pop_back();
  r = verify(write_report("no_trailer.json", edited) + " " + kCache);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("incomplete report (no trailer)"), std::string::npos) << r.err;
}

TEST_F(SnagVerify, ChecksEachPairAtTheMeanOfItsObjectsThickness) {
  // The cloth at 2e-3, the body at 0: cloth-body pairs at 1e-3.
  const std::string report = path("thick.json");
  const ToolRun scan = run(SNAG_SCAN_EXE, kCache + " --frames 26:27 -q --fail-on 0 --object-thickness cloth=2e-3 -r " +
                                              report);
  ASSERT_EQ(scan.exit_code, 0) << scan.err;
  const ToolRun r = verify(report + " " + kCache + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const json result = json::parse(r.out);
  EXPECT_GT(result.at("events").get<std::size_t>(), 0u);
  EXPECT_EQ(result.at("confirmed"), result.at("events"));
  EXPECT_EQ(result.at("object_thickness"), json({2e-3, 0.0}));
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
