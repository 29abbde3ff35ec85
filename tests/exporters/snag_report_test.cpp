// snag-report end to end on the bundled sample scanned by snag-scan (frames
// 20 to 27): the summary when no output is named, JUnit files that follow
// Jenkins' schema with a testcase per pair or track, CSV of regions and of
// events that Python's csv module reads back field for field, marked meshes
// read back by snag's own PLY reader with the region faces coloured,
// Markdown, batches of reports, and the exit codes of bad usage and input.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "io/ply_reader.hpp"
#include "tests/tools/report_json.hpp"
#include "tests/tools/run_process.hpp"
#include "tests/tools/sample_paths.hpp"

namespace snag::test {
namespace {

using nlohmann::json;

const std::string kScripts = std::string(SNAG_SOURCE_DIR) + "/tests/exporters/";

ProcessResult snag_report(const std::vector<std::string>& arguments) {
  return run_process(SNAG_REPORT_EXE, arguments);
}

json python_check(const std::string& script, const std::string& file) {
  const ProcessResult result = run_process(SNAG_PYTHON3, {kScripts + script, file});
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  if (result.exit_code != 0) return json::object();
  return json::parse(result.out);
}

/// The sample's cache as snag-report takes it.
std::vector<std::string> cache_options() {
  return {"--cache", kClothPc2, "-t", kClothRest, "--cache", kBodyPc2, "-t", kBodyRest};
}

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

/// The sample scanned once for all tests, frames 20 to 27: both kinds, both pairs.
class SnagReport : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scans_ = new TemporaryDirectory;
    auto scan = [](const std::string& name, const std::vector<std::string>& extra) {
      const std::string path = scans_->path(name);
      const ProcessResult r = run_process(
          SNAG_SCAN_EXE, with(with(sample_pc2_inputs(), {"--frames", "20:27", "-j", "2", "-q", "-r", path}), extra));
      EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.err;
      return path;
    };
    failing_ = new std::string(scan("sample.jsonl", {}));
    passing_ = new std::string(scan("passing.jsonl", {"--fail-on", "0"}));
    report_ = new json(load_report(*failing_));
  }
  static void TearDownTestSuite() {
    delete report_;
    delete failing_;
    delete passing_;
    delete scans_;
  }

  std::string out(const std::string& name) const { return dir_.path(name); }

  static TemporaryDirectory* scans_;
  static std::string* failing_;
  static std::string* passing_;
  static json* report_;
  TemporaryDirectory dir_;
};

TemporaryDirectory* SnagReport::scans_ = nullptr;
std::string* SnagReport::failing_ = nullptr;
std::string* SnagReport::passing_ = nullptr;
json* SnagReport::report_ = nullptr;

TEST_F(SnagReport, PrintsTheSummaryWhenNoOutputIsNamed) {
  const ProcessResult r = snag_report({*failing_});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.out.find("8 frames, 2 objects"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("verdict: FAIL"), std::string::npos) << r.out;
  EXPECT_TRUE(r.err.empty()) << r.err;

  const ProcessResult pass = snag_report({*passing_});
  EXPECT_EQ(pass.exit_code, 0) << pass.err;
  EXPECT_NE(pass.out.find("verdict: pass"), std::string::npos) << pass.out;

  const ProcessResult both = snag_report({*passing_, *failing_});
  EXPECT_EQ(both.exit_code, 1) << "one report fails";
  EXPECT_NE(both.out.find("report: " + *passing_), std::string::npos) << both.out;
}

TEST_F(SnagReport, JunitHasACaseForEveryPairAndKind) {
  const ProcessResult r = snag_report({*failing_, "--junit", out("junit.xml")});
  ASSERT_EQ(r.exit_code, 1) << r.err;
  const json junit = python_check("check_junit.py", out("junit.xml"));
  ASSERT_EQ(junit.at("suites").size(), 1u);
  const json& suite = junit["suites"][0];
  EXPECT_EQ(suite["name"], "snag.sample");
  // cloth self, cloth / body, body self, for collisions and intersections.
  EXPECT_EQ(suite["tests"], 6);
  std::size_t with_events = 0;
  for (const json& p : report_->at("trailer").at("pairs")) with_events += p.at("events").get<std::size_t>() > 0;
  EXPECT_EQ(suite["failures"].get<std::size_t>(), with_events) << "every checked event fails the sample's rules";
  std::map<std::string, const json*> cases;
  for (const json& c : suite["cases"]) cases[c["name"].get<std::string>()] = &c;
  for (const json& p : report_->at("trailer").at("pairs")) {
    const std::string a = p["objects"][0], b = p["objects"][1];
    const std::string name = (a == b ? a + " (self)" : a + " / " + b) + " " + p["kind"].get<std::string>();
    ASSERT_EQ(cases.count(name), 1u) << name;
    const json& failure = (*cases[name])["failure"];
    ASSERT_FALSE(failure.is_null()) << name;
    const std::string message = failure["message"];
    EXPECT_EQ(message.rfind(std::to_string(p["events"].get<std::size_t>()) + " " + p["kind"].get<std::string>(), 0),
              0u)
        << message;
    EXPECT_NE(message.find("largest region"), std::string::npos) << message;
    EXPECT_NE(message.find(" faces "), std::string::npos) << "element ids: " << message;
  }
  EXPECT_TRUE((*cases["body (self) intersection"])["failure"].is_null());
  EXPECT_EQ(suite["properties"]["settings.frames"], "20:27");
}

TEST_F(SnagReport, JunitTracksAndBatches) {
  const ProcessResult r = snag_report({*failing_, *passing_, "--junit", out("junit.xml"), "--junit-granularity",
                                       "track"});
  ASSERT_EQ(r.exit_code, 1) << r.err;
  const json junit = python_check("check_junit.py", out("junit.xml"));
  ASSERT_EQ(junit.at("suites").size(), 2u);
  std::size_t root_tracks = 0;
  std::set<std::string> pairs_with_tracks;
  for (const json& t : report_->at("tracks")) {
    if (!t.at("merged_into").is_null()) continue;
    ++root_tracks;
    pairs_with_tracks.insert(t["objects"].dump() + t["kind"].get<std::string>());
  }
  EXPECT_EQ(root_tracks, report_->at("summary").at("tracks").get<std::size_t>());
  const std::size_t expected = root_tracks + 6 - pairs_with_tracks.size();
  EXPECT_EQ(junit["suites"][0]["tests"].get<std::size_t>(), expected);
  EXPECT_EQ(junit["suites"][0]["failures"].get<std::size_t>(), root_tracks);
  EXPECT_EQ(junit["suites"][1]["tests"].get<std::size_t>(), expected);
  EXPECT_EQ(junit["suites"][1]["failures"], 0) << "the passing report fails no case";
  EXPECT_EQ(junit["suites"][1]["name"], "snag.passing");
}

TEST_F(SnagReport, RegionCsvMatchesTheReport) {
  ASSERT_EQ(snag_report({*failing_, "--csv", out("regions.csv")}).exit_code, 1);
  const json table = python_check("check_csv.py", out("regions.csv"));
  const json& regions = report_->at("regions");
  ASSERT_EQ(table.at("rows").size(), regions.size());
  std::map<std::size_t, std::size_t> merged_into;
  for (const json& t : report_->at("tracks")) {
    if (!t["merged_into"].is_null()) merged_into[t["id"]] = t["merged_into"];
  }
  const json& header = table["header"];
  for (std::size_t i = 0; i < regions.size(); ++i) {
    std::map<std::string, std::string> row;
    for (std::size_t c = 0; c < header.size(); ++c) row[header[c]] = table["rows"][i][c];
    const json& region = regions[i];
    EXPECT_EQ(row["report"], *failing_);
    EXPECT_EQ(row["id"], std::to_string(region["id"].get<std::size_t>()));
    EXPECT_EQ(row["kind"], region["kind"]);
    EXPECT_EQ(row["object_a"], region["objects"][0]);
    EXPECT_EQ(row["object_b"], region["objects"][1]);
    EXPECT_EQ(row["frame"], std::to_string(region["frame"].get<std::size_t>()));
    EXPECT_EQ(row["events"], std::to_string(region["events"].get<std::size_t>()));
    EXPECT_EQ(row["face_count"], std::to_string(region["face_count"].get<std::size_t>()));
    std::size_t track = region["track"];
    while (merged_into.count(track)) track = merged_into[track];
    EXPECT_EQ(row["track"], std::to_string(track));
    EXPECT_EQ(std::stod(row["centroid_x"]), region["centroid"][0].get<double>());
    EXPECT_EQ(std::stod(row["bounds_hi_z"]), region["bounds"][1][2].get<double>());
    if (region["kind"] == "collision") {
      EXPECT_EQ(std::stod(row["toi"]), region["toi"].get<double>());
    } else {
      EXPECT_EQ(row["toi"], "");
    }
  }
}

TEST_F(SnagReport, EventCsvListsTheReportsEvents) {
  ASSERT_EQ(snag_report({*failing_, "--csv", out("events.csv"), "--csv-rows", "events"}).exit_code, 1);
  const json table = python_check("check_csv.py", out("events.csv"));
  const json& events = report_->at("events");
  ASSERT_EQ(table.at("rows").size(), events.size());
  const json& header = table["header"];
  auto column = [&](const std::string& name) {
    for (std::size_t c = 0; c < header.size(); ++c) {
      if (header[c] == name) return c;
    }
    ADD_FAILURE() << name;
    return std::size_t{0};
  };
  const std::size_t kind = column("kind"), frame = column("frame"), a_id = column("a_id"), b_id = column("b_id"),
                    region = column("region"), x = column("position_x"), toi = column("toi");
  for (std::size_t i = 0; i < events.size(); ++i) {
    const json& e = events[i];
    const json& row = table["rows"][i];
    ASSERT_EQ(row[kind], e["kind"]) << i;
    ASSERT_EQ(row[frame], std::to_string(e["frame"].get<std::size_t>())) << i;
    ASSERT_EQ(row[region], e["region"].is_null() ? "" : std::to_string(e["region"].get<std::size_t>())) << i;
    ASSERT_EQ(std::stod(row[x].get<std::string>()), e["position"][0].get<double>()) << i;
    if (e["kind"] == "intersection") {
      ASSERT_EQ(row[a_id], std::to_string(e["a"]["face"].get<std::size_t>())) << i;
      ASSERT_EQ(row[b_id], std::to_string(e["b"]["face"].get<std::size_t>())) << i;
    } else {
      ASSERT_EQ(std::stod(row[toi].get<std::string>()), e["toi"].get<double>()) << i;
    }
  }
}

// Region and colour of each face of a marked PLY (binary layout of write_marked_ply).
std::vector<std::pair<std::int32_t, std::array<unsigned char, 3>>> face_marks(const std::string& bytes,
                                                                              std::size_t vertices,
                                                                              std::size_t faces) {
  std::vector<std::pair<std::int32_t, std::array<unsigned char, 3>>> marks;
  std::size_t at = bytes.find("end_header\n") + 11 + 12 * vertices;
  for (std::size_t f = 0; f < faces && at + 20 <= bytes.size(); ++f, at += 20) {
    std::pair<std::int32_t, std::array<unsigned char, 3>> mark;
    std::memcpy(mark.second.data(), bytes.data() + at + 13, 3);
    std::memcpy(&mark.first, bytes.data() + at + 16, 4);
    marks.push_back(mark);
  }
  return marks;
}

TEST_F(SnagReport, MarkedMeshesColourEveryRegionFaceOfTheWorstFrames) {
  const ProcessResult r =
      snag_report(with({*failing_, "--marked-meshes", out("meshes"), "--worst", "2"}, cache_options()));
  ASSERT_EQ(r.exit_code, 1) << r.err;
  // The two frames with the most checked events.
  std::vector<std::pair<std::size_t, std::size_t>> frames;
  for (const json& f : report_->at("frames")) {
    frames.emplace_back(f["collisions"].get<std::size_t>() + f["intersections"].get<std::size_t>(), f["index"]);
  }
  std::sort(frames.begin(), frames.end(), [](auto x, auto y) { return x.first > y.first || (x.first == y.first && x.second < y.second); });
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(out("meshes"))) files += entry.is_regular_file();
  EXPECT_EQ(files, 2u);
  const std::size_t cloth_faces = 1800;
  for (std::size_t i = 0; i < 2; ++i) {
    const std::size_t frame = frames[i].second;
    const std::string path = out("meshes") + "/sample_frame_" + std::to_string(frame) + ".ply";
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    const io::MeshData mesh = io::read_ply(path);
    EXPECT_EQ(mesh.positions.size(), 961u + 114u);
    ASSERT_EQ(mesh.objects.size(), 1u);
    ASSERT_EQ(mesh.objects[0].triangles.size(), 1800u + 224u);
    // The smallest region id of each global face at this frame, from the report.
    std::map<std::size_t, std::size_t> expected;
    for (const json& region : report_->at("regions")) {
      if (region["frame"] != frame) continue;
      for (const json& side : region["faces"]) {
        const std::size_t offset = side["object"] == "body" ? cloth_faces : 0;
        for (const json& id : side["ids"]) {
          const std::size_t face = offset + id.get<std::size_t>();
          if (!expected.count(face)) expected[face] = region["id"];
        }
      }
    }
    ASSERT_FALSE(expected.empty());
    const auto marks = face_marks(read_file(path), 961 + 114, 1800 + 224);
    ASSERT_EQ(marks.size(), 1800u + 224u);
    std::size_t coloured = 0, grey = 0;
    for (std::size_t f = 0; f < marks.size(); ++f) {
      const auto& [region, colour] = marks[f];
      const bool is_grey = colour[0] == colour[1] && colour[1] == colour[2];
      grey += is_grey;
      coloured += !is_grey;
      if (expected.count(f)) {
        EXPECT_EQ(region, static_cast<std::int32_t>(expected[f])) << "face " << f;
      } else {
        EXPECT_EQ(region, -1) << "face " << f;
      }
    }
    EXPECT_EQ(coloured, expected.size()) << "frame " << frame;
    EXPECT_EQ(grey, marks.size() - expected.size());
  }
}

TEST_F(SnagReport, MarkedMeshesOfChosenFrames) {
  const ProcessResult r =
      snag_report(with({*failing_, "--marked-meshes", out("m"), "--frames", "20,22:23"}, cache_options()));
  ASSERT_EQ(r.exit_code, 1) << r.err;
  for (const char* frame : {"20", "22", "23"}) {
    EXPECT_TRUE(std::filesystem::exists(out("m") + "/sample_frame_" + frame + ".ply")) << frame;
  }
  EXPECT_FALSE(std::filesystem::exists(out("m") + "/sample_frame_21.ply"));
}

TEST_F(SnagReport, MarkdownForAStepSummary) {
  const ProcessResult r = snag_report({*failing_, *passing_, "--markdown", "-"});
  ASSERT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.out.rfind("# snag: FAIL (1 of 2 reports)\n", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("## FAIL: sample"), std::string::npos);
  EXPECT_NE(r.out.find("## pass: passing"), std::string::npos);
  EXPECT_NE(r.out.find("| cloth / body | intersection |"), std::string::npos);
  EXPECT_NE(r.err.find(*failing_ + ": FAIL"), std::string::npos) << "verdicts go to stderr when stdout is taken";
}

// The page's content is html.cpp's to test; here only that snag-report hands it the reports and the cache.
TEST_F(SnagReport, HtmlPageIsWrittenWithAndWithoutTheCache) {
  ProcessResult r = snag_report(with({*failing_, "--html", out("page.html"), "--worst", "1"}, cache_options()));
  ASSERT_EQ(r.exit_code, 1) << r.err;
  std::string page = read_file(out("page.html"));
  EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(page.find("</html>"), std::string::npos);
  r = snag_report({*failing_, *passing_, "--html", out("batch.html")});
  ASSERT_EQ(r.exit_code, 1) << r.err;
  page = read_file(out("batch.html"));
  EXPECT_NE(page.find("</html>"), std::string::npos);
}

TEST_F(SnagReport, BadUsageAndInputExitTwoWithOneLine) {
  // Errors found after parsing are one line; CLI11's own add a line pointing to --help.
  auto expect_error = [](const std::vector<std::string>& arguments, const std::string& words,
                         std::size_t lines = 1) {
    const ProcessResult r = snag_report(arguments);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_EQ(lines_of(r.err).size(), lines) << r.err;
    EXPECT_NE(lines_of(r.err + "\n").front().find(words), std::string::npos) << r.err;
  };
  expect_error({out("missing.jsonl")}, "missing.jsonl");
  const std::string truncated = dir_.write("truncated.jsonl", read_file(*failing_).substr(0, 5000));
  expect_error({truncated}, "truncated.jsonl");
  expect_error({*failing_, "--marked-meshes", out("m")}, "--cache");
  expect_error(with({*failing_, "--marked-meshes", out("m")}, {"--cache", kClothPc2, "-t", kClothRest}),
               *failing_ + ": the --cache inputs are not the cache of this report");
  expect_error(with({*failing_, "--marked-meshes", out("m"), "--frames", "5"}, cache_options()), "frame 5");
  expect_error(with({*failing_, *failing_, "--marked-meshes", out("m")}, cache_options()), "same file names");
  expect_error({*failing_, "--csv-rows", "events"}, "--csv");
  expect_error({*failing_, "--junit", "-", "--csv", "-"}, "standard output");
  expect_error({*failing_, "--junit-granularity", "frame", "--junit", out("j.xml")}, "granularity", 2);
  expect_error({*failing_, "--junit", out("no/such/dir/j.xml")}, "j.xml");
  EXPECT_FALSE(std::filesystem::exists(out("m"))) << "nothing written on bad usage";
}

}  // namespace
}  // namespace snag::test
