// Order keys (libcd/geometry/order_key.hpp) against the doubles' own order:
// every pair of a set of doubles that holds both zeros, both infinities,
// subnormals, the extremes and random bit patterns of every exponent orders
// as its keys do, -0 just below +0; every key gives its double back, bit for
// bit; the largest complement of keys gives the smallest double.
#include "libcd/geometry/order_key.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace snag {
namespace {

std::uint64_t bits_of(double d) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &d, sizeof bits);
  return bits;
}

std::vector<double> samples() {
  using limits = std::numeric_limits<double>;
  std::vector<double> values = {0.5, 1.0, 1e300};
  for (double d : {limits::infinity(), limits::max(), limits::min(), limits::denorm_min(), 0.0}) {
    values.push_back(d);
    values.push_back(-d);
  }
  values.push_back(-0.5);
  values.push_back(-1.0);
  values.push_back(-1e300);
  std::mt19937_64 random(11);
  while (values.size() < 600) {
    double d = 0;
    const std::uint64_t bits = random();
    std::memcpy(&d, &bits, sizeof d);
    if (!std::isnan(d)) values.push_back(d);
  }
  return values;
}

TEST(OrderKey, KeysOrderAsTheDoublesDoWithMinusZeroBelowPlusZero) {
  const std::vector<double> values = samples();
  for (double a : values) {
    for (double b : values) {
      const bool below = a < b || (a == b && std::signbit(a) && !std::signbit(b));
      ASSERT_EQ(order_key(a) < order_key(b), below) << a << " " << b;
    }
  }
}

TEST(OrderKey, EveryKeyGivesItsDoubleBackAndNoneIsZero) {
  for (double d : samples()) {
    EXPECT_EQ(bits_of(from_order_key(order_key(d))), bits_of(d)) << d;
    EXPECT_NE(order_key(d), 0u) << d;
  }
}

TEST(OrderKey, TheLargestComplementIsTheSmallestDouble) {
  const std::vector<double> values = samples();
  std::uint64_t largest = 0, largest_complement = 0;
  for (double d : values) {
    largest = std::max(largest, order_key(d));
    largest_complement = std::max(largest_complement, ~order_key(d));
  }
  EXPECT_EQ(from_order_key(largest), std::numeric_limits<double>::infinity());
  EXPECT_EQ(from_order_key(~largest_complement), -std::numeric_limits<double>::infinity());
  const std::uint64_t zeros = std::max(~order_key(0.0), ~order_key(-0.0));
  EXPECT_TRUE(std::signbit(from_order_key(~zeros)));  // the smaller of the two zeros is -0
}

}  // namespace
}  // namespace snag
