#include <gtest/gtest.h>

#include <cmath>

#include "io/obj_reader.hpp"
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

}  // namespace
}  // namespace snag::io
