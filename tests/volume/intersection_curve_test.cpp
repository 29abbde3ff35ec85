// intersection_curve_length(): two sheets crossing at right angles along a
// known segment, a sheet folded through itself, and a flat sheet whose
// neighbouring faces share edges and vertices only (no curve).
#include <gtest/gtest.h>

#include <numeric>

#include "volume/intersection_curve.hpp"
#include "volume/testing/shapes.hpp"

namespace {

using namespace snag::volume;
using snag::Vec3;
namespace vt = snag::volume::testing;

std::vector<std::size_t> all_faces(const TriangleMesh& mesh) {
  std::vector<std::size_t> faces(mesh.triangles.size());
  std::iota(faces.begin(), faces.end(), 0);
  return faces;
}

TEST(IntersectionCurve, TwoSheetsCrossingAtRightAngles) {
  // A 2 x 2 sheet at z = 0 and a 1.5 x 1.5 one turned upright (the plane y = 0.1):
  // they cross along x in [-0.75, 0.75] at y = 0.1, z = 0.
  const TriangleMesh flat = vt::sheet({0, 0, 0.0}, 2, 8);
  const TriangleMesh upright = vt::turned_about_x(vt::sheet({0.013, 0.1, 0.0}, 1.5, 5), {0.013, 0.1, 0.0});
  const CurveLength curve = intersection_curve_length(flat, all_faces(flat), upright, all_faces(upright), false);
  EXPECT_NEAR(curve.length, 1.5, 1e-12);
  EXPECT_GT(curve.segments, 6u);
  EXPECT_EQ(curve.coplanar, 0u);
}

TEST(IntersectionCurve, ASheetFoldedThroughItself) {
  // One open mesh of both sheets: a self-intersection of one object.
  const TriangleMesh flat = vt::sheet({0, 0, 0.0}, 2, 8);
  const TriangleMesh upright = vt::turned_about_x(vt::sheet({0.013, 0.1, 0.0}, 1.5, 5), {0.013, 0.1, 0.0});
  const TriangleMesh folded = vt::joined(flat, upright);
  const CurveLength curve = intersection_curve_length(folded, all_faces(folded), folded, {}, true);
  EXPECT_NEAR(curve.length, 1.5, 1e-12);
}

TEST(IntersectionCurve, NeighboursThatShareEdgesDoNotCount) {
  const TriangleMesh flat = vt::sheet({0, 0, 0.0}, 2, 8);
  const CurveLength curve = intersection_curve_length(flat, all_faces(flat), flat, {}, true);
  EXPECT_EQ(curve.length, 0);
  EXPECT_EQ(curve.segments, 0u);
}

TEST(IntersectionCurve, OverlappingCoplanarSheetsAreCountedApart) {
  const TriangleMesh a = vt::sheet({0, 0, 0.0}, 1, 2);
  const TriangleMesh b = vt::sheet({0.3, 0.1, 0.0}, 1, 2);
  const CurveLength curve = intersection_curve_length(a, all_faces(a), b, all_faces(b), false);
  EXPECT_EQ(curve.length, 0);
  EXPECT_GT(curve.coplanar, 0u);
}

}  // namespace
