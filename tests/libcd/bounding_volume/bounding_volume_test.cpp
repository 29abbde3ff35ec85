// Tests for bounding_volume/: swept 18-DOPs contain the moving triangle at
// every sampled time, thickness inflation contains the thickness ball, and
// bounding spheres contain their points.
#include <gtest/gtest.h>

#include <random>

#include "libcd/bounding_volume/bounding_sphere.hpp"
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
