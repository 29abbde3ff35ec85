// Welding of coincident vertices (io/vertex_weld.hpp) on hand-made caches
// whose answers are known: a cube split per face as FBX and Collada deliver
// it, vertices that part in a later frame, signed zeros, non-finite
// positions, distances and chains, and separate objects.
#include "io/vertex_weld.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "libcd/core/error.hpp"

namespace snag::io {
namespace {

/// A cache held in memory: one frame list of global positions per frame.
class MemorySource final : public FrameSource {
 public:
  MemorySource(std::vector<Object> objects, std::vector<std::vector<Vec3>> frames)
      : scene_(std::move(objects)), frames_(std::move(frames)) {}
  const Scene& scene() const override { return scene_; }
  std::size_t frame_count() const override { return frames_.size(); }
  void read_frame(std::size_t i, std::vector<Vec3>& positions) const override {
    ++reads;
    positions = frames_[i];
  }
  std::string description() const override { return "memory"; }
  mutable std::size_t reads = 0;

 private:
  Scene scene_;
  std::vector<std::vector<Vec3>> frames_;
};

WeldSettings exact() { return parse_weld("exact"); }

/// A unit cube with its own 4 vertices per face (24 vertices, 12 triangles),
/// as a format with one vertex per face corner gives it; frame f is turned
/// about z by 0.3 f radians and moved along x by f.
std::unique_ptr<MemorySource> split_cube(std::size_t frames) {
  const int faces[6][4][3] = {{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
                              {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},
                              {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}};
  std::vector<Vec3> rest;
  std::vector<Triangle> triangles;
  for (const auto& face : faces) {
    const auto base = static_cast<Index>(rest.size());
    for (const auto& c : face) rest.push_back({double(c[0]), double(c[1]), double(c[2])});
    triangles.push_back({base, base + 1, base + 2});
    triangles.push_back({base, base + 2, base + 3});
  }
  std::vector<std::vector<Vec3>> positions;
  for (std::size_t f = 0; f < frames; ++f) {
    const double angle = 0.3 * static_cast<double>(f), c = std::cos(angle), s = std::sin(angle);
    std::vector<Vec3> frame;
    for (const Vec3& p : rest) frame.push_back({c * p.x - s * p.y + static_cast<double>(f), s * p.x + c * p.y, p.z});
    positions.push_back(std::move(frame));
  }
  std::vector<Object> objects;
  objects.push_back(make_object("cube", 24, std::move(triangles)));
  return std::make_unique<MemorySource>(std::move(objects), std::move(positions));
}

TEST(ParseWeld, ReadsMethodsAndDistances) {
  EXPECT_EQ(parse_weld("auto").method, WeldSettings::Method::kAuto);
  EXPECT_EQ(parse_weld("none").method, WeldSettings::Method::kNone);
  EXPECT_EQ(parse_weld("exact").method, WeldSettings::Method::kExact);
  EXPECT_EQ(parse_weld("0").method, WeldSettings::Method::kExact);
  const WeldSettings distance = parse_weld("1e-4");
  EXPECT_EQ(distance.method, WeldSettings::Method::kDistance);
  EXPECT_DOUBLE_EQ(distance.distance, 1e-4);
  for (const char* bad : {"", "-1", "nan", "inf", "1mm", "exactly"}) {
    EXPECT_THROW(parse_weld(bad), UsageError) << bad;
  }
}

TEST(VertexWeld, NoneReturnsTheSourceItself) {
  auto cube = split_cube(2);
  const FrameSource* original = cube.get();
  EXPECT_EQ(weld_vertices(std::move(cube), parse_weld("none")).get(), original);
}

TEST(VertexWeld, ExactWeldMakesASplitCubeClosed) {
  auto welded = weld_vertices(split_cube(5), exact());
  const Object& cube = welded->scene().objects().at(0);
  EXPECT_EQ(cube.vertex_count, 8u);
  EXPECT_EQ(cube.triangles.size(), 12u);
  EXPECT_EQ(cube.edges.size(), 18u);
  const EdgeCounts kinds = count_edge_kinds(cube);
  EXPECT_EQ(kinds.boundary, 0u);
  EXPECT_EQ(kinds.non_manifold, 0u);
  EXPECT_EQ(cube.weld.method, "exact");
  EXPECT_EQ(file_vertex_count(cube), 24u);
  EXPECT_NE(welded->description().find("16 coincident vertices welded (exact)"), std::string::npos);

  // Each vertex is named by the smallest file vertex joined into it, and
  // every file vertex maps to the vertex that carries its position.
  auto file = split_cube(5);
  std::vector<Vec3> file_x, welded_x;
  for (std::size_t f = 0; f < 5; ++f) {
    file->read_frame(f, file_x);
    welded->read_frame(f, welded_x);
    ASSERT_EQ(welded_x.size(), 8u);
    for (Index v = 0; v < 24; ++v) {
      const Index w = vertex_of_file_vertex(cube, v);
      EXPECT_LE(file_vertex_id(cube, w), v);
      EXPECT_EQ(vertex_of_file_vertex(cube, file_vertex_id(cube, w)), w);
      EXPECT_EQ(welded_x[w].x, file_x[v].x);
      EXPECT_EQ(welded_x[w].y, file_x[v].y);
      EXPECT_EQ(welded_x[w].z, file_x[v].z);
    }
  }
}

TEST(VertexWeld, VerticesThatPartInALaterFrameStaySeparate) {
  // Three coincident vertices in frames 0 and 1; in frame 2 vertex 1 leaves,
  // vertices 0 and 2 stay together.
  std::vector<std::vector<Vec3>> frames(3, std::vector<Vec3>{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  frames[2][1] = {0, 0, 1e-300};
  std::vector<Object> objects;
  objects.push_back(make_object("o", 5, {{0, 3, 4}, {1, 3, 4}, {2, 4, 3}}));
  auto welded = weld_vertices(std::make_unique<MemorySource>(std::move(objects), frames), exact());
  const Object& object = welded->scene().objects().at(0);
  EXPECT_EQ(object.vertex_count, 4u);
  EXPECT_EQ(vertex_of_file_vertex(object, 0), vertex_of_file_vertex(object, 2));
  EXPECT_NE(vertex_of_file_vertex(object, 0), vertex_of_file_vertex(object, 1));
  EXPECT_EQ(file_vertex_id(object, vertex_of_file_vertex(object, 1)), 1u);
}

TEST(VertexWeld, ExactWeldStopsReadingWhenNothingCoincides) {
  std::vector<std::vector<Vec3>> frames(50, std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  std::vector<Object> objects;
  objects.push_back(make_object("o", 3, {{0, 1, 2}}));
  auto source = std::make_unique<MemorySource>(std::move(objects), frames);
  const MemorySource* memory = source.get();
  auto welded = weld_vertices(std::move(source), exact());
  EXPECT_EQ(memory->reads, 1u);
  EXPECT_EQ(welded->scene().objects()[0].vertex_count, 3u);
  EXPECT_TRUE(welded->scene().objects()[0].weld.file_ids.empty());
  EXPECT_EQ(welded->scene().objects()[0].weld.method, "exact");
}

TEST(VertexWeld, SignedZerosJoinAndNonFinitePositionsNever) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<std::vector<Vec3>> frames(
      2, std::vector<Vec3>{{0, 0, 0}, {-0.0, 0, -0.0}, {nan, 0, 0}, {nan, 0, 0}, {inf, 1, 1}, {inf, 1, 1}});
  std::vector<Object> objects;
  objects.push_back(make_object("o", 6, {{0, 2, 4}, {1, 3, 5}}));
  auto welded = weld_vertices(std::make_unique<MemorySource>(std::move(objects), frames), exact());
  const Object& object = welded->scene().objects().at(0);
  EXPECT_EQ(object.vertex_count, 5u);
  EXPECT_EQ(vertex_of_file_vertex(object, 0), vertex_of_file_vertex(object, 1));
}

TEST(VertexWeld, NeverJoinsVerticesOfDifferentObjects) {
  std::vector<std::vector<Vec3>> frames(2, std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  std::vector<Object> objects;
  objects.push_back(make_object("a", 3, {{0, 1, 2}}));
  objects.push_back(make_object("b", 3, {{0, 1, 2}}));
  auto welded = weld_vertices(std::make_unique<MemorySource>(std::move(objects), frames), exact());
  EXPECT_EQ(welded->scene().vertex_count(), 6u);
}

TEST(VertexWeld, ACollapsedTriangleKeepsItsIdWithARepeatedVertex) {
  std::vector<std::vector<Vec3>> frames(2, std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}});
  std::vector<Object> objects;
  objects.push_back(make_object("o", 4, {{0, 1, 2}, {0, 1, 3}}));
  auto welded = weld_vertices(std::make_unique<MemorySource>(std::move(objects), frames), exact());
  const Object& object = welded->scene().objects().at(0);
  ASSERT_EQ(object.triangles.size(), 2u);
  EXPECT_EQ(object.triangles[1][1], object.triangles[1][2]);
}

TEST(VertexWeld, DistanceWeldJoinsChainsThatStayClose) {
  // 0-1 and 1-2 are 0.6e-3 apart (within 1e-3), 0-2 is 1.2e-3 apart: one
  // chain. 3 is 0.6e-3 from 4 in frame 0 but 2e-3 in frame 1: apart.
  const std::vector<Vec3> frame0{{0, 0, 0}, {0.6e-3, 0, 0}, {1.2e-3, 0, 0}, {5, 0, 0}, {5, 0.6e-3, 0}, {0, 5, 0}};
  std::vector<Vec3> frame1 = frame0;
  frame1[4] = {5, 2e-3, 0};
  std::vector<Object> objects;
  objects.push_back(make_object("o", 6, {{0, 3, 5}, {1, 4, 5}, {2, 3, 5}}));
  auto welded = weld_vertices(std::make_unique<MemorySource>(std::move(objects), std::vector{frame0, frame1}),
                              parse_weld("1e-3"));
  const Object& object = welded->scene().objects().at(0);
  EXPECT_EQ(object.vertex_count, 4u);
  EXPECT_EQ(object.weld.method, "distance 0.001");
  EXPECT_EQ(vertex_of_file_vertex(object, 2), vertex_of_file_vertex(object, 0));
  EXPECT_EQ(file_vertex_id(object, vertex_of_file_vertex(object, 2)), 0u);
  EXPECT_NE(vertex_of_file_vertex(object, 3), vertex_of_file_vertex(object, 4));
}

TEST(VertexWeld, DistanceThatJoinsEverythingIsRefused) {
  std::vector<Vec3> grid;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) grid.push_back({0.01 * i, 0.01 * j, 0});
  std::vector<Triangle> triangles;
  for (Index v = 0; v + 2 < grid.size(); v += 3) triangles.push_back({v, v + 1, v + 2});
  std::vector<Object> objects;
  objects.push_back(make_object("o", static_cast<Index>(grid.size()), triangles));
  auto source = std::make_unique<MemorySource>(std::move(objects), std::vector<std::vector<Vec3>>{grid});
  EXPECT_THROW(weld_vertices(std::move(source), parse_weld("10")), UsageError);
}

}  // namespace
}  // namespace snag::io
