#include "io/mapped_file.hpp"
#include "io/obj_reader.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "test_files.hpp"

namespace snag::io {
namespace {

using testing::expect_input_error;

TEST(ObjReader, ParsesDecimalsToCorrectlyRoundedDoubles) {
  // 1 + 2^-53 written out exactly is a tie that rounds to even (1.0); one more
  // digit past it must round up to 1 + 2^-52.
  const MeshData mesh = parse_obj(
      "v 0.1 -0.2 +0.3\n"
      "v 1.00000000000000011102230246251565404236316680908203125 "
      "1.000000000000000111022302462515654042363166809082031251 1e-310\n"
      "v 3 4.5e2 -0\n"
      "f 1 2 3\n",
      "t.obj");
  ASSERT_EQ(mesh.positions.size(), 3u);
  EXPECT_EQ(mesh.positions[0], (Vec3{0.1, -0.2, 0.3}));
  EXPECT_EQ(mesh.positions[1].x, 1.0);
  EXPECT_EQ(mesh.positions[1].y, std::nextafter(1.0, 2.0));
  EXPECT_EQ(mesh.positions[1].z, 1e-310);
  EXPECT_EQ(mesh.positions[2], (Vec3{3, 450, 0}));
  ASSERT_EQ(mesh.objects.size(), 1u);
  EXPECT_EQ(mesh.objects[0].name, "t");
  EXPECT_EQ(mesh.objects[0].triangles, (std::vector<Triangle>{{0, 1, 2}}));
}

TEST(ObjReader, ReadsEveryFaceEntryFormAndRelativeIndices) {
  const MeshData mesh = parse_obj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
      "f 1 2 3\n"
      "f 1/1 2/2 4/3\n"
      "f 2//1 4//1 3//1\n"
      "f 1/1/1 3/3/1 4/2/1\n"
      "f -4 -3 -1\n",
      "t.obj");
  EXPECT_EQ(mesh.objects[0].triangles,
            (std::vector<Triangle>{{0, 1, 2}, {0, 1, 3}, {1, 3, 2}, {0, 2, 3}, {0, 1, 3}}));
}

TEST(ObjReader, FanTriangulatesPolygons) {
  const MeshData mesh = parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\nf 1 2 3 4 5\n", "t.obj");
  EXPECT_EQ(mesh.objects[0].triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}));
}

TEST(ObjReader, SplitsBlenderObjectsWithLocalVertices) {
  const MeshData mesh = parse_obj(
      "# Blender 3.4\nmtllib scene.mtl\n"
      "o Cloth\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 7 7 7\nvt 0 0\nvn 0 0 1\ns off\nusemtl Fabric\ng Cloth_Fabric\n"
      "f 1/1/1 2/1/1 3/1/1\nl 1 2\n"
      "o Body\nv 5 5 5\nv 6 5 5\nv 5 6 5\nv 5 5 6\nusemtl Skin\nf 5 6 7\nf 5 7 8\n"
      "o Empty\n",
      "scene.obj");
  ASSERT_EQ(mesh.positions.size(), 8u);
  ASSERT_EQ(mesh.objects.size(), 2u);  // "Empty" has no faces; g stays inside o
  EXPECT_EQ(mesh.objects[0].name, "Cloth");
  EXPECT_EQ(mesh.objects[0].vertices, (std::vector<Index>{0, 1, 2}));  // unused vertex 4 dropped
  EXPECT_EQ(mesh.objects[0].triangles, (std::vector<Triangle>{{0, 1, 2}}));
  EXPECT_EQ(mesh.objects[1].name, "Body");
  EXPECT_EQ(mesh.objects[1].vertices, (std::vector<Index>{4, 5, 6, 7}));
  EXPECT_EQ(mesh.objects[1].triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}}));
}

TEST(ObjReader, UsesGroupsWhenThereAreNoObjects) {
  const MeshData mesh = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\ng Top\nf 1 2 4\ng Side\nf 1 3 4\ng Top\nf 2 3 4\n",
                                  "dir/mesh.obj");
  ASSERT_EQ(mesh.objects.size(), 3u);
  EXPECT_EQ(mesh.objects[0].name, "mesh");
  EXPECT_EQ(mesh.objects[1].name, "Top");
  EXPECT_EQ(mesh.objects[1].triangles.size(), 2u);  // repeated name continues the object
  EXPECT_EQ(mesh.objects[1].vertices, (std::vector<Index>{0, 1, 2, 3}));
  EXPECT_EQ(mesh.objects[2].name, "Side");
}

TEST(ObjReader, KeepsSharedAndDuplicatePositionsAsListed) {
  const MeshData mesh = parse_obj("v 0 0 0\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 3 4\nf 2 4 3\n", "t.obj");
  EXPECT_EQ(mesh.positions.size(), 4u);  // no welding
  EXPECT_EQ(mesh.objects[0].triangles, (std::vector<Triangle>{{0, 2, 3}, {1, 3, 2}}));
}

TEST(ObjReader, AcceptsCrLfAndMissingFinalNewline) {
  const MeshData mesh = parse_obj("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3", "t.obj");
  EXPECT_EQ(mesh.objects[0].triangles.size(), 1u);
  EXPECT_EQ(mesh.positions[2], (Vec3{0, 1, 0}));
}

TEST(ObjReader, RejectsIndexZero) {
  expect_input_error([] { parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "z.obj"); }, "z.obj:4: vertex index 0");
}

TEST(ObjReader, RejectsIndexOutOfRange) {
  expect_input_error([] { parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n", "r.obj"); },
                     "r.obj:5: vertex index 4 out of range");
  expect_input_error([] { parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", "r.obj"); }, "r.obj:4: relative vertex index -4");
}

TEST(ObjReader, RejectsNonFiniteCoordinates) {
  expect_input_error([] { parse_obj("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "n.obj"); }, "n.obj:2: coordinate is not finite");
  expect_input_error([] { parse_obj("v 0 0 inf\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "n.obj"); }, "n.obj:1: coordinate is not finite");
}

TEST(ObjReader, RejectsMalformedNumbers) {
  expect_input_error([] { parse_obj("v 0 0 0\nv 1 x 0\n", "m.obj"); }, "m.obj:2: expected a number");
  expect_input_error([] { parse_obj("v 0 0\n", "m.obj"); }, "m.obj:1: expected a number");
  expect_input_error([] { parse_obj("v 0 0 0\nf 1 a 2\n", "m.obj"); }, "m.obj:2: expected a vertex index");
}

TEST(ObjReader, RejectsFacesOfFewerThanThreeVertices) {
  expect_input_error([] { parse_obj("v 0 0 0\nv 1 0 0\nf 1 2\n", "d.obj"); }, "d.obj:3: face with 2 vertices cannot be triangulated");
}

TEST(ObjReader, RejectsEmptyMesh) {
  expect_input_error([] { parse_obj("", "e.obj"); }, "e.obj: no faces");
  expect_input_error([] { parse_obj("v 0 0 0\nv 1 0 0\nl 1 2\n", "e.obj"); }, "no faces");
}

TEST(ObjReader, ReadsFileAndNamesMissingOne) {
  testing::TempDir dir;
  const std::string path = dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(read_obj(path).objects[0].name, "tri");
  expect_input_error([&] { read_obj(dir.path("missing.obj")); }, "missing.obj: no such file");
}

/// A Blender-like frame: two objects, normals and texture coordinates that
/// change with the positions, smoothing and material lines, faces in every
/// entry form (one relative), and comments.
std::string blender_like_obj(double lift, const std::string& newline = "\n") {
  auto number = [](double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6f", value);
    return std::string(text);
  };
  std::string text = "# Blender 4.0 frame " + number(lift) + newline + "mtllib scene.mtl" + newline;
  text += "o Cloth" + newline;
  for (int k = 0; k < 4; ++k)
    text += "v " + number(k % 2) + " " + number(k / 2 + lift) + " " + number(0.125 * k) + newline;
  text += "vn " + number(lift) + " 0 1" + newline + "vt 0 0" + newline + "vt 1 " + number(lift) + newline;
  text += "s 0" + newline + "usemtl Cotton" + newline + "f 1/1/1 2/2/1 4/2/1" + newline + "f 1//1 4//1 -2//1" + newline;
  text += "  # a comment among the faces" + newline;
  text += "o Ball" + newline;
  for (int k = 0; k < 3; ++k) text += "v " + number(5 + k) + " " + number(lift) + " " + number(-k) + " 0.5" + newline;
  text += "vn 0 0 " + number(1 + lift) + newline + "f 5 6 7";  // no newline at the end
  return text;
}

// The layout of the first frame reads a later one's vertices as parse_obj
// does, whatever its normals, texture coordinates and comments say, with LF
// and CRLF line ends.
TEST(ObjReader, FrameLayoutReadsTheVerticesOfFramesLikeTheFirst) {
  for (const std::string newline : {"\n", "\r\n"}) {
    const std::string first = blender_like_obj(0, newline);
    const MeshData reference = parse_obj(first, "f_0.obj");
    ASSERT_EQ(reference.objects.size(), 2u);
    const ObjFrameLayout layout(first);
    for (double lift : {0.0, 0.5, -1234.5678}) {
      const std::string later = blender_like_obj(lift, newline);
      const MeshData full = parse_obj(later, "f_1.obj");
      ASSERT_EQ(full.objects.size(), 2u);
      EXPECT_EQ(full.objects[0].triangles, reference.objects[0].triangles);
      std::vector<Vec3> positions;
      ASSERT_TRUE(layout.read_positions(later, positions)) << lift;
      EXPECT_EQ(positions, full.positions);
    }
  }
}

// A line parse_obj reads that is not the first frame's, a vertex more or
// less or in another place, a last line that gains a newline, or a vertex
// parse_obj refuses: the layout declines, and the full parse reads the frame
// (and says what is wrong with it).
TEST(ObjReader, FrameLayoutDeclinesFramesNotLikeTheFirst) {
  const std::string first = blender_like_obj(0);
  const ObjFrameLayout layout(first);
  std::vector<Vec3> positions;
  ASSERT_TRUE(layout.read_positions(blender_like_obj(2), positions));
  auto declines = [&](const std::string& from, const std::string& to) {
    std::string other = blender_like_obj(2);
    const std::size_t at = other.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    other.replace(at, from.size(), to);
    EXPECT_FALSE(layout.read_positions(other, positions)) << from << " -> " << to;
  };
  declines("f 1/1/1 2/2/1 4/2/1", "f 1/1/1 2/2/1 3/2/1");               // another face
  declines("f 1//1 4//1 -2//1", "f 1//1 4//1 -3//1");                   // another relative index
  declines("o Ball", "o ball");                                         // another object name
  declines("s 0\n", "s 1\n");                                           // another line parse_obj may read
  declines("usemtl Cotton\n", "usemtl Cotton\nl 1 2\n");                // a line more
  declines("o Ball\n", "o Ball\nv 1 2 3\n");                            // a vertex more
  declines("v 7.000000 2.000000 -2.000000 0.5\n", "");                  // a vertex less
  declines("vn 0 0 3.000000\n", "vn 0 0 3.000000\nv 1 2 3\n");          // a vertex after the faces
  declines("v 1.000000 3.000000 0.375000\n", "");                       // ... and one fewer before them
  declines("f 5 6 7", "f 5 6 7\n");                                     // a newline at the end
  declines("f 5 6 7", "f 5 6 7 # closing");                             // the last line longer
  declines("v 0.000000 2.000000 0.000000", "v 0.000000 nan 0.000000");  // parse_obj refuses these two
  declines("v 0.000000 2.000000 0.000000", "v 0.000000 2.0x 0.000000");
  // As many vertices, one after a face's relative index: parse_obj reads other triangles.
  std::string moved = blender_like_obj(2);
  moved.replace(moved.find("v 1.000000 3.000000 0.375000\n"), 29, "");
  moved.replace(moved.find("  # a comment"), 0, "v 1.000000 3.000000 0.375000\n");
  EXPECT_NE(parse_obj(moved, "m.obj").objects[0].triangles, parse_obj(first, "f.obj").objects[0].triangles);
  EXPECT_FALSE(layout.read_positions(moved, positions));
}

// The OBJ sequences Blender exported (tests/real_assets, make_real_assets.py):
// the first frame's layout reads every later frame, as the parser reads it.
TEST(ObjReader, FrameLayoutReadsEveryFrameOfBlendersObjSequences) {
  const std::string data = std::string(SNAG_SOURCE_DIR) + "/tests/real_assets/data/";
  for (const char* scene : {"rigid_box", "rigid_cylinder", "bent_tube", "garment", "box_through_box"}) {
    auto frame_path = [&](int frame) {
      char name[32];
      std::snprintf(name, sizeof name, "/obj_%04d.obj", frame);
      return data + scene + name;
    };
    const MappedFile first(frame_path(0));
    const ObjFrameLayout layout(first.bytes());
    int frames = 0;
    for (int frame = 1; std::filesystem::exists(frame_path(frame)); ++frame, ++frames) {
      const MappedFile later(frame_path(frame));
      std::vector<Vec3> positions;
      ASSERT_TRUE(layout.read_positions(later.bytes(), positions)) << scene << " frame " << frame;
      EXPECT_EQ(positions, parse_obj(later.bytes(), frame_path(frame)).positions) << scene << " frame " << frame;
    }
    EXPECT_GE(frames, 16) << scene;
  }
}

}  // namespace
}  // namespace snag::io
