// orient2d and orient3d against exact rational determinants (GMP rationals),
// on random, near-degenerate and extreme-exponent inputs.
#include <CGAL/Gmpq.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "libcd/geometry/predicates.hpp"

namespace snag {
namespace {

using Rational = CGAL::Gmpq;

int rational_sign(const Rational& x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }

/// det[a-d, b-d, c-d] in exact rationals (Shewchuk's orient3d convention).
int oracle_orient3d(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  const Rational adx = Rational(a.x) - Rational(d.x), ady = Rational(a.y) - Rational(d.y),
                 adz = Rational(a.z) - Rational(d.z);
  const Rational bdx = Rational(b.x) - Rational(d.x), bdy = Rational(b.y) - Rational(d.y),
                 bdz = Rational(b.z) - Rational(d.z);
  const Rational cdx = Rational(c.x) - Rational(d.x), cdy = Rational(c.y) - Rational(d.y),
                 cdz = Rational(c.z) - Rational(d.z);
  return rational_sign(adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) +
                       cdz * (adx * bdy - bdx * ady));
}

int oracle_orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  const Rational acx = Rational(ax) - Rational(cx), acy = Rational(ay) - Rational(cy);
  const Rational bcx = Rational(bx) - Rational(cx), bcy = Rational(by) - Rational(cy);
  return rational_sign(acx * bcy - acy * bcx);
}

/// Moves x by `ulps` representable doubles (negative: downwards).
double nudge(double x, int ulps) {
  for (; ulps > 0; --ulps) x = std::nextafter(x, INFINITY);
  for (; ulps < 0; ++ulps) x = std::nextafter(x, -INFINITY);
  return x;
}

struct Sampler {
  std::mt19937_64 rng{12345};
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
  Vec3 point(double extent) { return {uniform(-extent, extent), uniform(-extent, extent), uniform(-extent, extent)}; }
  /// A point of the plane abc rounded to doubles, then nudged by a few ulps.
  Vec3 near_plane(Vec3 a, Vec3 b, Vec3 c) {
    const double s = uniform(-1, 2), t = uniform(-1, 2);
    Vec3 p = a + s * (b - a) + t * (c - a);
    for (int i = 0; i < 3; ++i) p[i] = nudge(p[i], integer(-2, 2));
    return p;
  }
};

TEST(Orient3d, MatchesRationalsOnRandomPoints) {
  Sampler sampler;
  for (int n = 0; n < 20000; ++n) {
    const Vec3 a = sampler.point(1), b = sampler.point(1), c = sampler.point(1), d = sampler.point(1);
    ASSERT_EQ(orient3d(a, b, c, d), oracle_orient3d(a, b, c, d));
  }
}

TEST(Orient3d, MatchesRationalsOnPointsWithinAFewUlpsOfAPlane) {
  Sampler sampler;
  PredicateCounters counters;
  for (int n = 0; n < 20000; ++n) {
    const double extent = std::ldexp(1.0, sampler.integer(-40, 40));
    const Vec3 a = sampler.point(extent), b = sampler.point(extent), c = sampler.point(extent);
    const Vec3 d = sampler.near_plane(a, b, c);
    const int expected = oracle_orient3d(a, b, c, d);
    ASSERT_EQ(orient3d(a, b, c, d, &counters), expected) << "case " << n;
    // Every argument order gives the permutation's sign.
    ASSERT_EQ(orient3d(b, a, c, d), -expected);
    ASSERT_EQ(orient3d(d, b, c, a), -expected);
  }
  EXPECT_GT(counters.exact, 1000u) << "near-degenerate input should reach the exact stage";
}

TEST(Orient3d, MatchesRationalsOnSmallIntegerGridsWithManyZeros) {
  Sampler sampler;
  int zero_count = 0;
  for (int n = 0; n < 20000; ++n) {
    const double scale = std::ldexp(1.0, sampler.integer(-240, 240));
    Vec3 p[4];
    for (Vec3& q : p)
      q = Vec3{double(sampler.integer(-3, 3)), double(sampler.integer(-3, 3)), double(sampler.integer(-3, 3))} * scale;
    const int expected = oracle_orient3d(p[0], p[1], p[2], p[3]);
    zero_count += expected == 0;
    ASSERT_EQ(orient3d(p[0], p[1], p[2], p[3]), expected);
  }
  EXPECT_GT(zero_count, 500);
}

TEST(Orient3d, MatchesRationalsWithHugeAndTinyExponentsTogether) {
  // The tilted plane x + y + z = huge (huge up to 2^249) and a point on it
  // whose zero x coordinate is replaced by +-tiny (down to 2^-249) or kept:
  // only the exact stage can see the offset.
  Sampler sampler;
  PredicateCounters counters;
  int zero_count = 0;
  for (int n = 0; n < 5000; ++n) {
    const double huge = std::ldexp(1.0, sampler.integer(150, 249));
    const double tiny = sampler.integer(-1, 1) * std::ldexp(1.0, sampler.integer(-249, -150));
    const double y = huge * sampler.integer(-1024, 1024) / 1024.0;
    const Vec3 a{huge, 0, 0}, b{0, huge, 0}, c{0, 0, huge};
    const Vec3 d{tiny, y, huge - y};
    const int expected = oracle_orient3d(a, b, c, d);
    zero_count += expected == 0;
    ASSERT_EQ(orient3d(a, b, c, d, &counters), expected) << "case " << n;
    ASSERT_EQ(orient3d(d, a, b, c, &counters), -expected) << "case " << n;
    // Mixed magnitudes within each point, in general position.
    const Vec3 e{sampler.uniform(-1, 1) * huge, tiny, sampler.uniform(-1, 1)};
    ASSERT_EQ(orient3d(a, e, c, d), oracle_orient3d(a, e, c, d)) << "case " << n;
  }
  EXPECT_GT(counters.exact, 5000u);
  EXPECT_GT(zero_count, 1000);
}

TEST(Orient3d, AllFloat32InputsAreInTheExactRange) {
  EXPECT_TRUE(is_in_exact_range(double(std::numeric_limits<float>::max())));
  EXPECT_TRUE(is_in_exact_range(double(std::numeric_limits<float>::denorm_min())));
  EXPECT_TRUE(is_in_exact_range(0.0));
  EXPECT_FALSE(is_in_exact_range(1e300));
  EXPECT_FALSE(is_in_exact_range(1e-300));
}

TEST(Orient2d, MatchesRationalsOnNearCollinearPoints) {
  Sampler sampler;
  PredicateCounters counters;
  for (int n = 0; n < 20000; ++n) {
    const double extent = std::ldexp(1.0, sampler.integer(-200, 200));
    const double ax = sampler.uniform(-extent, extent), ay = sampler.uniform(-extent, extent);
    const double bx = sampler.uniform(-extent, extent), by = sampler.uniform(-extent, extent);
    const double s = sampler.uniform(-1, 2);
    const double cx = nudge(ax + s * (bx - ax), sampler.integer(-2, 2));
    const double cy = nudge(ay + s * (by - ay), sampler.integer(-2, 2));
    const int expected = oracle_orient2d(ax, ay, bx, by, cx, cy);
    ASSERT_EQ(orient2d(ax, ay, bx, by, cx, cy, &counters), expected) << "case " << n;
    ASSERT_EQ(orient2d(bx, by, ax, ay, cx, cy), -expected);
  }
  EXPECT_GT(counters.exact, 1000u);
}

TEST(Orient2d, MatchesRationalsWithHugeAndTinyExponentsTogether) {
  Sampler sampler;
  for (int n = 0; n < 5000; ++n) {
    const double huge = std::ldexp(1.0, sampler.integer(150, 249));
    const double tiny = sampler.integer(-1, 1) * std::ldexp(1.0, sampler.integer(-249, -150));
    const double y = std::ldexp(double(sampler.integer(-1000, 1000)), sampler.integer(0, 150));
    const double cx = sampler.uniform(-1, 1) * huge;
    ASSERT_EQ(orient2d(-huge, y, huge, y, cx, y + tiny), oracle_orient2d(-huge, y, huge, y, cx, y + tiny));
  }
}

TEST(PredicateCounters, CountOnlyUndecidedCasesAsExact) {
  PredicateCounters counters;
  EXPECT_EQ(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}, &counters), 1);
  EXPECT_EQ(counters.calls, 1u);
  EXPECT_EQ(counters.exact, 0u);
  // Coplanar but with no zero difference: the filter cannot prove zero.
  EXPECT_EQ(orient3d({0.1, 0.2, 0.3}, {1.1, 0.7, 0.3}, {0.3, 1.9, 0.3}, {0.7, 0.5, 0.3}, &counters), 0);
  EXPECT_EQ(counters.calls, 2u);
  EXPECT_EQ(counters.exact, 0u) << "equal z makes every z difference an exact zero";
  // a, b, c collinear: the determinant is zero with a nonzero permanent,
  // which the filter cannot certify.
  EXPECT_EQ(orient3d({1, 1, 1}, {3, 5, 7}, {2, 3, 4}, {0.5, 0.25, 2}, &counters), 0);
  EXPECT_EQ(counters.calls, 3u);
  EXPECT_EQ(counters.exact, 1u);
}

}  // namespace
}  // namespace snag
