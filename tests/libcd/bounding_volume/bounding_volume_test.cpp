// Tests for bounding_volume/: swept 18-DOPs contain the moving triangle at
// every sampled time, thickness inflation contains the thickness ball,
// bounding spheres contain their points, and float boxes are rounded outward
// (boxes apart only where the DOPs are apart).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "libcd/bounding_volume/bounding_sphere.hpp"
#include "libcd/bounding_volume/float_box.hpp"
#include "libcd/bounding_volume/primitive_bounds.hpp"

namespace snag {
namespace {

Vec3 random_point(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return {u(rng), u(rng), u(rng)};
}

TEST(SweptDop, ContainsSweptTriangleAtSampledTimes) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const double scale = trial % 2 ? 1e3 : 1e-2;
    Vec3 p_t0[3], p_t1[3];
    for (int i = 0; i < 3; ++i) {
      p_t0[i] = random_point(rng, scale);
      p_t1[i] = p_t0[i] + random_point(rng, scale * 0.5);
    }
    const Dop18 dop = swept_dop(p_t0, p_t1, 3, 0.0);
    for (int s = 0; s < 200; ++s) {
      const double t = unit(rng);
      double b0 = unit(rng), b1 = unit(rng);
      if (b0 + b1 > 1) b0 = 1 - b0, b1 = 1 - b1;
      const double b2 = 1 - b0 - b1;
      Vec3 q[3];
      for (int i = 0; i < 3; ++i) q[i] = lerp(p_t0[i], p_t1[i], t);
      EXPECT_TRUE(dop_contains(dop, b0 * q[0] + b1 * q[1] + b2 * q[2]));
    }
  }
}

TEST(SweptDop, ThicknessInflationContainsTheBall) {
  std::mt19937 rng(3);
  const Vec3 v_t0{1, 2, 3}, v_t1{1.5, 2, 2};
  const double h = 0.25;
  const Dop18 dop = swept_dop(&v_t0, &v_t1, 1, h);
  std::normal_distribution<double> g;
  for (int s = 0; s < 1000; ++s) {
    Vec3 d{g(rng), g(rng), g(rng)};
    d = d / std::sqrt(squared_norm(d)) * h;
    const double t = (s % 11) / 10.0;
    EXPECT_TRUE(dop_contains(dop, lerp(v_t0, v_t1, t) + d));
  }
  EXPECT_FALSE(dop_contains(dop, v_t0 + Vec3{0, 0, 2 * h}));
}

TEST(Dop18, OverlapIsClosedAndSymmetric) {
  const Vec3 a[2] = {{0, 0, 0}, {1, 1, 1}};
  const Vec3 b[2] = {{1, 1, 1}, {2, 2, 2}};  // touches a in one point
  const Vec3 c[2] = {{1.5, 0, 0}, {2, 0.4, 0}};  // inside a's box slabs? no: x beyond
  const Dop18 da = dop_of_points(a, 2, 0, 0), db = dop_of_points(b, 2, 0, 0), dc = dop_of_points(c, 2, 0, 0);
  EXPECT_TRUE(dop_overlap(da, db));
  EXPECT_TRUE(dop_overlap(db, da));
  EXPECT_FALSE(dop_overlap(da, dc));
  EXPECT_FALSE(dop_overlap(dc, da));
  // Boxes overlap but a diagonal slab separates: the segment (0,0,0)-(1,1,1)
  // against the point (0.9, 0.1, 0.5) (x - y = 0.8 versus 0).
  const Vec3 p{0.9, 0.1, 0.5};
  const Dop18 dp = dop_of_points(&p, 1, 0, 0);
  EXPECT_FALSE(dop_overlap(da, dp));
}

TEST(FloatBox, BoundsAreTheNearestFloatsOnTheirSide) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-160, 140);  // float's denormals to past its range
  std::vector<double> values = {0.0, -0.0, 1.0, -1.0, 0.1, -0.1, 1e-45, -1e-45, 3.4e38, 3.5e38, -3.5e38, 1e300,
                                -1e300, kInf, -kInf};
  for (int i = 0; i < 100000; ++i) values.push_back(std::ldexp(mantissa(rng), exponent(rng)));
  for (double d : values) {
    const float below = float_at_most(d), above = float_at_least(d);
    ASSERT_LE(static_cast<double>(below), d) << d;
    ASSERT_GE(static_cast<double>(above), d) << d;
    if (std::isinf(d)) continue;
    // Nearest on its side: the next float outward would pass d.
    ASSERT_GT(static_cast<double>(std::nextafter(below, std::numeric_limits<float>::infinity())), d) << d;
    ASSERT_LT(static_cast<double>(std::nextafter(above, -std::numeric_limits<float>::infinity())), d) << d;
    if (static_cast<double>(static_cast<float>(d)) == d) {
      EXPECT_EQ(below, static_cast<float>(d));
      EXPECT_EQ(above, static_cast<float>(d));
    }
  }
  EXPECT_TRUE(std::isnan(float_at_most(std::nan(""))));
  EXPECT_TRUE(std::isnan(float_at_least(std::nan(""))));
}

TEST(FloatBox, BoxesApartOnlyWhereTheDopsAreApart) {
  // Slabs that meet or miss each other by less than a float's spacing, where
  // rounding either way decides: the boxes must never call apart what the
  // DOPs call overlapping, and they must still part most pairs the DOPs part
  // along x, y or z by more than that spacing.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0, 1);
  std::uniform_int_distribution<int> axis_of(0, 2);
  int rejected = 0, rejectable = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    const double scale = std::ldexp(1.0, static_cast<int>(unit(rng) * 40) - 20);
    Dop18 a, b;
    for (int k = 0; k < kDopAxes; ++k) {
      a.lo[k] = b.lo[k] = -scale;
      a.hi[k] = b.hi[k] = scale;
    }
    const int axis = axis_of(rng);
    const double gap = (unit(rng) - 0.5) * scale * (trial % 2 ? 1e-5 : 1e-9);  // < 0: they overlap
    a.hi[axis] = scale * (0.5 + unit(rng));
    b.lo[axis] = a.hi[axis] + gap;
    const bool dops = dop_overlap(a, b);
    const bool boxes = float_boxes_may_overlap(float_box_of(a), float_box_of(b));
    ASSERT_TRUE(boxes || !dops) << "axis " << axis << " a.hi " << a.hi[axis] << " b.lo " << b.lo[axis];
    if (gap > 4 * scale * std::numeric_limits<float>::epsilon()) {
      ++rejectable;
      rejected += !boxes;
    }
  }
  EXPECT_GT(rejectable, 1000);
  EXPECT_EQ(rejected, rejectable);
}

TEST(FloatBox, NanBoundsLeaveTheDecisionToTheDops) {
  Dop18 a, b;
  for (int k = 0; k < kDopAxes; ++k) {
    a.lo[k] = 0, a.hi[k] = 1;
    b.lo[k] = 2, b.hi[k] = 3;
  }
  a.hi[0] = a.hi[1] = a.hi[2] = std::nan("");
  b.lo[0] = b.lo[1] = b.lo[2] = std::nan("");
  EXPECT_TRUE(float_boxes_may_overlap(float_box_of(a), float_box_of(b)));
}

TEST(FloatBox, BoxesTheSweepFindsApartInYAreApart) {
  // sweep_low(b) > sweep_high(a) must mean float_boxes_may_overlap(a, b) is
  // false: the cells' sweeps cull such pairs untested. Bounds of a few
  // values, NaN among them (the sweep takes it as -inf or +inf).
  const float values[] = {-1.0f, -0.0f, 0.0f, 1.0f, 2.0f, INFINITY, -INFINITY, std::nanf("")};
  int apart = 0;
  for (float a_lo : values)
    for (float a_hi : values)
      for (float b_lo : values)
        for (float b_hi : values) {
          FloatBox a{{0, a_lo, 0}, {1, a_hi, 1}}, b{{0, b_lo, 0}, {1, b_hi, 1}};
          // The sweep's order is total: no NaN (its lower bound as -inf, its upper as +inf).
          ASSERT_EQ(sweep_low(a), std::isnan(a_lo) ? -INFINITY : a_lo);
          ASSERT_EQ(sweep_high(a), std::isnan(a_hi) ? INFINITY : a_hi);
          if (!(sweep_low(b) > sweep_high(a))) continue;
          ++apart;
          ASSERT_FALSE(float_boxes_may_overlap(a, b)) << a_lo << " " << a_hi << " " << b_lo << " " << b_hi;
        }
  EXPECT_GT(apart, 100);
}

TEST(BoundingSphere, ContainsItsPoints) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 100; ++trial) {
    Vec3 points[6];
    for (Vec3& p : points) p = random_point(rng, 10);
    const Sphere s = sphere_of_points(points, 6);
    for (const Vec3& p : points) EXPECT_LE(std::sqrt(squared_norm(p - s.centre)), s.radius * (1 + 1e-12));
  }
}

}  // namespace
}  // namespace snag
