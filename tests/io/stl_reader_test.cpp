#include <gtest/gtest.h>

#include <limits>

#include "io/stl_reader.hpp"
#include "test_files.hpp"

namespace snag::io {
namespace {

using testing::expect_input_error;
using testing::put;

// Two triangles sharing the edge (1,0,0)-(0,1,0); the shared corners are
// written once as +0 and once as -0 to check that they weld.
const float kCorners[2][3][3] = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{1, -0.0f, 0}, {1, 1, 0.1f}, {-0.0f, 1, 0}}};

std::string binary_stl(const std::string& header_text = "binary stl") {
  std::string bytes = header_text;
  bytes.resize(80, ' ');
  put<std::uint32_t>(bytes, 2);
  for (const auto& triangle : kCorners) {
    for (int k = 0; k < 3; ++k) put<float>(bytes, 0);  // normal
    for (const auto& corner : triangle) {
      for (float value : corner) put<float>(bytes, value);
    }
    put<std::uint16_t>(bytes, 0);
  }
  return bytes;
}

void expect_welded(const MeshData& mesh) {
  ASSERT_EQ(mesh.positions.size(), 4u);
  EXPECT_EQ(mesh.positions[0], (Vec3{0, 0, 0}));
  EXPECT_EQ(mesh.positions[1], (Vec3{1, 0, 0}));
  EXPECT_EQ(mesh.positions[2], (Vec3{0, 1, 0}));
  EXPECT_EQ(mesh.positions[3], (Vec3{1, 1, static_cast<double>(0.1f)}));
  EXPECT_EQ(mesh.objects.at(0).triangles, (std::vector<Triangle>{{0, 1, 2}, {1, 3, 2}}));
  EXPECT_EQ(mesh.objects[0].name, "tri");
}

TEST(StlReader, WeldsBinaryCornersInFirstAppearanceOrder) { expect_welded(parse_stl(binary_stl(), "tri.stl")); }

TEST(StlReader, TakesBinaryThatStartsWithSolidAsBinary) {
  expect_welded(parse_stl(binary_stl("solid but binary"), "tri.stl"));
}

TEST(StlReader, WeldsAsciiCorners) {
  const std::string text =
      "solid tri\n"
      "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n      vertex 0 1 0\n"
      "    endloop\n  endfacet\n"
      "  facet normal 0 0 1\n    outer loop\n      vertex 1 -0 0\n      vertex 1 1 0.100000001490116119384765625\n"
      "      vertex -0 1 0\n    endloop\n  endfacet\n"
      "endsolid tri\n";
  expect_welded(parse_stl(text, "tri.stl"));
}

TEST(StlReader, RejectsTruncatedBinary) {
  std::string bytes = binary_stl();
  bytes.resize(bytes.size() - 10);
  expect_input_error([&] { parse_stl(bytes, "t.stl"); }, "binary STL header says 2 triangles (184 bytes) but the file has 174 bytes");
  expect_input_error([] { parse_stl("abc", "t.stl"); }, "truncated");
}

TEST(StlReader, RejectsNonFiniteCoordinates) {
  std::string bytes = binary_stl();
  const float inf = std::numeric_limits<float>::infinity();
  std::memcpy(&bytes[84 + 50 + 12 + 4], &inf, 4);
  expect_input_error([&] { parse_stl(bytes, "n.stl"); }, "triangle 1: coordinate is not finite");
  expect_input_error([] { parse_stl("solid x\nfacet normal 0 0 1\nouter loop\nvertex nan 0 0\n", "n.stl"); },
                     "n.stl:4: coordinate is not finite");
}

TEST(StlReader, RejectsMalformedAsciiAndEmptyMeshes) {
  expect_input_error([] { parse_stl("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n",
                                    "d.stl"); },
                     "d.stl:6: facet with 2 vertices cannot be triangulated");
  expect_input_error([] { parse_stl("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", "d.stl"); }, "d.stl:5:");
  expect_input_error([] { parse_stl("solid x\nendsolid x\n", "e.stl"); }, "no facets");
  std::string empty_binary(80, ' ');
  put<std::uint32_t>(empty_binary, 0);
  expect_input_error([&] { parse_stl(empty_binary, "e.stl"); }, "no triangles");
}

}  // namespace
}  // namespace snag::io
