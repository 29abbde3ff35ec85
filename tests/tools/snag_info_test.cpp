// snag-info end to end: the sample cache read in every supported way gives the
// counts of samples/README.md, --json has the keys man/snag-info.1 documents,
// and every malformed input ends with exit code 2 and one line on standard
// error that names the file and the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/tools/run_process.hpp"
#include "tests/tools/sample_paths.hpp"

namespace snag::test {
namespace {

using nlohmann::json;

ProcessResult snag_info(const std::vector<std::string>& arguments) { return run_process(SNAG_INFO_EXE, arguments); }

json info_json(std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), "--json");
  const ProcessResult result = snag_info(arguments);
  EXPECT_EQ(result.exit_code, 0) << result.err;
  return json::parse(result.out);
}

/// The sample's two objects with the counts of samples/README.md (edges:
/// cloth 30·31·2 + 30·30 diagonals, body 3·224/2), and its 40 frames.
void expect_sample_counts(const json& info) {
  ASSERT_EQ(info.at("objects").size(), 2u) << info.dump(1);
  const json& cloth = info["objects"][0];
  const json& body = info["objects"][1];
  EXPECT_EQ(cloth.at("vertices"), 961);
  EXPECT_EQ(cloth.at("triangles"), 1800);
  EXPECT_EQ(cloth.at("edges"), 2760);
  EXPECT_EQ(body.at("vertices"), 114);
  EXPECT_EQ(body.at("triangles"), 224);
  EXPECT_EQ(body.at("edges"), 336);
  EXPECT_EQ(info.at("frames"), 40);
}

TEST(SnagInfo, ObjSequenceByPatternGivesSampleCounts) {
  const json info = info_json({kObjPattern});
  expect_sample_counts(info);
  EXPECT_EQ(info["objects"][0]["name"], "cloth");
  EXPECT_EQ(info["objects"][1]["name"], "body");
}

TEST(SnagInfo, ObjSequenceByGlobGivesSampleCounts) { expect_sample_counts(info_json({kObjGlob})); }

TEST(SnagInfo, ObjSequenceByDirectoryGivesSampleCounts) { expect_sample_counts(info_json({kObjSequenceDir})); }

TEST(SnagInfo, TwoPointCachesWithTopologyGiveSampleCounts) { expect_sample_counts(info_json(sample_pc2_inputs())); }

TEST(SnagInfo, PointCachesAndObjSequenceAgreeOnBoundsAndStatistics) {
  // The OBJ sequence holds the PC2 values bit for bit (samples/README.md), so
  // everything computed from the positions is identical.
  json from_pc2 = info_json(sample_pc2_inputs());
  json from_obj = info_json({kObjPattern});
  for (const char* key : {"bounds", "triangle_sphere_radius", "virtual_subdivision", "max_displacement"}) {
    EXPECT_EQ(from_pc2.at(key), from_obj.at(key)) << key;
  }
}

TEST(SnagInfo, JsonHasTheDocumentedKeys) {
  const json info = info_json({kObjPattern});
  for (const char* key : {"version", "source", "objects", "frames", "time_range", "bounds", "triangle_sphere_radius",
                          "virtual_subdivision", "max_displacement"}) {
    EXPECT_TRUE(info.contains(key)) << key;
  }
  for (const json& object : info["objects"]) {
    for (const char* key : {"name", "vertices", "triangles", "edges", "boundary_edges", "non_manifold_edges",
                            "degenerate_triangles"}) {
      EXPECT_TRUE(object.contains(key)) << key;
    }
  }
  for (const char* key : {"min", "max"}) EXPECT_TRUE(info["bounds"].contains(key)) << key;
  for (const char* key : {"min", "mean", "max"}) EXPECT_TRUE(info["triangle_sphere_radius"].contains(key)) << key;
  for (const char* key : {"lambda", "cell_size", "subdivided_triangles", "levels"}) {
    EXPECT_TRUE(info["virtual_subdivision"].contains(key)) << key;
  }
  for (const char* key : {"over_cell_size", "frame", "vertex"}) {
    EXPECT_TRUE(info["max_displacement"].contains(key)) << key;
  }
  // Consistency of what the keys hold: a closed 31 x 31 grid has 120 boundary
  // edges; the UV sphere is closed; the radii are ordered.
  EXPECT_EQ(info["objects"][0]["boundary_edges"], 120);
  EXPECT_EQ(info["objects"][1]["boundary_edges"], 0);
  const json& radius = info["triangle_sphere_radius"];
  EXPECT_LE(radius["min"].get<double>(), radius["mean"].get<double>());
  EXPECT_LE(radius["mean"].get<double>(), radius["max"].get<double>());
  EXPECT_GT(radius["min"].get<double>(), 0.0);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(info["bounds"]["min"][k].get<double>(), info["bounds"]["max"][k].get<double>());
  }
}

TEST(SnagInfo, FrameSelectionEveryThirdOfTheFirstTenGivesFourFrames) {
  const json info = info_json({"--frames", "0:9:3", kObjPattern});
  EXPECT_EQ(info.at("frames"), 4);
  const json pc2 = info_json({"--frames", "0:9:3", kClothPc2, "-t", kClothRest});
  EXPECT_EQ(pc2.at("frames"), 4);
}

TEST(SnagInfo, HumanSummaryNamesObjectsAndCounts) {
  const ProcessResult result = snag_info({kObjPattern});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("cloth"), std::string::npos);
  EXPECT_NE(result.out.find("961 vertices"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("40"), std::string::npos);
}

// --- malformed inputs ---------------------------------------------------------

/// Exit code 2, nothing on standard output, and exactly one line on standard
/// error that holds every one of `needles` (the file, the problem).
void expect_one_line_error(const ProcessResult& result, const std::vector<std::string>& needles) {
  EXPECT_EQ(result.exit_code, 2) << result.err;
  const std::vector<std::string> lines = lines_of(result.err);
  ASSERT_EQ(lines.size(), 1u) << "standard error:\n" << result.err;
  for (const std::string& needle : needles) {
    EXPECT_NE(lines[0].find(needle), std::string::npos) << "'" << needle << "' missing from: " << lines[0];
  }
  EXPECT_TRUE(result.out.empty()) << result.out;
}

/// A small valid OBJ: a unit square in two triangles.
const char* const kSquareObj =
    "v 0 0 0\n"
    "v 1 0 0\n"
    "v 1 1 0\n"
    "v 0 1 0\n"
    "f 1 2 3\n"
    "f 1 3 4\n";

TEST(SnagInfoRejects, MissingFile) {
  TemporaryDirectory dir;
  const std::string missing = dir.path("no_such_cloth.obj");
  expect_one_line_error(snag_info({missing}), {"no_such_cloth.obj", "no such file"});
}

TEST(SnagInfoRejects, UnknownExtension) {
  TemporaryDirectory dir;
  const std::string file = dir.write("cloth.xyz123", "v 0 0 0\n");
  expect_one_line_error(snag_info({file}), {"cloth.xyz123", "unknown"});
}

TEST(SnagInfoRejects, TruncatedPc2) {
  TemporaryDirectory dir;
  std::string bytes = read_file(kBodyPc2);
  bytes.resize(bytes.size() / 2 + 5);  // mid-frame, mid-float
  const std::string file = dir.write("truncated.pc2", bytes);
  expect_one_line_error(snag_info({file, "-t", kBodyRest}), {"truncated.pc2", "truncated"});
}

TEST(SnagInfoRejects, Pc2HeaderShorterThan32Bytes) {
  TemporaryDirectory dir;
  const std::string file = dir.write("short.pc2", read_file(kBodyPc2).substr(0, 20));
  expect_one_line_error(snag_info({file, "-t", kBodyRest}), {"short.pc2", "truncated"});
}

TEST(SnagInfoRejects, Pc2WhosePointCountDisagreesWithTheTopology) {
  // body.pc2 has 114 points; cloth_rest.obj has 961 vertices.
  const ProcessResult result = snag_info({kBodyPc2, "-t", kClothRest});
  expect_one_line_error(result, {"body.pc2", "114", "961"});
}

TEST(SnagInfoRejects, ObjWithOutOfRangeIndexNamesTheLine) {
  TemporaryDirectory dir;
  const std::string file = dir.write("bad_index.obj",
                                     "# three vertices\n"
                                     "v 0 0 0\n"
                                     "v 1 0 0\n"
                                     "v 0 1 0\n"
                                     "f 1 2 3\n"
                                     "f 1 2 7\n");
  expect_one_line_error(snag_info({file}), {"bad_index.obj:6", "out of range"});
}

TEST(SnagInfoRejects, ObjWithNanCoordinate) {
  TemporaryDirectory dir;
  const std::string file = dir.write("nan.obj",
                                     "v 0 0 0\n"
                                     "v 1 nan 0\n"
                                     "v 0 1 0\n"
                                     "f 1 2 3\n");
  expect_one_line_error(snag_info({file}), {"nan.obj:2"});
}

TEST(SnagInfoRejects, Pc2WithNanCoordinateNamesTheFrame) {
  TemporaryDirectory dir;
  std::string bytes = read_file(kBodyPc2);
  // Header 32 bytes, then 114 points x 3 floats per frame: put a NaN in frame 3.
  const std::size_t offset = 32 + (3 * 114 + 10) * 3 * sizeof(float) + sizeof(float);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&bytes[offset], &nan, sizeof nan);
  const std::string file = dir.write("nan.pc2", bytes);
  expect_one_line_error(snag_info({file, "-t", kBodyRest}), {"nan.pc2", "not finite", "frame 3"});
}

TEST(SnagInfoRejects, ObjWithoutFaces) {
  TemporaryDirectory dir;
  const std::string file = dir.write("empty.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expect_one_line_error(snag_info({file}), {"empty.obj", "empty"});
}

TEST(SnagInfoRejects, EmptyObjFile) {
  TemporaryDirectory dir;
  const std::string file = dir.write("nothing.obj", "");
  expect_one_line_error(snag_info({file}), {"nothing.obj", "empty"});
}

TEST(SnagInfoRejects, ObjSequenceWhoseTopologyChangesNamesTheFrame) {
  TemporaryDirectory dir;
  dir.write("seq/shape_0001.obj", kSquareObj);
  dir.write("seq/shape_0002.obj", kSquareObj);
  dir.write("seq/shape_0003.obj",
            "v 0 0 0\n"
            "v 1 0 0\n"
            "v 1 1 0\n"
            "v 0 1 0\n"
            "f 1 2 4\n"
            "f 2 3 4\n");
  const ProcessResult result = snag_info({dir.path("seq/shape_%04d.obj")});
  // The third file is frame 2 (0-based).
  expect_one_line_error(result, {"shape_0003.obj", "frame 2"});
}

TEST(SnagInfoRejects, ObjSequenceWhoseVertexCountChanges) {
  TemporaryDirectory dir;
  dir.write("seq/shape_0001.obj", kSquareObj);
  dir.write("seq/shape_0002.obj", std::string(kSquareObj) + "v 2 2 2\n");
  const ProcessResult result = snag_info({dir.path("seq")});
  expect_one_line_error(result, {"shape_0002.obj", "frame 1", "vertices"});
}

TEST(SnagInfoRejects, BadFrameSelections) {
  for (const char* frames : {"abc", "5:2", "0:9:0", "-1:3", "1:2:3:4"}) {
    SCOPED_TRACE(frames);
    const ProcessResult result = snag_info({"--frames", frames, kObjPattern});
    expect_one_line_error(result, {"frame selection", frames});
  }
}

TEST(SnagInfoRejects, FrameSelectionPastTheEnd) {
  const ProcessResult result = snag_info({"--frames", "50:60", kObjPattern});
  EXPECT_EQ(result.exit_code, 2) << result.err;
  EXPECT_EQ(lines_of(result.err).size(), 1u) << result.err;
}

TEST(SnagInfoRejects, PointCacheWithoutTopology) {
  const ProcessResult result = snag_info({kBodyPc2});
  expect_one_line_error(result, {"body.pc2", "topology"});
}

TEST(SnagInfoRejects, UnknownOption) {
  const ProcessResult result = snag_info({"--no-such-option", kObjPattern});
  EXPECT_EQ(result.exit_code, 2) << result.err;
  EXPECT_NE(result.err.find("no-such-option"), std::string::npos) << result.err;
}

TEST(SnagInfoRejects, NoInput) {
  const ProcessResult result = snag_info({});
  EXPECT_EQ(result.exit_code, 2) << result.err;
}

TEST(SnagInfoRejects, LambdaOutOfRange) {
  const ProcessResult result = snag_info({"--lambda", "0.5", kObjPattern});
  EXPECT_EQ(result.exit_code, 2) << result.err;
}

}  // namespace
}  // namespace snag::test
