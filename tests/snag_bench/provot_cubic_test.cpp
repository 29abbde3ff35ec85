// Provot's cubic CCD (tools/bench/provot_cubic_ccd.hpp) on configurations
// whose answer is known analytically, in float and in double, and against
// the exact method on plain random crossings far from any degeneracy.
#include <gtest/gtest.h>

#include <random>

#include "tools/bench/ccd_methods.hpp"
#include "tools/bench/provot_cubic_ccd.hpp"

namespace snag::bench {
namespace {

template <typename T>
class ProvotCubic : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(ProvotCubic, Precisions);

/// A vertex falling from z = 1 to z = -1 at (x, y) onto the unit right triangle of z = 0.
std::array<Vec3, 8> falling_vertex(double x, double y) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  return {Vec3{x, y, 1}, a, b, c, Vec3{x, y, -1}, a, b, c};
}

TYPED_TEST(ProvotCubic, VertexThroughTheTriangleCollides) {
  EXPECT_TRUE(provot_cubic_ccd<TypeParam>(falling_vertex(0.25, 0.25), false));
}

TYPED_TEST(ProvotCubic, VertexBesideTheTriangleDoesNot) {
  EXPECT_FALSE(provot_cubic_ccd<TypeParam>(falling_vertex(0.75, 0.75), false));
  EXPECT_FALSE(provot_cubic_ccd<TypeParam>(falling_vertex(-0.1, 0.5), false));
}

TYPED_TEST(ProvotCubic, VertexStoppingAboveThePlaneDoesNot) {
  std::array<Vec3, 8> x = falling_vertex(0.25, 0.25);
  x[4].z = 0.1;
  EXPECT_FALSE(provot_cubic_ccd<TypeParam>(x, false));
}

TYPED_TEST(ProvotCubic, CrossedEdgesCollideAndOffsetOnesDoNot) {
  // Edge a along x at z = 0; edge b along y moving from z = 1 to z = -1 over a's middle.
  std::array<Vec3, 8> x = {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0.5, -0.5, 1}, Vec3{0.5, 0.5, 1},
                           Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0.5, -0.5, -1}, Vec3{0.5, 0.5, -1}};
  EXPECT_TRUE(provot_cubic_ccd<TypeParam>(x, true));
  for (int i : {2, 3, 6, 7}) x[i].x += 1;  // now past a's end
  EXPECT_FALSE(provot_cubic_ccd<TypeParam>(x, true));
}

TYPED_TEST(ProvotCubic, CoplanarForTheWholeStepIsTestedAtItsStartMiddleAndEnd) {
  // In the plane z = 0 throughout: the cubic is identically 0.
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  std::array<Vec3, 8> inside = {Vec3{-1, 0.25, 0}, a, b, c, Vec3{0.25, 0.25, 0}, a, b, c};  // ends inside
  EXPECT_TRUE(provot_cubic_ccd<TypeParam>(inside, false));
  std::array<Vec3, 8> outside = {Vec3{-1, 0.25, 0}, a, b, c, Vec3{-0.5, 0.25, 0}, a, b, c};
  EXPECT_FALSE(provot_cubic_ccd<TypeParam>(outside, false));
}

TYPED_TEST(ProvotCubic, CoordinatesBeyondFloatsRangeAreBounded) {
  // The vertex falls from z = 1e300 through the triangle. In float that start
  // is an infinity and no root is found (a miss, as documented); double finds it.
  std::array<Vec3, 8> x = falling_vertex(0.25, 0.25);
  x[0].z = 1e300;
  EXPECT_EQ(provot_cubic_ccd<TypeParam>(x, false), (std::is_same<TypeParam, double>::value));
}

TYPED_TEST(ProvotCubic, FindsEveryRootOfACubicInOrder) {
  // (t - 1/4)(t - 1/2)(t - 3/4) = t^3 - 3/2 t^2 + 11/16 t - 3/32
  cubic_detail::Cubic<TypeParam> f{1, TypeParam(-1.5), TypeParam(11.0 / 16), TypeParam(-3.0 / 32)};
  TypeParam roots[3];
  ASSERT_EQ(cubic_detail::unit_roots(f, roots), 3);
  const TypeParam tolerance = std::is_same<TypeParam, float>::value ? 1e-5f : 1e-12;
  EXPECT_NEAR(roots[0], 0.25, tolerance);
  EXPECT_NEAR(roots[1], 0.5, tolerance);
  EXPECT_NEAR(roots[2], 0.75, tolerance);
  // A root exactly at t = 1, and none outside [0, 1].
  cubic_detail::Cubic<TypeParam> g{0, 0, 1, -1};
  ASSERT_EQ(cubic_detail::unit_roots(g, roots), 1);
  EXPECT_EQ(roots[0], TypeParam(1));
  cubic_detail::Cubic<TypeParam> h{0, 0, 1, 2};
  EXPECT_EQ(cubic_detail::unit_roots(h, roots), 0);
}

TEST(ProvotCubicDouble, AgreesWithTheExactMethodOnPlainCrossings) {
  // Random vertices falling through or well beside random triangles: every
  // answer is decided by a margin of 0.05, far above the tolerance.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  int positives = 0;
  for (int i = 0; i < 200; ++i) {
    const double x = u(rng), y = u(rng);
    if (std::abs(x + y - 1) < 0.05 || x < 0.05 || y < 0.05) continue;
    CcdQueryPoints q{false, falling_vertex(x, y)};
    q.points[0].z = 0.1 + u(rng);
    q.points[4].z = -0.1 - u(rng);
    const bool truth = exact_collides(q);
    positives += truth;
    EXPECT_EQ(provot_cubic_ccd<double>(q.points, false), truth) << x << " " << y;
    EXPECT_EQ(provot_cubic_ccd<float>(q.points, false), truth) << x << " " << y;
  }
  EXPECT_GT(positives, 20);
}

}  // namespace
}  // namespace snag::bench
