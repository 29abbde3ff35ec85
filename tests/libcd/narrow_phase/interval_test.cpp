// Outward-rounded interval arithmetic against the exact results given by
// error-free transformations (TwoSum, and fma for products).
#include "libcd/narrow_phase/interval.hpp"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <random>
#include <vector>

namespace snag {
namespace {

// True when the exact value s + e (e the rounding error of s) lies in r.
bool encloses(Interval r, double s, double e) {
  const bool above_lo = r.lo < s || (r.lo == s && e >= 0);
  const bool below_hi = r.hi > s || (r.hi == s && e <= 0);
  return above_lo && below_hi;
}

double two_sum_error(double a, double b, double s) {
  const double b_virtual = s - a;
  const double a_virtual = s - b_virtual;
  return (a - a_virtual) + (b - b_virtual);
}

TEST(Interval, SumsAndProductsEncloseTheExactResult) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-1070, 60);
  for (int i = 0; i < 200000; ++i) {
    const double a = std::ldexp(mantissa(rng), exponent(rng) / 2);
    const double b = std::ldexp(mantissa(rng), exponent(rng) / 2);
    const double c = std::ldexp(mantissa(rng), exponent(rng));
    const double sum = a + c, product = a * b;
    ASSERT_TRUE(encloses(point_interval(a) + point_interval(c), sum, two_sum_error(a, c, sum))) << a << " " << c;
    ASSERT_TRUE(encloses(point_interval(a) * point_interval(b), product, std::fma(a, b, -product))) << a << " " << b;
  }
}

TEST(Interval, StepsOutwardAcrossPowersOfTwoAndSubnormals) {
  EXPECT_LT(round_down(1.0), 1.0);
  EXPECT_GT(round_up(1.0), 1.0);
  EXPECT_LT(round_down(0.0), 0.0);
  EXPECT_GT(round_up(0.0), 0.0);
  const Interval subnormal = point_interval(1e-310) * point_interval(1e-10);  // about 1e-320
  EXPECT_LT(subnormal.lo, subnormal.hi);
  EXPECT_GT(subnormal.lo, 0.0);
  const Interval underflow = point_interval(1e-200) * point_interval(1e-200);  // rounds to zero
  EXPECT_LT(underflow.lo, 0.0);
  EXPECT_GT(underflow.hi, 0.0);
}

TEST(Interval, NextUpAndDownAreNextafterForEveryFiniteDouble) {
  std::vector<double> values = {0.0, -0.0, 1.0, -1.0, 0.5, 2.0, DBL_MIN, -DBL_MIN, DBL_TRUE_MIN, -DBL_TRUE_MIN,
                                DBL_MAX, -DBL_MAX, std::nextafter(DBL_MIN, 0.0), 1e-310, -1e-310};
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> exponent(-1074, 1023);
  std::uniform_real_distribution<double> mantissa(-2.0, 2.0);
  for (int i = 0; i < 100000; ++i) values.push_back(std::ldexp(mantissa(rng), exponent(rng)));
  for (const double x : values) {
    if (x != DBL_MAX) EXPECT_EQ(next_up(x), std::nextafter(x, INFINITY)) << x;
    if (x != -DBL_MAX) EXPECT_EQ(next_down(x), std::nextafter(x, -INFINITY)) << x;
  }
  EXPECT_EQ(next_up(DBL_MAX), INFINITY);
  EXPECT_EQ(next_down(-DBL_MAX), -INFINITY);
  EXPECT_EQ(next_up(INFINITY), INFINITY);
  EXPECT_EQ(next_down(-INFINITY), -INFINITY);
  EXPECT_TRUE(std::isnan(next_up(NAN)));
}

TEST(Interval, PositionEnclosesTheMovingPointOverTheTimeInterval) {
  const Vec3 x_t0{0.5, -3, 8}, x_t1{1.5, 5, -2};  // dyadic: the checks below are exact
  const IntervalVec3 over = position_over(x_t0, x_t1, {0.25, 0.5});
  for (double t : {0.25, 0.3125, 0.375, 0.5}) {
    const Vec3 x = (1 - t) * x_t0 + t * x_t1;
    EXPECT_LE(over.x.lo, x.x);
    EXPECT_GE(over.x.hi, x.x);
    EXPECT_LE(over.y.lo, x.y);
    EXPECT_GE(over.y.hi, x.y);
    EXPECT_LE(over.z.lo, x.z);
    EXPECT_GE(over.z.hi, x.z);
  }
}

}  // namespace
}  // namespace snag
