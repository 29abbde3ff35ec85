// The early exits of the CCD kernels. coplanarity_keeps_sign (thickness 0)
// fires on pairs that stay off each other's plane; vertex_face_separated and
// edge_edge_separated on pairs that a fixed direction keeps apart. Neither
// fires on contacts at t = 0, at t = 1, inside the step, nor (the cubic) on
// coplanar or degenerate pairs.
// Random contacts are built exactly (small integers, dyadic times and
// parameters) so that the ground truth is known without rounding.
#include "libcd/narrow_phase/ccd_coplanarity_filter.hpp"

#include <gtest/gtest.h>

#include <array>
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

}  // namespace
}  // namespace snag
