// The outward steps of interval.hpp on the device: next_up and next_down are
// nextafter for every finite double, as on the host, and the interval
// operations give the host's doubles (the GPU's time search must
// round as the CPU's does for its answers to be bit-identical).
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

#include "gpu_test.hpp"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/cuda/launch.cuh"
#include "libcd/narrow_phase/interval.hpp"

namespace snag {
namespace {

__global__ void steps_kernel(const double* x, std::size_t count, double* up, double* down) {
  const std::size_t i = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i >= count) return;
  up[i] = next_up(x[i]);
  down[i] = next_down(x[i]);
}

// Interval i of a and of b: their sum, difference and product, as the
// 6 bounds of out[6 i ...].
__global__ void operations_kernel(const Interval* a, const Interval* b, std::size_t count, double* out) {
  const std::size_t i = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i >= count) return;
  const Interval results[3] = {a[i] + b[i], a[i] - b[i], a[i] * b[i]};
  for (int k = 0; k < 3; ++k) {
    out[6 * i + 2 * k] = results[k].lo;
    out[6 * i + 2 * k + 1] = results[k].hi;
  }
}

/// The same bits: equal doubles, or both NaN (which compare unequal).
bool same(double a, double b) { return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0; }

using IntervalDevice = test::GpuTest;

TEST_F(IntervalDevice, NextUpAndDownAreNextafterAndTheHostsForEveryDouble) {
  std::vector<double> values = {
      0.0,          -0.0,          1.0,     -1.0,     0.5,      2.0,       DBL_MIN, -DBL_MIN,
      DBL_TRUE_MIN, -DBL_TRUE_MIN, DBL_MAX, -DBL_MAX, INFINITY, -INFINITY, NAN,     std::nextafter(DBL_MIN, 0.0),
      1e-310,       -1e-310};
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> exponent(-1074, 1023);
  std::uniform_real_distribution<double> mantissa(-2.0, 2.0);
  for (int i = 0; i < 200000; ++i) values.push_back(std::ldexp(mantissa(rng), exponent(rng)));
  const std::size_t n = values.size();
  DeviceBuffer<double> x(n, nullptr), up(n, nullptr), down(n, nullptr);
  x.upload(values.data(), n);
  steps_kernel<<<detail::blocks_for(n), detail::kBlockSize>>>(x.data(), n, up.data(), down.data());
  SNAG_CUDA_CHECK_LAUNCH();
  std::vector<double> device_up(n), device_down(n);
  up.download(device_up.data(), n);
  down.download(device_down.data(), n);
  for (std::size_t i = 0; i < n; ++i) {
    const double v = values[i];
    EXPECT_TRUE(same(device_up[i], next_up(v))) << v;
    EXPECT_TRUE(same(device_down[i], next_down(v))) << v;
    if (std::isfinite(v) && v != DBL_MAX) EXPECT_EQ(device_up[i], std::nextafter(v, INFINITY)) << v;
    if (std::isfinite(v) && v != -DBL_MAX) EXPECT_EQ(device_down[i], std::nextafter(v, -INFINITY)) << v;
  }
  EXPECT_EQ(device_up[0], DBL_TRUE_MIN);  // +0 and -0 step to the smallest subnormal
  EXPECT_EQ(device_up[1], DBL_TRUE_MIN);
  EXPECT_TRUE(std::signbit(device_up[9]) && device_up[9] == 0);  // -DBL_TRUE_MIN steps up to -0
  EXPECT_EQ(device_up[13], -DBL_MAX);                            // -inf steps up to -DBL_MAX
}

// Sums, differences and products of intervals are the host's doubles, over
// intervals of mixed signs at every scale, from subnormal results to
// overflowing ones.
TEST_F(IntervalDevice, OperationsGiveTheHostsBounds) {
  std::mt19937_64 rng(12);
  std::uniform_int_distribution<int> exponent(-1074, 1023);
  std::uniform_real_distribution<double> mantissa(-2.0, 2.0);
  const auto random_interval = [&] {
    const int scale = exponent(rng);
    double lo = std::ldexp(mantissa(rng), scale), hi = std::ldexp(mantissa(rng), scale);
    if (rng() % 8 == 0) hi = lo;  // a point
    if (lo > hi) std::swap(lo, hi);
    return Interval{lo, hi};
  };
  std::vector<Interval> a, b;
  for (int i = 0; i < 100000; ++i) {
    a.push_back(random_interval());
    b.push_back(rng() % 4 == 0 ? a.back() : random_interval());
  }
  a.push_back({0.0, 0.0});
  b.push_back({-DBL_TRUE_MIN, DBL_TRUE_MIN});
  a.push_back({-0.0, DBL_TRUE_MIN});
  b.push_back({-DBL_TRUE_MIN, -0.0});
  const std::size_t n = a.size();
  DeviceBuffer<Interval> device_a(n, nullptr), device_b(n, nullptr);
  DeviceBuffer<double> out(6 * n, nullptr);
  device_a.upload(a.data(), n);
  device_b.upload(b.data(), n);
  operations_kernel<<<detail::blocks_for(n), detail::kBlockSize>>>(device_a.data(), device_b.data(), n, out.data());
  SNAG_CUDA_CHECK_LAUNCH();
  std::vector<double> bounds(6 * n);
  out.download(bounds.data(), 6 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const Interval expected[3] = {a[i] + b[i], a[i] - b[i], a[i] * b[i]};
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(same(bounds[6 * i + 2 * k], expected[k].lo)) << i << " op " << k;
      EXPECT_TRUE(same(bounds[6 * i + 2 * k + 1], expected[k].hi)) << i << " op " << k;
    }
  }
}

}  // namespace
}  // namespace snag
