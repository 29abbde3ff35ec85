// The early exits of the CCD kernels. coplanarity_keeps_sign (thickness 0)
// fires on pairs that stay off each other's plane; vertex_face_separated and
// edge_edge_separated on pairs that a fixed direction keeps apart, and
// triangles_separated on whole triangle pairs so kept apart. None fires on
// contacts at t = 0, at t = 1, inside the step, nor (the cubic) on coplanar
// or degenerate pairs; where triangles_separated fires, no feature pair of
// the two triangles touches.
// Random contacts are built exactly (small integers, dyadic times and
// parameters) so that the ground truth is known without rounding.
#include "libcd/narrow_phase/ccd_coplanarity_filter.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>

#include "libcd/narrow_phase/ccd_separating_direction.hpp"
#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "tests/libcd/narrow_phase/ccd_test_support.hpp"

namespace snag {
namespace {

using Points = std::array<Vec3, 8>;

// The filter on the vertex-face coplanarity function (p - a) . ((b - a) x (c - a)).
bool vertex_face_filter(const Points& x) {
  return coplanarity_keeps_sign(x[1], x[0], x[1], x[2], x[1], x[3], x[5], x[4], x[5], x[6], x[5], x[7]);
}
// The filter on the edge-edge coplanarity function (eb0 - ea0) . ((ea1 - ea0) x (eb1 - eb0)).
bool edge_edge_filter(const Points& x) {
  return coplanarity_keeps_sign(x[0], x[2], x[0], x[1], x[2], x[3], x[4], x[6], x[4], x[5], x[6], x[7]);
}

bool vertex_face_apart(const Points& x, double thickness) {
  return vertex_face_separated(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], thickness);
}
bool edge_edge_apart(const Points& x, double thickness) {
  return edge_edge_separated(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], thickness);
}

CcdResult vertex_face(const Points& x, double thickness = 0) {
  CcdSettings settings;
  settings.thickness = thickness;
  return vertex_face_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings);
}
CcdResult edge_edge(const Points& x, double thickness = 0) {
  CcdSettings settings;
  settings.thickness = thickness;
  return edge_edge_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings);
}

// The unit right triangle in z = 0, static, and a vertex from p_t0 to p_t1.
Points static_face(const Vec3& p_t0, const Vec3& p_t1) {
  return {p_t0, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, p_t1, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
}

TEST(CoplanarityFilter, FiresOnAVertexThatStaysAboveTheFace) {
  // Inside the face's swept box, 1e-3 above it the whole step.
  const Points x = static_face({0.2, 0.2, 1e-3}, {0.3, 0.1, 2e-3});
  EXPECT_TRUE(vertex_face_filter(x));
  EXPECT_EQ(vertex_face(x).answer, CcdAnswer::kNo);
}

TEST(CoplanarityFilter, FiresOnAVertexBelowAMovingTiltingFace) {
  // The face rises and tilts but the vertex stays well below it.
  const Points x = {Vec3{0.3, 0.3, -1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                    Vec3{0.3, 0.3, -0.5}, {0, 0, 0.2}, {1, 0, 0.5}, {0, 1, 0.3}};
  EXPECT_TRUE(vertex_face_filter(x));
  EXPECT_EQ(vertex_face(x).answer, CcdAnswer::kNo);
}

TEST(CoplanarityFilter, DoesNotFireOnAContactAtTheStart) {
  const Points x = static_face({0.25, 0.25, 0}, {0.25, 0.25, 1});
  EXPECT_FALSE(vertex_face_filter(x));
  EXPECT_NE(vertex_face(x).answer, CcdAnswer::kNo);
}

TEST(CoplanarityFilter, DoesNotFireOnAContactAtTheEnd) {
  const Points x = static_face({0.25, 0.25, 1}, {0.25, 0.25, 0});
  EXPECT_FALSE(vertex_face_filter(x));
  EXPECT_NE(vertex_face(x).answer, CcdAnswer::kNo);
}

TEST(CoplanarityFilter, DoesNotFireOnACrossingOfAMovingFace) {
  // The face rises from z = 0 to z = 1/2 while the vertex goes from z = -1 to
  // z = 1: they meet at t = 2/3, inside the step.
  const Points x = {Vec3{0.25, 0.25, -1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                    Vec3{0.25, 0.25, 1}, {0, 0, 0.5}, {1, 0, 0.5}, {0, 1, 0.5}};
  EXPECT_FALSE(vertex_face_filter(x));
  EXPECT_NE(vertex_face(x).answer, CcdAnswer::kNo);
}

TEST(CoplanarityFilter, DoesNotFireWhenCoplanarTheWholeStep) {
  // Vertex sliding across the face in its plane: contact at every t where it is inside.
  const Points inside = static_face({0.1, 0.1, 0}, {0.3, 0.2, 0});
  EXPECT_FALSE(vertex_face_filter(inside));
  EXPECT_NE(vertex_face(inside).answer, CcdAnswer::kNo);
  // Coplanar but outside: the filter cannot tell (the inclusion search may).
  EXPECT_FALSE(vertex_face_filter(static_face({2, 2, 0}, {3, 2, 0})));
  // Two edges in the plane z = 0 crossing each other all the time.
  const Points edges = {Vec3{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0},
                        Vec3{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_FALSE(edge_edge_filter(edges));
  EXPECT_NE(edge_edge(edges).answer, CcdAnswer::kNo);
}

TEST(CoplanarityFilter, DoesNotFireOnDegenerateFeatures) {
  // Zero-area face (collinear corners), the vertex far above it.
  const Points flat = {Vec3{0.5, 0, 1}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0},
                       Vec3{0.5, 0, 2}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  EXPECT_FALSE(vertex_face_filter(flat));
  // Parallel edges, their coplanarity function identically zero: edge b
  // falls onto edge a at t = 1/2 and overlaps it on x in [0.5, 1].
  const Points parallel = {Vec3{0, 0, 0}, {1, 0, 0}, {0.5, 0, 1}, {1.5, 0, 1},
                           Vec3{0, 0, 0}, {1, 0, 0}, {0.5, 0, -1}, {1.5, 0, -1}};
  EXPECT_FALSE(edge_edge_filter(parallel));
  EXPECT_NE(edge_edge(parallel).answer, CcdAnswer::kNo);
  // Zero-length edge.
  const Points point_edge = {Vec3{0, 0, 0}, {0, 0, 0}, {-1, 1, 1}, {1, 1, 1},
                             Vec3{0, 0, 0}, {0, 0, 0}, {-1, -1, 1}, {1, -1, 1}};
  EXPECT_FALSE(edge_edge_filter(point_edge));
}

TEST(CoplanarityFilter, FiresOnEdgesThatStayApartAcrossTheirPlanes) {
  // Edge b passes 1e-3 above edge a, crossing over it in projection.
  const Points x = {Vec3{0, 0, 0}, {1, 0, 0}, {0.5, -1, 1e-3}, {0.5, 1, 1e-3},
                    Vec3{0, 0, 0}, {1, 0, 0}, {0.6, -1, 2e-3}, {0.4, 1, 2e-3}};
  EXPECT_TRUE(edge_edge_filter(x));
  EXPECT_EQ(edge_edge(x).answer, CcdAnswer::kNo);
}

TEST(SeparatingDirection, FiresOnAVertexCrossingThePlaneBesideTheFace) {
  // The vertex crosses z = 0 at x = 2, outside the unit triangle.
  const Points x = static_face({2, 0.2, -1}, {2, 0.3, 1});
  EXPECT_FALSE(vertex_face_filter(x));
  EXPECT_TRUE(vertex_face_apart(x, 0));
  EXPECT_TRUE(vertex_face_apart(x, 0.5));
  EXPECT_FALSE(vertex_face_apart(x, 1.5));  // the gap is 1: too thick to separate
  EXPECT_EQ(vertex_face(x).answer, CcdAnswer::kNo);
  EXPECT_EQ(vertex_face(x, 0.5).answer, CcdAnswer::kNo);
  EXPECT_NE(vertex_face(x, 1.5).answer, CcdAnswer::kNo);
}

TEST(SeparatingDirection, FiresOnAnEdgePassingBeyondTheOthersEnd) {
  // The lines of the edges cross at t = 1/2 at (2, 0, 0), beyond edge a's end.
  const Points x = {Vec3{0, 0, 0}, {1, 0, 0}, {2, -1, 1}, {2, 1, 1},
                    Vec3{0, 0, 0}, {1, 0, 0}, {2, -1, -1}, {2, 1, -1}};
  EXPECT_FALSE(edge_edge_filter(x));
  EXPECT_TRUE(edge_edge_apart(x, 0));
  EXPECT_TRUE(edge_edge_apart(x, 0.9));
  EXPECT_FALSE(edge_edge_apart(x, 1.0));  // the gap is exactly 1: touching at that thickness
  EXPECT_EQ(edge_edge(x).answer, CcdAnswer::kNo);
  EXPECT_NE(edge_edge(x, 1.0).answer, CcdAnswer::kNo);
}

TEST(SeparatingDirection, DoesNotFireOnContactsAtTheEnds) {
  EXPECT_FALSE(vertex_face_apart(static_face({0.25, 0.25, 0}, {3, 3, 1}), 0));
  EXPECT_FALSE(vertex_face_apart(static_face({3, 3, 1}, {0, 0, 0}), 0));  // at a corner at t = 1
  EXPECT_FALSE(vertex_face_apart(static_face({3, 3, 1}, {0.5, 0.5, 0}), 0));  // on an edge at t = 1
}

// --- random contacts built exactly -------------------------------------------

// A random point with integer coordinates in [-64, 64].
Vec3 integer_point(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> coordinate(-64, 64);
  return {double(coordinate(rng)), double(coordinate(rng)), double(coordinate(rng))};
}

// A dyadic time of contact: 0, 1, 2^-m or 1 - 2^-m. With it, the start or end
// position that puts a point at `target` at time t is exact in doubles.
double dyadic_time(std::mt19937_64& rng) {
  const double times[] = {0, 1, 0.5, 0.25, 0.75, 0.125, 0.875, 1.0 / 1024, 1 - 1.0 / 1024};
  return times[std::uniform_int_distribution<int>(0, 8)(rng)];
}

// Moves point (x_t0, x_t1) so that it is at `target` at time t, keeping one
// of its ends; exact for dyadic_time values and integer-sized coordinates.
void pass_through(Vec3& x_t0, Vec3& x_t1, const Vec3& target, double t) {
  if (t == 0) {
    x_t0 = target;
  } else if (t == 1) {
    x_t1 = target;
  } else if (t <= 0.5) {
    x_t1 = x_t0 + (1 / t) * (target - x_t0);
  } else {
    x_t0 = x_t1 - (1 / (1 - t)) * (x_t1 - target);
  }
  ASSERT_EQ(test::at(x_t0, x_t1, t).x, target.x);
  ASSERT_EQ(test::at(x_t0, x_t1, t).y, target.y);
  ASSERT_EQ(test::at(x_t0, x_t1, t).z, target.z);
}

TEST(CoplanarityFilter, NeverRejectsAVertexFaceContactBuiltExactly) {
  std::mt19937_64 rng(31);
  std::uniform_int_distribution<int> sixteenth(0, 16);
  for (int i = 0; i < 20000; ++i) {
    Points x;
    for (Vec3& p : x) p = integer_point(rng);
    const double t = dyadic_time(rng);
    int u = sixteenth(rng), v = sixteenth(rng);
    if (u + v > 16) u = 16 - u, v = 16 - v;
    const Vec3 a = test::at(x[1], x[5], t), b = test::at(x[2], x[6], t), c = test::at(x[3], x[7], t);
    const Vec3 target = ((16 - u - v) / 16.0) * a + (u / 16.0) * b + (v / 16.0) * c;
    pass_through(x[0], x[4], target, t);
    ASSERT_FALSE(vertex_face_filter(x)) << "case " << i;
    ASSERT_FALSE(vertex_face_apart(x, 0)) << "case " << i;
    ASSERT_FALSE(vertex_face_apart(x, 0.5)) << "case " << i;
    ASSERT_NE(vertex_face(x).answer, CcdAnswer::kNo) << "case " << i;
  }
}

TEST(CoplanarityFilter, NeverRejectsAnEdgeEdgeContactBuiltExactly) {
  std::mt19937_64 rng(32);
  std::uniform_int_distribution<int> sixteenth(0, 16), ratio(0, 8);
  for (int i = 0; i < 20000; ++i) {
    Points x;
    for (Vec3& p : x) p = integer_point(rng);
    const double t = dyadic_time(rng);
    const double s = sixteenth(rng) / 16.0, r = ratio(rng) / 4.0;
    const Vec3 ea0 = test::at(x[0], x[4], t), ea1 = test::at(x[1], x[5], t), eb0 = test::at(x[2], x[6], t);
    const Vec3 touch = (1 - s) * ea0 + s * ea1;
    // eb1 beyond the touching point, seen from eb0: the point lies on edge b.
    pass_through(x[3], x[7], touch + r * (touch - eb0), t);
    ASSERT_FALSE(edge_edge_filter(x)) << "case " << i;
    ASSERT_FALSE(edge_edge_apart(x, 0)) << "case " << i;
    ASSERT_FALSE(edge_edge_apart(x, 0.5)) << "case " << i;
    ASSERT_NE(edge_edge(x).answer, CcdAnswer::kNo) << "case " << i;
  }
}

// --- two whole triangles -------------------------------------------------------

// A triangle's corners at the start and end of the step.
struct MovingTriangle {
  Vec3 t0[3], t1[3];
};

// Corners a, b, c moving by `by` over the step.
MovingTriangle moving(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& by) {
  return {{a, b, c}, {a + by, b + by, c + by}};
}

bool apart(const MovingTriangle& a, const MovingTriangle& b, double thickness) {
  return triangles_separated(a.t0, a.t1, b.t0, b.t1, thickness);
}

// The points of vertex i of `from` against face `to`, as vertex_face() takes them.
Points vertex_against_face(const MovingTriangle& from, int i, const MovingTriangle& to) {
  return {from.t0[i], to.t0[0], to.t0[1], to.t0[2], from.t1[i], to.t1[0], to.t1[1], to.t1[2]};
}
// The points of edge i of a (corners i, i + 1) against edge j of b.
Points edge_against_edge(const MovingTriangle& a, int i, const MovingTriangle& b, int j) {
  const int i1 = (i + 1) % 3, j1 = (j + 1) % 3;
  return {a.t0[i], a.t0[i1], b.t0[j], b.t0[j1], a.t1[i], a.t1[i1], b.t1[j], b.t1[j1]};
}

TEST(TriangleSeparation, FiresOnLayersMovingTogetherAlongTheirNormal) {
  // Two layers 0.1 apart in z, both moving 3 along x: their swept boxes meet.
  const Vec3 by{3, 0, 0};
  const MovingTriangle a = moving({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, by);
  const MovingTriangle b = moving({0, 0, 0.1}, {1, 0, 0.1}, {0, 1, 0.1}, by);
  EXPECT_TRUE(apart(a, b, 0));
  EXPECT_TRUE(apart(b, a, 0));
  EXPECT_TRUE(apart(a, b, 0.05));
  EXPECT_FALSE(apart(a, b, 0.2));  // the layers are within the thickness
}

TEST(TriangleSeparation, FiresFarFromTheOriginAndAcrossItsRange) {
  // The projection form's bound grows with the pair's own extent (5e-7 of
  // its largest corner offset, the file comment), not with where it lies:
  // layers 0.1 apart are decided a billion units out.
  const Vec3 by{3, 0, 0};
  for (const double far : {1e6, -1e6, 1e9, -1e9}) {
    const Vec3 o{far, far, far};
    const MovingTriangle a = moving(o + Vec3{0, 0, 0}, o + Vec3{1, 0, 0}, o + Vec3{0, 1, 0}, by);
    EXPECT_TRUE(apart(a, moving(o + Vec3{0, 0, 0.1}, o + Vec3{1, 0, 0.1}, o + Vec3{0, 1, 0.1}, by), 0)) << far;
  }
  // Pairs of any size whose largest offset lies in [2^-100, 2^120], the same
  // shape scaled, with the thickness scaled alike; outside it, nothing is
  // decided.
  for (const double size : {1e-29, 1e-10, 1.0, 1e10, 1e35, 1e-31, 1e37}) {
    const bool in_range = size >= 1e-29 && size <= 1e35;
    const Vec3 step{size, 0, 0};
    const MovingTriangle a = moving({0, 0, 0}, {size, 0, 0}, {0, size, 0}, step);
    const MovingTriangle b = moving({0, 0, 0.1 * size}, {size, 0, 0.1 * size}, {0, size, 0.1 * size}, step);
    EXPECT_EQ(apart(a, b, 0), in_range) << size;
    EXPECT_EQ(apart(b, a, 0.05 * size), in_range) << size;
    EXPECT_FALSE(apart(a, b, 0.2 * size)) << size;
  }
}

TEST(TriangleSeparation, NeverFiresAtOrWithinTheThickness) {
  // Layers exactly `gap` apart in z (the coordinates' differences exact),
  // far from the origin where the offsets round: a thickness equal to the
  // gap is not exceeded, one a thousandth below it is, by far more than
  // the bound (5e-7 of the pair's extent).
  const double gap = 1000.15 - 1000.1;  // exact (Sterbenz), about 0.05
  for (const double far : {0.0, 1000.1, 3e5}) {
    const double z = far == 0 ? 0 : 1000.1;
    const Vec3 o{far, -far, 0};
    const Vec3 by{0.25, -0.5, 0};
    const MovingTriangle a = moving(o + Vec3{0, 0, z}, o + Vec3{1.3, 0.1, z}, o + Vec3{0.2, 0.9, z}, by);
    const MovingTriangle b =
        moving(o + Vec3{0.4, 0.3, z + gap}, o + Vec3{1.1, 0.2, z + gap}, o + Vec3{0.3, 1.2, z + gap}, by);
    ASSERT_EQ((z + gap) - z, gap);
    EXPECT_FALSE(apart(a, b, gap)) << far;
    EXPECT_FALSE(apart(b, a, gap)) << far;
    EXPECT_FALSE(apart(a, b, 2 * gap)) << far;
    EXPECT_TRUE(apart(a, b, gap * 0.999)) << far;
    EXPECT_TRUE(apart(b, a, gap * 0.999)) << far;
  }
}

TEST(TriangleSeparation, FiresOnNeighboursInOneSheetAcrossAnEdge) {
  // Coplanar, 0.1 / sqrt(2) apart across a's long edge, both falling 2 in z:
  // their normals do not separate them, an edge's in-plane normal does.
  const Vec3 by{0, 0, -2};
  const MovingTriangle a = moving({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, by);
  const MovingTriangle b = moving({1.05, 0.05, 0}, {1.05, 1.05, 0}, {0.05, 1.05, 0}, by);
  EXPECT_TRUE(apart(a, b, 0));
  EXPECT_TRUE(apart(b, a, 0));
  // The margin is the thickness times |s|_1 (the file comment, step 2),
  // sqrt(2) |s| along this edge's normal: 0.03 is well inside the gap.
  EXPECT_TRUE(apart(a, b, 0.03));
  EXPECT_FALSE(apart(a, b, 0.1));
}

TEST(TriangleSeparation, DoesNotFireOnTrianglesThatMeetInTheStep) {
  // b's corner (0.2, 0.2) passes through a's face at t = 0.5.
  const MovingTriangle a = moving({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0});
  const MovingTriangle b = moving({0.2, 0.2, 1}, {0.3, 0.2, 2}, {0.2, 0.3, 2}, {0, 0, -2});
  EXPECT_FALSE(apart(a, b, 0));
  EXPECT_FALSE(apart(b, a, 0));
  EXPECT_FALSE(apart(a, b, 0.5));
}

TEST(TriangleSeparation, DoesNotFireOnASharedCornerDegenerateTrianglesOrInputsOutOfRange) {
  const Vec3 by{3, 0, 0};
  const MovingTriangle a = moving({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, by);
  EXPECT_FALSE(apart(a, moving({0, 0, 0}, {-1, 0, 0}, {0, -1, 0}, by), 0));  // only the corner in common
  // Two segments far apart: every direction tried is zero.
  EXPECT_FALSE(apart(moving({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, by), moving({0, 0, 5}, {1, 0, 5}, {2, 0, 5}, by), 0));
  const MovingTriangle b = moving({0, 0, 0.1}, {1, 0, 0.1}, {0, 1, 0.1}, by);
  ASSERT_TRUE(apart(a, b, 0));
  for (const double bad : {1e61, -1e61, std::numeric_limits<double>::infinity(), std::nan("")}) {
    MovingTriangle far = b;
    far.t1[2].y = bad;
    EXPECT_FALSE(apart(a, far, 0)) << bad;
    EXPECT_FALSE(apart(far, a, 0)) << bad;
  }
  EXPECT_FALSE(apart(a, b, -1));
  EXPECT_FALSE(apart(a, b, std::nan("")));
  EXPECT_FALSE(apart(a, b, 1e61));
}

TEST(TriangleSeparation, NeverFiresOnAContactBuiltExactly) {
  std::mt19937_64 rng(33);
  std::uniform_int_distribution<int> sixteenth(0, 16), corner(0, 2), ratio(0, 8);
  for (int i = 0; i < 20000; ++i) {
    MovingTriangle a, b;
    for (int k = 0; k < 3; ++k) {
      a.t0[k] = integer_point(rng);
      a.t1[k] = integer_point(rng);
      b.t0[k] = integer_point(rng);
      b.t1[k] = integer_point(rng);
    }
    const double t = dyadic_time(rng);
    const Vec3 a0 = test::at(a.t0[0], a.t1[0], t), a1 = test::at(a.t0[1], a.t1[1], t),
               a2 = test::at(a.t0[2], a.t1[2], t);
    const int k = corner(rng);
    if (i % 2 == 0) {  // a corner of b on a's face
      int u = sixteenth(rng), v = sixteenth(rng);
      if (u + v > 16) u = 16 - u, v = 16 - v;
      pass_through(b.t0[k], b.t1[k], ((16 - u - v) / 16.0) * a0 + (u / 16.0) * a1 + (v / 16.0) * a2, t);
    } else {  // b's edge (k, k + 1) through a point of a's edge (0, 1)
      const double along = sixteenth(rng) / 16.0;
      const Vec3 touch = (1 - along) * a0 + along * a1;
      const Vec3 from = test::at(b.t0[k], b.t1[k], t);
      const int k1 = (k + 1) % 3;
      pass_through(b.t0[k1], b.t1[k1], touch + (ratio(rng) / 4.0) * (touch - from), t);
    }
    ASSERT_FALSE(apart(a, b, 0)) << "case " << i;
    ASSERT_FALSE(apart(b, a, 0)) << "case " << i;
    ASSERT_FALSE(apart(a, b, 0.5)) << "case " << i;
  }
}

TEST(TriangleSeparation, NoFeaturePairTouchesWhereItFires) {
  // Random small triangles moving a little, crowded so that many pairs come
  // close: wherever the triangles are proved apart, the CCD of each of their
  // 6 vertex-face and 9 edge-edge pairs never answers kYes.
  std::mt19937_64 rng(34);
  std::size_t fired = 0, touching = 0;
  for (int i = 0; i < 4000; ++i) {
    const double thickness = i % 4 == 3 ? 0.05 : 0;
    MovingTriangle tri[2];
    const Vec3 common_centre = test::random_point(rng, 1), common_velocity = test::random_point(rng, 1);
    for (MovingTriangle& m : tri) {
      const Vec3 centre = common_centre + test::random_point(rng, 0.5),
                 velocity = common_velocity + test::random_point(rng, 0.3);
      for (int k = 0; k < 3; ++k) {
        m.t0[k] = centre + test::random_point(rng, 0.6);
        m.t1[k] = m.t0[k] + velocity + test::random_point(rng, 0.1);
      }
    }
    const bool separated = apart(tri[0], tri[1], thickness);
    fired += separated;
    bool any_yes = false;
    for (int s = 0; s < 2; ++s)
      for (int k = 0; k < 3; ++k)
        any_yes |= vertex_face(vertex_against_face(tri[s], k, tri[1 - s]), thickness).answer == CcdAnswer::kYes;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        any_yes |= edge_edge(edge_against_edge(tri[0], k, tri[1], j), thickness).answer == CcdAnswer::kYes;
    touching += any_yes;
    ASSERT_FALSE(separated && any_yes) << "case " << i;
  }
  std::cout << "fired " << fired << ", touching " << touching << "\n";
  EXPECT_GT(fired, 1000u);    // the test fires on many pairs,
  EXPECT_GT(touching, 300u);  // and many others touch
}

}  // namespace
}  // namespace snag
