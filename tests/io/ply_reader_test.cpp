#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "io/ply_reader.hpp"
#include "test_files.hpp"

namespace snag::io {
namespace {

using testing::expect_input_error;
using testing::put;

// Four vertices of a unit square with values that float32 and double store
// differently, and one quad face.
const double kValues[4][3] = {{0.1, -0.2, 0.3}, {1.7, 0.25, -3.3}, {2.2, 1e-3, 1e7 + 0.5}, {-0.0, 5, 6.1}};

struct PlyLayout {
  bool big_endian = false;
  bool doubles = false;
  bool int_count = false;     // list count int instead of uchar
  bool uint_indices = false;  // uint instead of int
};

/// A binary PLY of kValues with an extra property before x, z before y, and a
/// face element holding an extra list and a flag around the index list.
std::string binary_ply(const PlyLayout& layout, double scale = 1) {
  const char* real = layout.doubles ? "double" : "float";
  std::ostringstream header;
  header << "ply\nformat " << (layout.big_endian ? "binary_big_endian" : "binary_little_endian") << " 1.0\n"
         << "comment made by hand\nelement vertex 4\nproperty uchar red\nproperty " << real << " x\nproperty " << real
         << " z\nproperty " << real << " y\nproperty short extra\n"
         << "element face 1\nproperty list uchar float texcoord\nproperty list " << (layout.int_count ? "int" : "uchar")
         << " " << (layout.uint_indices ? "uint" : "int") << " vertex_indices\nproperty int flags\nend_header\n";
  std::string bytes = header.str();
  for (const auto& v : kValues) {
    put<std::uint8_t>(bytes, 200);
    for (int axis : {0, 2, 1}) {
      if (layout.doubles)
        put<double>(bytes, scale * v[axis], layout.big_endian);
      else
        put<float>(bytes, static_cast<float>(scale * v[axis]), layout.big_endian);
    }
    put<std::int16_t>(bytes, -5, layout.big_endian);
  }
  put<std::uint8_t>(bytes, 2);
  put<float>(bytes, 0.5f, layout.big_endian);
  put<float>(bytes, 0.25f, layout.big_endian);
  if (layout.int_count) put<std::int32_t>(bytes, 4, layout.big_endian);
  else put<std::uint8_t>(bytes, 4);
  for (std::int32_t id : {0, 1, 2, 3}) put<std::int32_t>(bytes, id, layout.big_endian);
  put<std::int32_t>(bytes, 77, layout.big_endian);
  return bytes;
}

void expect_square(const MeshData& mesh, bool doubles) {
  ASSERT_EQ(mesh.positions.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    for (int axis = 0; axis < 3; ++axis) {
      const double expected = doubles ? kValues[k][axis] : static_cast<double>(static_cast<float>(kValues[k][axis]));
      EXPECT_EQ(mesh.positions[k][axis], expected) << "vertex " << k << " axis " << axis;
    }
  }
  ASSERT_EQ(mesh.objects.size(), 1u);
  EXPECT_EQ(mesh.objects[0].name, "square");
  EXPECT_EQ(mesh.objects[0].vertices, (std::vector<Index>{0, 1, 2, 3}));
  EXPECT_EQ(mesh.objects[0].triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}}));
}

TEST(PlyReader, ReadsBinaryLittleEndianFloatExactly) { expect_square(parse_ply(binary_ply({}), "square.ply"), false); }

TEST(PlyReader, ReadsBinaryBigEndianDoubleExactly) {
  expect_square(parse_ply(binary_ply({true, true, false, false}), "square.ply"), true);
}

TEST(PlyReader, ReadsIntCountsAndUnsignedIndices) {
  expect_square(parse_ply(binary_ply({true, false, true, true}), "square.ply"), false);
  expect_square(parse_ply(binary_ply({false, true, true, false}), "square.ply"), true);
}

TEST(PlyReader, ReadsAsciiWithDeclaredPrecision) {
  // float properties round to float32 (as the binary file of the same data
  // would); double properties to the nearest double.
  std::ostringstream text;
  text.precision(17);
  text << "ply\r\nformat ascii 1.0\r\nelement vertex 4\r\nproperty float x\r\nproperty double y\r\nproperty float z\r\n"
       << "property int w\r\nelement face 1\r\nproperty list uchar uint vertex_index\r\nend_header\r\n";
  for (const auto& v : kValues) text << v[0] << " " << v[1] << " " << v[2] << " 9\r\n";
  text << "4 0 1 2 3\r\n";
  const MeshData mesh = parse_ply(text.str(), "a.ply");
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(mesh.positions[k].x, static_cast<double>(static_cast<float>(kValues[k][0])));
    EXPECT_EQ(mesh.positions[k].y, kValues[k][1]);
    EXPECT_EQ(mesh.positions[k].z, static_cast<double>(static_cast<float>(kValues[k][2])));
  }
  EXPECT_EQ(mesh.objects[0].triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}}));
}

TEST(PlyReader, ReadsAsciiDecimalsCorrectlyRounded) {
  const MeshData mesh = parse_ply(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0.1 0.2 0.3\n1.00000000000000011102230246251565404236316680908203125 0 0\n0 1 0\n3 0 1 2\n",
      "r.ply");
  EXPECT_EQ(mesh.positions[0], (Vec3{0.1, 0.2, 0.3}));
  EXPECT_EQ(mesh.positions[1].x, 1.0);
}

TEST(PlyReader, RejectsTruncatedBinary) {
  std::string bytes = binary_ply({});
  bytes.resize(bytes.size() - 3);
  expect_input_error([&] { parse_ply(bytes, "t.ply"); }, "truncated");
}

TEST(PlyReader, RejectsCountsLargerThanTheFileBeforeAllocating) {
  std::string bytes = binary_ply({});
  const std::size_t at = bytes.find("element vertex 4");
  bytes.replace(at, 16, "element vertex 400000000000");
  expect_input_error([&] { parse_ply(bytes, "big.ply"); }, "header says 400,000,000,000 vertex elements");
  expect_input_error([] { parse_ply("ply\nformat ascii 1.0\nelement vertex 99999999999999\nproperty float x\nproperty float y\n"
                                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n",
                                    "big.ply"); },
                     "header says 99,999,999,999,999 vertex elements");
}

TEST(PlyReader, RejectsNonFiniteCoordinates) {
  std::string bytes = binary_ply({});
  const std::size_t first_x = bytes.find("end_header\n") + 11 + 1;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&bytes[first_x + 15], &nan, 4);  // vertex 1's x (15 bytes per vertex)
  expect_input_error([&] { parse_ply(bytes, "n.ply"); }, "vertex 1: coordinate is not finite");
}

TEST(PlyReader, RejectsIndicesOutOfRange) {
  std::string bytes = binary_ply({});
  const std::int32_t bad = 4;
  std::memcpy(&bytes[bytes.size() - 8], &bad, 4);  // the last index
  expect_input_error([&] { parse_ply(bytes, "i.ply"); }, "face 0: vertex index 4 out of range");
  expect_input_error([] { parse_ply("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                    "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "i.ply"); },
                     "i.ply:13: face 0: vertex index -1 out of range");
}

TEST(PlyReader, ChecksIndicesOfPlainTriangleLists) {
  // One uchar count and int indices per face: the layout most tools write.
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 3\nproperty list uchar int vertex_indices\nend_header\n";
  for (float value : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put<float>(bytes, value);
  for (int face = 0; face < 3; ++face) {
    put<std::uint8_t>(bytes, 3);
    for (std::int32_t id : {0, 1, face == 1 ? 3 : 2}) put<std::int32_t>(bytes, id);
  }
  expect_input_error([&] { parse_ply(bytes, "p.ply"); }, "face 1: vertex index 3 out of range");
  bytes[bytes.size() - 26 + 9] = 2;  // repair face 1's last index
  EXPECT_EQ(parse_ply(bytes, "p.ply").objects[0].triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 1, 2}, {0, 1, 2}}));
}

TEST(PlyReader, RejectsFacesOfFewerThanThreeVertices) {
  expect_input_error([] { parse_ply("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                    "0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "f.ply"); },
                     "face 0 has 2 vertices and cannot be triangulated");
}

TEST(PlyReader, RejectsEmptyMeshAndBadHeaders) {
  expect_input_error([] { parse_ply("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                                    "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
                                    "e.ply"); },
                     "no faces");
  expect_input_error([] { parse_ply("PLY\n", "m.ply"); }, "m.ply:1: not a PLY file");
  expect_input_error([] { parse_ply("ply\nformat ascii 1.0\nelement vertex 1\n", "h.ply"); }, "without end_header");
  expect_input_error([] { parse_ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n", "h.ply"); },
                     "lacks an x, y or z");
  expect_input_error([] { parse_ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n", "h.ply"); },
                     "h.ply:4: unknown property type");
}

// A later frame whose bytes but the coordinates are the first frame's has
// its coordinates read alone, as parse_ply reads them, in every byte order
// and coordinate type.
TEST(PlyReader, FrameLayoutReadsTheCoordinatesOfFramesLikeTheFirst) {
  for (const PlyLayout& layout : {PlyLayout{}, PlyLayout{true, true, false, false}, PlyLayout{true, false, true, true},
                                  PlyLayout{false, true, false, false}}) {
    const auto first = PlyFrameLayout::of(binary_ply(layout), "square_0.ply");
    ASSERT_TRUE(first.has_value());
    const std::string later = binary_ply(layout, -2.75);
    std::vector<Vec3> positions;
    ASSERT_TRUE(first->read_positions(later, positions));
    EXPECT_EQ(positions, parse_ply(later, "square_1.ply").positions);
  }
}

// Any other byte outside the coordinates (a face's index, the header, the
// size), a coordinate that is not finite, a text file or vertices that are
// not first or hold other types: the layout declines, and the full parse
// reads the frame (and says what is wrong with it).
TEST(PlyReader, FrameLayoutDeclinesFramesNotLikeTheFirst) {
  const std::string bytes = binary_ply({});
  const auto first = PlyFrameLayout::of(bytes, "square_0.ply");
  ASSERT_TRUE(first.has_value());
  std::vector<Vec3> positions;
  std::string other = bytes;
  other[other.size() - 8] = 1;  // the last index
  EXPECT_FALSE(first->read_positions(other, positions));
  other = bytes;
  other.replace(other.find("by hand"), 7, "by HAND");
  EXPECT_FALSE(first->read_positions(other, positions));
  EXPECT_FALSE(first->read_positions(bytes + "x", positions));
  other = bytes;
  const float infinity = std::numeric_limits<float>::infinity();
  std::memcpy(&other[bytes.find("end_header\n") + 11 + 15 + 1], &infinity, 4);  // vertex 1's x
  EXPECT_FALSE(first->read_positions(other, positions));
  EXPECT_TRUE(first->read_positions(bytes, positions));

  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_FALSE(PlyFrameLayout::of(ascii, "a.ply").has_value());
  std::string faces_first =
      "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  put<std::uint8_t>(faces_first, 3);
  for (std::int32_t id : {0, 1, 2}) put<std::int32_t>(faces_first, id);
  for (float value : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put<float>(faces_first, value);
  EXPECT_EQ(parse_ply(faces_first, "f.ply").positions.size(), 3u);
  EXPECT_FALSE(PlyFrameLayout::of(faces_first, "f.ply").has_value());
  std::string short_x =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty short x\nproperty float y\nproperty float z\n"
      "element face 0\nproperty list uchar int vertex_indices\nend_header\n";
  EXPECT_FALSE(PlyFrameLayout::of(short_x, "s.ply").has_value());
  std::string huge = bytes;
  huge.replace(huge.find("element vertex 4"), 16, "element vertex 400000000000000000");
  EXPECT_FALSE(PlyFrameLayout::of(huge, "h.ply").has_value());
}

/// Reads vertex 0's x from a PLY file's body with an independent decoder.
float first_float_of_body(const std::string& path, bool big_endian) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t body = bytes.find("end_header\n") + 11;
  unsigned char raw[4];
  std::memcpy(raw, &bytes[body], 4);
  if (big_endian) std::swap(raw[0], raw[3]), std::swap(raw[1], raw[2]);
  float value;
  std::memcpy(&value, raw, 4);
  return value;
}

TEST(PlyReader, ReadsRealToolOutputFromSharedData) {
  const std::string meshes = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/";
  const MeshData cloth = read_ply(meshes + "cloth_ball92.ply");  // binary big-endian float
  EXPECT_EQ(cloth.positions.size(), 46598u);
  EXPECT_EQ(cloth.objects.at(0).triangles.size(), 92230u);
  EXPECT_EQ(cloth.positions[0].x, static_cast<double>(first_float_of_body(meshes + "cloth_ball92.ply", true)));
  const MeshData next = read_ply(meshes + "cloth_ball93.ply");
  EXPECT_EQ(next.objects.at(0).triangles, cloth.objects[0].triangles);
  const MeshData bunny = read_ply(meshes + "bunny.ply");  // binary little-endian double
  EXPECT_EQ(bunny.positions.size(), 2503u);
  EXPECT_EQ(bunny.objects.at(0).triangles.size(), 5002u);
  for (const char* name : {"cube.ply", "two-cubes-far.ply", "two-cubes-close.ply", "two-cubes-intersecting.ply",
                           "thick-cloth/t0.ply", "thick-cloth/t1.ply"}) {
    const MeshData mesh = read_ply(meshes + name);
    EXPECT_FALSE(mesh.objects.at(0).triangles.empty()) << name;
    for (const Triangle& t : mesh.objects[0].triangles) {
      for (Index v : t) ASSERT_LT(v, mesh.positions.size()) << name;
    }
  }
  EXPECT_EQ(read_ply(meshes + "thick-cloth/t0.ply").positions.size(), 233u);
}

}  // namespace
}  // namespace snag::io
