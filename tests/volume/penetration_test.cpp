// penetration(): a cloth sheet pushed into a sphere by a known distance: the
// depth is that distance and the area inside is the disc the sphere cuts from
// the sheet's plane; the cut triangle areas against a hand count.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cmath>

#include "volume/penetration.hpp"
#include "volume/testing/shapes.hpp"

namespace {

using namespace snag::volume;
using snag::Vec3;
namespace vt = snag::volume::testing;

class PenetrationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { openvdb::initialize(); }
};

// The sheet's faces that cross the sphere: the region a scan would report.
std::vector<std::size_t> crossing_faces(const TriangleMesh& sheet, const Vec3& centre, double radius) {
  std::vector<std::size_t> faces;
  for (std::size_t t = 0; t < sheet.triangles.size(); ++t) {
    int inside = 0;
    for (snag::Index v : sheet.triangles[t]) inside += squared_norm(sheet.vertices[v] - centre) < radius * radius;
    if (inside == 1 || inside == 2) faces.push_back(t);
  }
  return faces;
}

TEST_F(PenetrationTest, ASheetPushedIntoASphere) {
  const double radius = 1;
  const Vec3 centre{0.01, -0.02, 0};
  const TriangleMesh sphere = vt::icosphere(centre, radius, 4);  // 5120 faces
  for (double depth : {0.3, 0.1}) {
    const TriangleMesh cloth = vt::sheet({0, 0, radius - depth}, 3, 40);
    const std::vector<std::size_t> seeds = crossing_faces(cloth, centre, radius);
    ASSERT_FALSE(seeds.empty());
    Box region = triangle_box(cloth, seeds[0]);
    for (std::size_t f : seeds) region = {min(region.lo, triangle_box(cloth, f).lo), max(region.hi, triangle_box(cloth, f).hi)};
    const double h = 0.03;
    const Penetration measured = penetration(cloth, vertex_faces(cloth.triangles, cloth.vertices.size()), seeds,
                                             sphere, region, h);
    EXPECT_NEAR(measured.depth, depth, 0.1 * h + 0.002) << "depth " << depth;
    const double disc = M_PI * (radius * radius - (radius - depth) * (radius - depth));
    EXPECT_NEAR(measured.area, disc, 0.02 * disc) << "depth " << depth;
    ASSERT_TRUE(measured.level_set);
  }
}

TEST_F(PenetrationTest, ASheetThatOnlyTouchesHasNoDepth) {
  const TriangleMesh box = vt::box_mesh({-1, -1, -1}, {1, 1, 0});
  const TriangleMesh cloth = vt::sheet({0, 0, 0.05}, 1, 4);
  std::vector<std::size_t> all(cloth.triangles.size());
  for (std::size_t t = 0; t < all.size(); ++t) all[t] = t;
  const Penetration measured =
      penetration(cloth, vertex_faces(cloth.triangles, cloth.vertices.size()), all, box, mesh_box(cloth), 0.05);
  EXPECT_EQ(measured.depth, 0);
  EXPECT_EQ(measured.area, 0);
}

TEST(AreaBelowZero, CutsATriangleWhereTheLinearFunctionChangesSign) {
  EXPECT_DOUBLE_EQ(area_below_zero(2, -1, -1, -1), 2);
  EXPECT_DOUBLE_EQ(area_below_zero(2, 1, 1, 0), 0);
  // One corner below: the similar triangle with both sides halved.
  EXPECT_DOUBLE_EQ(area_below_zero(2, -1, 1, 1), 0.5);
  EXPECT_DOUBLE_EQ(area_below_zero(2, 1, -1, 1), 0.5);
  // Two corners below: the rest.
  EXPECT_DOUBLE_EQ(area_below_zero(2, 1, -1, -1), 1.5);
  EXPECT_DOUBLE_EQ(area_below_zero(2, -3, -3, 1), 2 - 2 * 0.25 * 0.25);
}

}  // namespace
