// The exporters of snag-report on a hand-made report (hand_made_report.hpp)
// whose every count is known: the digest, JUnit XML checked against the
// structure of Jenkins' schema by Python's xml.etree (check_junit.py), CSV
// read back by Python's csv module (check_csv.py), Markdown, marked PLY
// meshes read back by snag's own PLY reader, and the cache positions of a
// report checked against its header.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "exporters/csv.hpp"
#include "exporters/digest.hpp"
#include "exporters/frame_positions.hpp"
#include "exporters/junit.hpp"
#include "exporters/markdown.hpp"
#include "exporters/marked_ply.hpp"
#include "io/ply_reader.hpp"
#include "libcd/core/error.hpp"
#include "tests/exporters/hand_made_report.hpp"
#include "tests/tools/run_process.hpp"
#include "tests/tools/sample_paths.hpp"

namespace snag::test {
namespace {

using nlohmann::json;
using exporters::ReportDigest;

const std::string kScripts = std::string(SNAG_SOURCE_DIR) + "/tests/exporters/";

/// Runs a checker script on `file` and returns what it printed, parsed.
json python_check(const std::string& script, const std::string& file) {
  const ProcessResult result = run_process(SNAG_PYTHON3, {kScripts + script, file});
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  if (result.exit_code != 0) return json::object();
  return json::parse(result.out);
}

class HandMadeReport : public ::testing::Test {
 protected:
  void SetUp() override { write_hand_made_report(path_); }
  std::string write(const std::string& name, const std::string& text) const { return dir_.write(name, text); }

  TemporaryDirectory dir_;
  const std::string path_ = dir_.path("shot.jsonl");
};

TEST_F(HandMadeReport, DigestKeepsEveryRecordAndResolvesMergedTracks) {
  const ReportDigest digest = exporters::read_digest(path_);
  ASSERT_EQ(digest.frames.size(), 3u);
  ASSERT_EQ(digest.regions.size(), 4u);
  ASSERT_EQ(digest.tracks.size(), 3u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(digest.regions[i].id, i);
    EXPECT_TRUE(digest.regions[i].faces_a.empty()) << "no frame asked for: no face lists";
  }
  std::vector<std::size_t> face_counts;
  for (const report::RegionRecord& r : digest.regions) face_counts.push_back(r.face_count);
  EXPECT_EQ(face_counts, (std::vector<std::size_t>{2, 2, 2, 1}));
  EXPECT_EQ(exporters::root_track_of(digest, 2), 0u);
  EXPECT_EQ(exporters::root_track_of(digest, 0), 0u);
  EXPECT_EQ(exporters::root_track_of(digest, 1), 1u);
  ASSERT_EQ(digest.largest_region.size(), 2u);
  EXPECT_EQ(digest.largest_region.at(0).id, 0u) << "regions 0 and 2 tie at two faces: the earlier id";
  EXPECT_EQ(digest.largest_region.at(0).faces_a, (std::vector<std::size_t>{1, 2}));
  EXPECT_EQ(digest.largest_region.at(1).faces_b, (std::vector<std::size_t>{0}));
  EXPECT_FALSE(digest.trailer.pass);

  const ReportDigest frame_11 = exporters::read_digest(path_, {11});
  EXPECT_TRUE(frame_11.regions[0].faces_a.empty());
  EXPECT_EQ(frame_11.regions[2].faces_a, (std::vector<std::size_t>{2, 4}));
  EXPECT_EQ(frame_11.regions[3].faces_a, (std::vector<std::size_t>{5}));
}

TEST_F(HandMadeReport, WorstFramesHaveTheMostCheckedEvents) {
  const ReportDigest digest = exporters::read_digest(path_);
  EXPECT_EQ(exporters::worst_frames(digest, 5), (std::vector<std::size_t>{10, 11}));
  EXPECT_EQ(exporters::worst_frames(digest, 1), (std::vector<std::size_t>{10}));
  EXPECT_TRUE(exporters::worst_frames(digest, 0).empty());
}

TEST_F(HandMadeReport, CheckedPairsFollowTheRulesAndOnlyCountedKindsFail) {
  const ReportDigest digest = exporters::read_digest(path_);
  const std::vector<report::PairSummary> pairs = exporters::checked_pairs(digest);
  ASSERT_EQ(pairs.size(), 6u) << "2 kinds x (cape self, cape / body, body self)";
  std::size_t failing = 0;
  for (const report::PairSummary& p : pairs) {
    if (exporters::pair_fails(digest.trailer, p)) {
      ++failing;
      EXPECT_EQ(p.kind, EventKind::kCollision);
      EXPECT_EQ(p.object_a, 0u);
      EXPECT_EQ(p.object_b, 0u);
      EXPECT_EQ(p.events, 4u);
    }
  }
  EXPECT_EQ(failing, 1u) << "the verdict failed on collisions: the intersections pass";
  EXPECT_EQ(exporters::pair_label(digest.header, 0, 1), kCape + " / " + kBody);
  EXPECT_EQ(exporters::pair_label(digest.header, 1, 1), kBody + " (self)");
}

TEST(HandMadeReportWithoutFaces, ExportersWorkWithoutRegionFaceLists) {
  TemporaryDirectory dir;
  const std::string path = dir.path("bare.jsonl");
  write_hand_made_report(path, "none");
  const ReportDigest digest = exporters::read_digest(path, {}, true);
  ASSERT_EQ(digest.regions.size(), 4u);
  EXPECT_TRUE(digest.regions[0].faces_a.empty());
  std::vector<std::size_t> face_counts;
  for (const report::RegionRecord& r : digest.regions) face_counts.push_back(r.face_count);
  EXPECT_EQ(face_counts, (std::vector<std::size_t>{2, 2, 2, 1})) << "the count stays without the lists";
  std::ostringstream xml;
  exporters::write_junit(xml, {digest}, exporters::JunitGranularity::kPair);
  const json junit = python_check("check_junit.py", dir.write("junit.xml", xml.str()));
  EXPECT_EQ(junit["failures"], 1);
}

TEST(ReportStem, DropsDirectoryAndReportExtension) {
  EXPECT_EQ(exporters::report_stem("runs/shot.v2.jsonl"), "shot.v2");
  EXPECT_EQ(exporters::report_stem("a.json"), "a");
  EXPECT_EQ(exporters::report_stem("plain"), "plain");
  EXPECT_EQ(exporters::report_stem("-"), "stdin");
}

TEST_F(HandMadeReport, JunitPairCasesFollowJenkinsSchema) {
  std::ostringstream xml;
  exporters::write_junit(xml, {exporters::read_digest(path_)}, exporters::JunitGranularity::kPair);
  const json junit = python_check("check_junit.py", write("junit.xml", xml.str()));
  ASSERT_EQ(junit.at("suites").size(), 1u);
  EXPECT_EQ(junit["tests"], 6);
  EXPECT_EQ(junit["failures"], 1);
  const json& suite = junit["suites"][0];
  EXPECT_EQ(suite["name"], "snag.shot");
  EXPECT_EQ(suite["properties"]["verdict"], "FAIL: collisions 4 >= 1");
  EXPECT_EQ(suite["properties"]["settings.frames"], "10:12");
  std::set<std::string> names;
  for (const json& c : suite["cases"]) {
    names.insert(c["name"].get<std::string>());
    EXPECT_EQ(c["classname"], "snag.shot");
    if (c["name"] == kCape + " (self) collision") {
      ASSERT_FALSE(c["failure"].is_null());
      const std::string message = c["failure"]["message"];
      EXPECT_NE(message.find("4 collisions in 2 frames"), std::string::npos) << message;
      EXPECT_NE(message.find("region 0 at frame 10"), std::string::npos) << message;
      EXPECT_NE(message.find(kCape + " faces 1 2"), std::string::npos) << message;
      EXPECT_NE(message.find("1 allowed"), std::string::npos) << message;
      EXPECT_EQ(c["failure"]["type"], "snag.collision");
      EXPECT_NE(c["failure"]["text"].get<std::string>().find("track 0: frames 10-11"), std::string::npos);
    } else {
      EXPECT_TRUE(c["failure"].is_null()) << c["name"];
    }
    if (c["name"] == kCape + " / " + kBody + " intersection") {
      EXPECT_NE(c["out"].get<std::string>().find("not over the report's thresholds"), std::string::npos);
    }
  }
  EXPECT_EQ(names, (std::set<std::string>{kCape + " (self) collision", kCape + " / " + kBody + " collision",
                                          kBody + " (self) collision", kCape + " (self) intersection",
                                          kCape + " / " + kBody + " intersection", kBody + " (self) intersection"}));
}

TEST_F(HandMadeReport, JunitTrackCasesNameEachTrackThatDidNotMerge) {
  std::ostringstream xml;
  const ReportDigest digest = exporters::read_digest(path_);
  exporters::write_junit(xml, {digest, digest}, exporters::JunitGranularity::kTrack);
  const json junit = python_check("check_junit.py", write("junit.xml", xml.str()));
  ASSERT_EQ(junit.at("suites").size(), 2u) << "a testsuite per report";
  EXPECT_EQ(junit["tests"], 12);
  EXPECT_EQ(junit["failures"], 2);
  std::set<std::string> names;
  for (const json& c : junit["suites"][0]["cases"]) names.insert(c["name"].get<std::string>());
  EXPECT_EQ(names.count(kCape + " (self) collision track 0"), 1u);
  EXPECT_EQ(names.count(kCape + " / " + kBody + " intersection track 1"), 1u);
  EXPECT_EQ(names.count(kCape + " (self) collision track 2"), 0u) << "track 2 merged into track 0";
  EXPECT_EQ(names.count(kBody + " (self) collision"), 1u) << "pairs without tracks stay as pair cases";
}

TEST_F(HandMadeReport, RegionCsvQuotesNamesAndKeepsExactNumbers) {
  std::ostringstream csv;
  exporters::write_region_csv(csv, {exporters::read_digest(path_)});
  const json table = python_check("check_csv.py", write("regions.csv", csv.str()));
  ASSERT_EQ(table.at("rows").size(), 4u);
  const json& header = table["header"];
  auto column = [&](const std::string& name) {
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return i;
    }
    ADD_FAILURE() << "no column " << name;
    return std::size_t{0};
  };
  const json& rows = table["rows"];
  EXPECT_EQ(rows[0][column("report")], path_);
  EXPECT_EQ(rows[0][column("object_a")], kCape);
  EXPECT_EQ(rows[1][column("object_b")], kBody);
  EXPECT_EQ(rows[1][column("kind")], "intersection");
  EXPECT_EQ(rows[1][column("toi")], "") << "intersections have no time of impact";
  EXPECT_EQ(std::stod(rows[0][column("toi")].get<std::string>()), 10.25);
  EXPECT_EQ(rows[3][column("track")], "0") << "region 3's track 2 merged into track 0";
  EXPECT_EQ(rows[2][column("face_count")], "2");
  EXPECT_EQ(std::stod(rows[2][column("centroid_y")].get<std::string>()), 1.0 / 3.0) << "round trip";
  EXPECT_EQ(std::stod(rows[2][column("centroid_z")].get<std::string>()), -2.5e-7);
  EXPECT_EQ(std::stod(rows[3][column("bounds_lo_x")].get<std::string>()), 0.1 * 3);
}

TEST_F(HandMadeReport, EventCsvListsEveryEventRecord) {
  std::ostringstream csv;
  exporters::write_event_csv(csv, {path_, path_});
  const json table = python_check("check_csv.py", write("events.csv", csv.str()));
  const json& rows = table.at("rows");
  ASSERT_EQ(rows.size(), 12u) << "6 event records, twice";
  const json& header = table["header"];
  auto at = [&](const json& row, const std::string& name) {
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return row[i].get<std::string>();
    }
    ADD_FAILURE() << "no column " << name;
    return std::string();
  };
  EXPECT_EQ(at(rows[0], "type"), "vf");
  EXPECT_EQ(at(rows[0], "a_element"), "vertex");
  EXPECT_EQ(at(rows[0], "b_element"), "face");
  EXPECT_EQ(at(rows[0], "b_id"), "1");
  EXPECT_EQ(at(rows[0], "region"), "0");
  EXPECT_EQ(at(rows[0], "certainty"), "proven");
  EXPECT_EQ(at(rows[2], "region"), "") << "allowed";
  EXPECT_EQ(at(rows[2], "allowed"), "0");
  EXPECT_EQ(at(rows[3], "kind"), "intersection");
  EXPECT_EQ(at(rows[3], "type"), "");
  EXPECT_EQ(at(rows[3], "object_b"), kBody);
  EXPECT_EQ(std::stod(at(rows[3], "position_x")), 0.125);
  EXPECT_EQ(std::stod(at(rows[1], "toi")), 10.25);
}

TEST_F(HandMadeReport, MarkdownTableHasARowPerPairAndKind) {
  std::ostringstream md;
  exporters::write_markdown(md, {exporters::read_digest(path_)});
  const std::string text = md.str();
  EXPECT_EQ(text.rfind("# snag: FAIL\n", 0), 0u) << text;
  EXPECT_NE(text.find("**Verdict: FAIL: collisions 4 \\>= 1**"), std::string::npos) << text;
  EXPECT_NE(text.find("| cape, \"hero\" (self) | collision | 4 | 3 | 1 | 2 | 10 (2 events) | 1 | FAIL |"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("| cape, \"hero\" / body\\<1\\>& | intersection | 1 | 1 | 1 | 1 | 10 (1 events) | 0 | pass |"),
            std::string::npos)
      << text;
  std::size_t table_lines = 0;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) table_lines += line.rfind("| ", 0) == 0;
  EXPECT_EQ(table_lines, 1u + 6u + 1u + 2u) << "pair table with its header, tracks table with its header";
}

// Face records of a marked PLY as write_marked_ply lays them out: count, three ids, colour, region.
struct MarkedFace {
  std::array<unsigned char, 3> colour;
  std::int32_t region;
};

std::vector<MarkedFace> marked_faces(const std::string& bytes, std::size_t vertices, std::size_t faces) {
  const std::size_t body = bytes.find("end_header\n") + 11;
  std::vector<MarkedFace> marked;
  std::size_t at = body + 12 * vertices;
  for (std::size_t f = 0; f < faces; ++f, at += 20) {
    EXPECT_EQ(bytes[at], 3);
    MarkedFace face;
    std::memcpy(face.colour.data(), bytes.data() + at + 13, 3);
    std::memcpy(&face.region, bytes.data() + at + 16, 4);
    marked.push_back(face);
  }
  EXPECT_EQ(at, bytes.size());
  return marked;
}

TEST_F(HandMadeReport, MarkedPlyReadsBackWithRegionsColoured) {
  const ReportDigest digest = exporters::read_digest(path_, {11});
  std::vector<Object> objects;
  objects.push_back(make_object(kCape, 6, {{0, 1, 2}, {1, 2, 3}, {2, 3, 4}, {3, 4, 5}, {0, 2, 4}, {1, 3, 5}}));
  objects.push_back(make_object(kBody, 4, {{0, 1, 2}, {1, 2, 3}}));
  const Scene scene(std::move(objects));
  std::vector<Vec3> positions;
  for (std::size_t v = 0; v < 10; ++v) positions.push_back({0.5 * v, -0.25 * v, 2.0});

  const std::vector<std::size_t> regions = exporters::face_regions(digest, scene, 11);
  std::ostringstream ply;
  exporters::write_marked_ply(ply, scene, positions, regions, "test");
  const std::string bytes = ply.str();

  const io::MeshData mesh = io::parse_ply(bytes, "marked.ply");
  ASSERT_EQ(mesh.positions.size(), 10u);
  for (std::size_t v = 0; v < 10; ++v) {
    EXPECT_EQ(mesh.positions[v].x, positions[v].x);
    EXPECT_EQ(mesh.positions[v].y, positions[v].y);
  }
  ASSERT_EQ(mesh.objects.size(), 1u);
  ASSERT_EQ(mesh.objects[0].triangles.size(), 8u);
  EXPECT_EQ(mesh.objects[0].triangles[6], (Triangle{6, 7, 8})) << "body's faces after cape's, global vertex ids";

  const std::vector<MarkedFace> faces = marked_faces(bytes, 10, 8);
  const std::vector<std::int32_t> expected{-1, -1, 2, -1, 2, 3, -1, -1};  // frame 11: faces 2 4 (region 2), 5 (3)
  for (std::size_t f = 0; f < 8; ++f) {
    EXPECT_EQ(faces[f].region, expected[f]) << "face " << f;
    const auto colour = expected[f] < 0 ? exporters::kUnmarkedColour : exporters::region_colour(expected[f]);
    EXPECT_EQ(faces[f].colour, colour) << "face " << f;
  }
}

TEST(RegionColour, DistinctAndNeverGrey) {
  std::set<std::array<unsigned char, 3>> colours;
  for (std::size_t id = 0; id < 64; ++id) {
    const auto c = exporters::region_colour(id);
    colours.insert(c);
    EXPECT_NE(c, exporters::kUnmarkedColour);
    const int spread = std::max({c[0], c[1], c[2]}) - std::min({c[0], c[1], c[2]});
    EXPECT_GT(spread, 100) << "region " << id << " is too grey";
  }
  EXPECT_EQ(colours.size(), 64u);
}

// A digest whose header describes the sample scanned at frames 20 to 27.
ReportDigest sample_digest() {
  ReportDigest digest;
  digest.path = "sample.jsonl";
  digest.header.objects = {{"cloth", 961, 961, 1800, 2760, "none", 0}, {"body", 114, 114, 224, 336, "none", 0}};
  digest.header.frame_count = 8;
  digest.header.settings.frames = "20:27";
  return digest;
}

io::CacheOptions sample_cache(bool with_body) {
  io::CacheOptions options;
  options.inputs.push_back({kClothPc2, kClothRest, "", {}});
  if (with_body) options.inputs.push_back({kBodyPc2, kBodyRest, "", {}});
  options.frames = io::parse_frame_selection("0:1");  // replaced by the report's
  return options;
}

TEST(FramePositions, OpensTheCacheWithTheReportsFrames) {
  const exporters::FramePositions positions(sample_digest(), sample_cache(true));
  EXPECT_EQ(positions.scene().vertex_count(), 961u + 114u);
  EXPECT_TRUE(positions.has_frame(20));
  EXPECT_TRUE(positions.has_frame(27));
  EXPECT_FALSE(positions.has_frame(19));
  const auto frames = positions.positions(std::set<std::size_t>{21, 25});
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames.at(25).size(), 961u + 114u);
  EXPECT_NE(frames.at(21)[0].x, frames.at(25)[0].x);
  EXPECT_THROW(positions.positions(std::size_t{28}), UsageError);
}

TEST(FramePositions, RefusesACacheThatIsNotTheReports) {
  try {
    exporters::FramePositions positions(sample_digest(), sample_cache(false));
    FAIL() << "one object where the report has two";
  } catch (const InputError& error) {
    EXPECT_EQ(error.where().file, "sample.jsonl");
    EXPECT_NE(std::string(error.what()).find("1 objects, the report 2"), std::string::npos) << error.what();
  }
  ReportDigest renamed = sample_digest();
  renamed.header.objects[1].name = "ball";
  EXPECT_THROW(exporters::FramePositions(renamed, sample_cache(true)), InputError);
  ReportDigest other_frames = sample_digest();
  other_frames.header.frame_count = 9;
  EXPECT_THROW(exporters::FramePositions(other_frames, sample_cache(true)), InputError);
  EXPECT_THROW(exporters::FramePositions(sample_digest(), io::CacheOptions{}), UsageError);
}

}  // namespace
}  // namespace snag::test
