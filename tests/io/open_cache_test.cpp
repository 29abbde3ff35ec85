#include "io/open_cache.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "test_files.hpp"

namespace snag::io {
namespace {

using testing::expect_input_error;

/// A one-triangle OBJ whose first x is `x`, so each frame is recognisable.
std::string triangle_obj(double x, const std::string& object = "") {
  std::string text = object.empty() ? "" : "o " + object + "\n";
  return text + "v " + std::to_string(x) + " 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n";
}

std::vector<double> first_xs(const FrameSource& source) {
  std::vector<double> xs;
  std::vector<Vec3> positions;
  for (std::size_t i = 0; i < source.frame_count(); ++i) {
    source.read_frame(i, positions);
    xs.push_back(positions.at(0).x);
  }
  return xs;
}

CacheOptions one_input(const std::string& path, const std::string& name = "") {
  CacheOptions options;
  options.inputs.push_back({path, "", name});
  return options;
}

TEST(OpenCache, ReadsSequenceByPrintfPattern) {
  testing::TempDir dir;
  dir.write("cloth_0010.obj", triangle_obj(10));
  dir.write("cloth_0009.obj", triangle_obj(9));
  dir.write("cloth_0011.obj", triangle_obj(11));
  dir.write("cloth_1.obj", triangle_obj(-1));       // not "%04d"
  dir.write("cloth_00012.obj", triangle_obj(-1));   // not "%04d" either
  dir.write("cloth_0013.obj.bak", triangle_obj(-1));
  const auto source = open_cache(one_input(dir.path("cloth_%04d.obj")));
  EXPECT_EQ(first_xs(*source), (std::vector<double>{9, 10, 11}));
  EXPECT_EQ(source->frame_time(0), 9.0);
  EXPECT_EQ(source->scene().objects().at(0).name, "cloth");
}

TEST(OpenCache, ReadsSequenceByGlobInNaturalOrder) {
  testing::TempDir dir;
  for (int frame : {1, 2, 9, 10, 11}) dir.write("f_" + std::to_string(frame) + ".obj", triangle_obj(frame));
  const auto source = open_cache(one_input(dir.path("f_*.obj")));
  EXPECT_EQ(first_xs(*source), (std::vector<double>{1, 2, 9, 10, 11}));
  EXPECT_EQ(source->frame_time(4), 11.0);
}

TEST(OpenCache, ReadsSequenceFromDirectory) {
  testing::TempDir dir;
  for (int frame : {3, 20, 100}) dir.write("s" + std::to_string(frame) + ".obj", triangle_obj(frame, "Cloth"));
  dir.write("notes.txt", "not a mesh");
  const auto source = open_cache(one_input(dir.path("")));
  EXPECT_EQ(first_xs(*source), (std::vector<double>{3, 20, 100}));
  EXPECT_EQ(source->scene().objects().at(0).name, "Cloth");
}

TEST(OpenCache, RejectsDirectoryWithSeveralFormats) {
  testing::TempDir dir;
  dir.write("a1.obj", triangle_obj(1));
  dir.write("a2.stl", "solid x\nendsolid x\n");
  expect_input_error([&] { open_cache(one_input(dir.path(""))); }, "several formats (.obj, .stl)");
}

TEST(OpenCache, StreamsOneFilePerFrame) {
  testing::TempDir dir;
  for (int frame : {1, 2, 3}) dir.write("c" + std::to_string(frame) + ".obj", triangle_obj(frame));
  const auto source = open_cache(one_input(dir.path("c%d.obj")));
  std::filesystem::remove(dir.path("c2.obj"));  // only frame 1's read needs it
  std::vector<Vec3> positions;
  source->read_frame(2, positions);
  EXPECT_EQ(positions[0].x, 3.0);
  expect_input_error([&] { source->read_frame(1, positions); }, "c2.obj: no such file");
}

TEST(OpenCache, GivesFrameZeroFromTheReadThatGaveTheTopology) {
  testing::TempDir dir;
  for (int frame : {1, 2}) dir.write("c" + std::to_string(frame) + ".obj", triangle_obj(frame));
  const auto source = open_cache(one_input(dir.path("c%d.obj")));
  std::filesystem::remove(dir.path("c1.obj"));  // not read again
  EXPECT_EQ(first_xs(*source), (std::vector<double>{1, 2}));
}

TEST(OpenCache, RejectsTopologyChangeNamingFrameAndDifference) {
  testing::TempDir dir;
  dir.write("m0.obj", triangle_obj(0));
  dir.write("m1.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\nf 1 2 4\n");
  dir.write("m2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 1\n");
  dir.write("m3.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const auto source = open_cache(one_input(dir.path("m%d.obj")));
  std::vector<Vec3> positions;
  expect_input_error([&] { source->read_frame(1, positions); }, "m1.obj: frame 1: 3 triangles, expected 2");
  expect_input_error([&] { source->read_frame(2, positions); }, "m2.obj: frame 2: triangle 1 is (1,3,0), expected (1,3,2)");
  expect_input_error([&] { source->read_frame(3, positions); }, "m3.obj: frame 3: 3 vertices, expected 4");
}

/// A binary big-endian PLY square (two triangles) whose first x is `x` and
/// whose second face is (`a`, `b`, `c`).
std::string square_ply(float x, std::int32_t a = 1, std::int32_t b = 3, std::int32_t c = 2) {
  std::string bytes =
      "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
  for (float value : {x, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 1.f, 1.f, 0.25f})
    testing::put<float>(bytes, value, true);
  for (const auto& face : {std::array<std::int32_t, 3>{0, 1, 2}, std::array<std::int32_t, 3>{a, b, c}}) {
    testing::put<std::uint8_t>(bytes, 3);
    for (std::int32_t id : face) testing::put<std::int32_t>(bytes, id, true);
  }
  return bytes;
}

// Frames of a binary PLY sequence like the first but for their coordinates
// are read from their coordinates alone; the others still have their
// topology checked and their coordinates' faults named.
TEST(OpenCache, ReadsBinaryPlySequencesLikeTheirFullParse) {
  testing::TempDir dir;
  for (int frame : {0, 1, 2}) dir.write("p" + std::to_string(frame) + ".ply", square_ply(0.5f + frame));
  dir.write("p3.ply", square_ply(7, 1, 3, 0));
  dir.write("p4.ply", square_ply(std::numeric_limits<float>::quiet_NaN()));
  std::string longer = square_ply(8);
  longer.replace(longer.find("end_header"), 0, "comment another tool\n");
  dir.write("p5.ply", longer);
  const auto source = open_cache(one_input(dir.path("p%d.ply")));
  std::vector<Vec3> positions;
  for (int frame : {1, 2}) {
    source->read_frame(frame, positions);
    EXPECT_EQ(positions, (std::vector<Vec3>{{0.5 + frame, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.25}}));
  }
  expect_input_error([&] { source->read_frame(3, positions); },
                     "p3.ply: frame 3: triangle 1 is (1,3,0), expected (1,3,2)");
  expect_input_error([&] { source->read_frame(4, positions); }, "vertex 0: coordinate is not finite");
  source->read_frame(5, positions);  // another header: parsed in full, the same topology
  EXPECT_EQ(positions[0].x, 8.0);
}

TEST(OpenCache, ReadsObjSequencesLikeTheirFullParse) {
  testing::TempDir dir;
  for (int frame : {0, 1, 2}) dir.write("q" + std::to_string(frame) + ".obj", triangle_obj(0.5 + frame));
  std::string normals = triangle_obj(3.5);  // normals and a comment of its own: read from its vertices alone
  normals.replace(normals.find("f 1"), 0, "vn 0 0 1\n# frame 3\n");
  dir.write("q3.obj", normals);
  std::string other = triangle_obj(4);
  other.replace(other.find("f 2 4 3"), 7, "f 2 4 1");
  dir.write("q4.obj", other);
  std::string bad = triangle_obj(5);
  bad.replace(bad.find("v 1 1 0"), 7, "v 1 inf 0");
  dir.write("q5.obj", bad);
  dir.write("q6.obj", "s 1\n" + triangle_obj(6));  // another line: parsed in full, the same topology
  const auto source = open_cache(one_input(dir.path("q%d.obj")));
  std::vector<Vec3> positions;
  for (int frame : {1, 2, 3}) {
    source->read_frame(frame, positions);
    EXPECT_EQ(positions, (std::vector<Vec3>{{0.5 + frame, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}));
  }
  expect_input_error([&] { source->read_frame(4, positions); },
                     "q4.obj: frame 4: triangle 1 is (1,3,0), expected (1,3,2)");
  expect_input_error([&] { source->read_frame(5, positions); }, "q5.obj:4: coordinate is not finite");
  source->read_frame(6, positions);
  EXPECT_EQ(positions[0].x, 6.0);
}

TEST(OpenCache, CombinesInputsAsNamedObjects) {
  testing::TempDir dir;
  for (int frame : {1, 2}) {
    dir.write("cloth" + std::to_string(frame) + ".obj", triangle_obj(frame));
    dir.write("body" + std::to_string(frame) + ".ply",
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
                  std::to_string(frame * 100) + " 0 0\n0 0 1\n0 1 1\n3 0 1 2\n");
  }
  CacheOptions options;
  options.inputs.push_back({dir.path("cloth%d.obj"), "", ""});
  options.inputs.push_back({dir.path("body%d.ply"), "", "Body"});
  options.inputs.push_back({dir.path("cloth%d.obj"), "", ""});
  const auto source = open_cache(options);
  ASSERT_EQ(source->scene().objects().size(), 3u);
  EXPECT_EQ(source->scene().objects()[0].name, "cloth");
  EXPECT_EQ(source->scene().objects()[1].name, "Body");
  EXPECT_EQ(source->scene().objects()[2].name, "cloth_2");
  EXPECT_EQ(source->scene().vertex_count(), 11u);
  EXPECT_EQ(source->scene().triangles()[2], (Triangle{4, 5, 6}));
  std::vector<Vec3> positions;
  source->read_frame(1, positions);
  ASSERT_EQ(positions.size(), 11u);
  EXPECT_EQ(positions[0].x, 2.0);
  EXPECT_EQ(positions[4].x, 200.0);
  EXPECT_EQ(positions[7].x, 2.0);
}

TEST(OpenCache, RejectsInputsWithDifferentFrameCounts) {
  testing::TempDir dir;
  for (int frame : {1, 2, 3}) dir.write("a" + std::to_string(frame) + ".obj", triangle_obj(frame));
  for (int frame : {1, 2}) dir.write("b" + std::to_string(frame) + ".obj", triangle_obj(frame));
  CacheOptions options;
  options.inputs.push_back({dir.path("a%d.obj"), "", ""});
  options.inputs.push_back({dir.path("b%d.obj"), "", ""});
  expect_input_error([&] { open_cache(options); }, "b%d.obj: 2 frames, but " + dir.path("a%d.obj") + " has 3");
  options.frames.last = 1;  // the first two frames of each: now they agree
  EXPECT_EQ(open_cache(options)->frame_count(), 2u);
}

TEST(OpenCache, AppliesFrameSelection) {
  testing::TempDir dir;
  for (int frame = 0; frame < 10; ++frame) dir.write("s" + std::to_string(frame) + ".obj", triangle_obj(frame));
  CacheOptions options = one_input(dir.path("s%d.obj"));
  options.frames = parse_frame_selection("2:7:2");
  const auto source = open_cache(options);
  EXPECT_EQ(first_xs(*source), (std::vector<double>{2, 4, 6}));
  EXPECT_EQ(source->frame_time(1), 4.0);
  options.frames = parse_frame_selection("8:");
  EXPECT_EQ(first_xs(*open_cache(options)), (std::vector<double>{8, 9}));
  options.frames = parse_frame_selection("10:");
  EXPECT_THROW(open_cache(options), UsageError);
}

TEST(OpenCache, ReadsSingleFilesOfEachFormat) {
  testing::TempDir dir;
  const auto source = open_cache(one_input(dir.write("one.obj", triangle_obj(5)), "Thing"));
  EXPECT_EQ(source->frame_count(), 1u);
  EXPECT_EQ(source->scene().objects().at(0).name, "Thing");
  const std::string meshes = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/";
  CacheOptions options;
  options.inputs.push_back({meshes + "cloth_ball92.ply", "", ""});
  EXPECT_EQ(open_cache(options)->scene().triangle_count(), 92230u);
}

TEST(OpenCache, RejectsMissingAndUnknownInputs) {
  testing::TempDir dir;
  expect_input_error([&] { open_cache(one_input(dir.path("none.obj"))); }, "none.obj: no such file");
  expect_input_error([&] { open_cache(one_input(dir.path("none_%04d.obj"))); }, "no files match the frame pattern");
  expect_input_error([&] { open_cache(one_input(dir.path("none_*.obj"))); }, "no files match the glob");
  expect_input_error([&] { open_cache(one_input(dir.write("x.xyz", "1 2 3"))); }, "unknown mesh format '.xyz'");
  EXPECT_THROW(open_cache(one_input(dir.write("c.pc2", "x"))), UsageError);
}

}  // namespace
}  // namespace snag::io
