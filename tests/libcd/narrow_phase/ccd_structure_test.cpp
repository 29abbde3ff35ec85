// The decisions by structure of ccd_structure.hpp on hand-made cases whose
// answers are known by construction: exact contact tests at one instant,
// exact comparison of displacements, and the kernels' answers on pairs that
// touch at t = 0 or do not move.
#include "libcd/narrow_phase/ccd_structure.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"

namespace snag {
namespace {

using ccd_detail::moves_together;
using ccd_detail::point_on_segment;
using ccd_detail::point_on_triangle;
using ccd_detail::segments_meet;

const Vec3 kA{0, 0, 0}, kB{1, 0, 0}, kC{0, 1, 0};

double up(double x) { return std::nextafter(x, 2.0); }

TEST(CcdStructure, PointOnTriangleIsExactOnCornersEdgesAndInterior) {
  EXPECT_TRUE(point_on_triangle(kA, kA, kB, kC));
  EXPECT_TRUE(point_on_triangle(kC, kA, kB, kC));
  EXPECT_TRUE(point_on_triangle({0.5, 0.5, 0}, kA, kB, kC));  // on the hypotenuse
  EXPECT_TRUE(point_on_triangle({0.25, 0, 0}, kA, kB, kC));
  EXPECT_TRUE(point_on_triangle({0.25, 0.25, 0}, kA, kB, kC));
  EXPECT_FALSE(point_on_triangle({0.5, up(0.5), 0}, kA, kB, kC));  // one ulp beyond the hypotenuse
  EXPECT_FALSE(point_on_triangle({0.25, 0.25, 0x1p-200}, kA, kB, kC));  // a hair above
  EXPECT_FALSE(point_on_triangle({-0x1p-200, 0.25, 0}, kA, kB, kC));
  // A tilted triangle whose plane is not a coordinate plane.
  const Vec3 a{1, 0, 0}, b{0, 1, 0}, c{0, 0, 1};
  EXPECT_TRUE(point_on_triangle({0.25, 0.25, 0.5}, a, b, c));
  EXPECT_FALSE(point_on_triangle({0.25, 0.25, up(0.5)}, a, b, c));
}

TEST(CcdStructure, PointOnCollapsedTriangleIsOnOneOfItsEdges) {
  const Vec3 a{0, 0, 0}, b{2, 2, 2}, m{1, 1, 1};
  EXPECT_TRUE(point_on_triangle({0.5, 0.5, 0.5}, a, b, m));
  EXPECT_TRUE(point_on_triangle(b, a, m, b));
  EXPECT_FALSE(point_on_triangle({3, 3, 3}, a, b, m));
  EXPECT_FALSE(point_on_triangle({0.5, 0.5, up(0.5)}, a, b, m));
  EXPECT_TRUE(point_on_triangle(m, m, m, m));  // a triangle collapsed to a point
  EXPECT_FALSE(point_on_triangle(a, m, m, m));
}

TEST(CcdStructure, PointOnSegmentNeedsCollinearAndBetween) {
  EXPECT_TRUE(point_on_segment({0.5, 0, 0}, kA, kB));
  EXPECT_TRUE(point_on_segment(kB, kA, kB));
  EXPECT_FALSE(point_on_segment({1.5, 0, 0}, kA, kB));
  EXPECT_FALSE(point_on_segment({0.5, 0x1p-200, 0}, kA, kB));
  EXPECT_TRUE(point_on_segment(kA, kA, kA));
  EXPECT_FALSE(point_on_segment(kB, kA, kA));
}

TEST(CcdStructure, SegmentsMeetDecidesCrossingsTouchesAndParallels) {
  EXPECT_TRUE(segments_meet({-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}));          // cross
  EXPECT_TRUE(segments_meet({-1, 0, 0}, {1, 0, 0}, {0, 0, 0}, {0, 1, 0}));           // T touch
  EXPECT_TRUE(segments_meet({-1, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 1, 0}));           // shared end
  EXPECT_TRUE(segments_meet({0, 0, 0}, {2, 0, 0}, {1, 0, 0}, {3, 0, 0}));            // collinear overlap
  EXPECT_FALSE(segments_meet({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}));           // collinear apart
  EXPECT_FALSE(segments_meet({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}));           // parallel apart
  EXPECT_FALSE(segments_meet({-1, 0, 0}, {1, 0, 0}, {0, -1, 0x1p-200}, {0, 1, 0}));  // skew by a hair
  EXPECT_FALSE(segments_meet({-1, 0, 0}, {1, 0, 0}, {0, 0x1p-200, 0}, {0, 1, 0}));    // T missed by a hair
  EXPECT_TRUE(segments_meet({0.5, 0, 0}, {0.5, 0, 0}, kA, kB));                      // a point on the edge
  EXPECT_FALSE(segments_meet({0.5, 1, 0}, {0.5, 1, 0}, kA, kB));
  // Crossing in a plane that is not a coordinate plane.
  EXPECT_TRUE(segments_meet({1, 0, 0}, {0, 1, 1}, {0, 0, 1}, {1, 1, 0}));
}

TEST(CcdStructure, MovesTogetherComparesDisplacementsExactly) {
  const Vec3 d{3, -2, 0.5};
  const Vec3 same[8] = {kA, kB, kC, {5, 5, 5}, kA + d, kB + d, kC + d, Vec3{5, 5, 5} + d};
  EXPECT_TRUE(moves_together(same));
  const Vec3 still[8] = {kA, kB, kC, kA, kA, kB, kC, kA};
  EXPECT_TRUE(moves_together(still));
  // 1 - 2^-60 and 1 round to the same double, but are different displacements.
  const Vec3 rounded[8] = {{0x1p-60, 0, 0}, kA, kB, kC, {1, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0}};
  EXPECT_FALSE(moves_together(rounded));
}

TEST(CcdStructure, KernelsProveContactsAtTheStart) {
  // A vertex on the face's corner b moving away, and one inside the face.
  for (const Vec3& p : {kB, Vec3{0.25, 0.5, 0}}) {
    const CcdResult r = vertex_face_ccd(p, kA, kB, kC, p + Vec3{1, 2, 3}, kA, kB, kC, {});
    EXPECT_EQ(r.answer, CcdAnswer::kYes);
    EXPECT_EQ(r.toi_lo, 0);
    EXPECT_EQ(r.toi_hi, 0);
  }
  // Two edges sharing an end, each moving its own way.
  const CcdResult ee = edge_edge_ccd(kA, kB, kA, kC, Vec3{0, 0, 1}, kB, Vec3{0, 0, -1}, kC, {});
  EXPECT_EQ(ee.answer, CcdAnswer::kYes);
  EXPECT_EQ(ee.toi_hi, 0);
  // Within the thickness at t = 0 without touching.
  const CcdResult thick = vertex_face_ccd({0.25, 0.25, 0.1}, kA, kB, kC, {0.25, 0.25, 5}, kA, kB, kC, {0.125});
  EXPECT_EQ(thick.answer, CcdAnswer::kYes);
  EXPECT_EQ(thick.toi_hi, 0);
  const CcdResult thick_ee =
      edge_edge_ccd({-1, 0, 0.1}, {1, 0, 0.1}, {0, -1, 0}, {0, 1, 0}, {-1, 0, 5}, {1, 0, 5}, {0, -1, 0}, {0, 1, 0},
                    {0.125});
  EXPECT_EQ(thick_ee.answer, CcdAnswer::kYes);
  EXPECT_EQ(thick_ee.toi_hi, 0);
}

TEST(CcdStructure, KernelsDecidePairsThatMoveAsOne) {
  // Resting beside the face in its plane, and translating with it: never
  // touching. The structure alone decides it.
  const Vec3 d{0.5, -0.25, 2};
  const Vec3 p{0.5, 0.5 + 0x1p-30, 0};
  EXPECT_EQ(vertex_face_ccd(p, kA, kB, kC, p, kA, kB, kC, {}).answer, CcdAnswer::kNo);
  EXPECT_EQ(vertex_face_ccd(p, kA, kB, kC, p + d, kA + d, kB + d, kC + d, {}).answer, CcdAnswer::kNo);
  CcdResult r;
  ASSERT_TRUE(vertex_face_structure(ccd_detail::VertexFaceContact{{p, kA, kB, kC, p + d, kA + d, kB + d, kC + d}},
                                    CcdSettings{}, &r));
  EXPECT_EQ(r.answer, CcdAnswer::kNo);
  // Moving apart from a contact is not moving as one: a later touch is for
  // the search to find.
  EXPECT_FALSE(vertex_face_structure(ccd_detail::VertexFaceContact{{p, kA, kB, kC, p + d, kA, kB, kC}},
                                     CcdSettings{}, &r));
  // Collinear edges end to end with a gap, moving together.
  const Vec3 e0{2, 0, 0}, e1{3, 0, 0};
  EXPECT_EQ(edge_edge_ccd(kA, kB, e0, e1, kA + d, kB + d, e0 + d, e1 + d, {}).answer, CcdAnswer::kNo);
}

}  // namespace
}  // namespace snag
