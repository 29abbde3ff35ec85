// The GPU bounds stage (libcd/cuda/bounds_reduction) against a CPU oracle
// written here independently: radii from the definition (centroid sphere; the
// smallest sphere enclosing two spheres has radius max(r0, r1, (d + r0 + r1)/2)),
// box and means by plain loops. Radii must match to the last bit of the shared
// math (no FMA contraction on the device), the means to rounding of the sum order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "gpu_test.hpp"
#include "libcd/cuda/bounds_reduction.hpp"
#include "libcd/cuda/triangle_sphere.hpp"
#include "ply_mesh.hpp"

namespace snag {
namespace {

struct CpuBounds {
  std::vector<double> static_radii, swept_radii;
  Vec3 lo, hi;
  double mean_static = 0, mean_swept = 0;
};

double distance(Vec3 a, Vec3 b) { return std::sqrt(squared_norm(a - b)); }

CpuBounds cpu_bounds(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                     const std::vector<Triangle>& triangles) {
  CpuBounds out;
  const double inf = std::numeric_limits<double>::infinity();
  out.lo = {inf, inf, inf};
  out.hi = {-inf, -inf, -inf};
  for (const auto* frame : {&x_t0, &x_t1}) {
    for (const Vec3& p : *frame) {
      for (int k = 0; k < 3; ++k) {
        out.lo[k] = std::min(out.lo[k], p[k]);
        out.hi[k] = std::max(out.hi[k], p[k]);
      }
    }
  }
  for (const Triangle& t : triangles) {
    double r[2];
    Vec3 c[2];
    for (int i = 0; i < 2; ++i) {
      const std::vector<Vec3>& x = i == 0 ? x_t0 : x_t1;
      c[i] = (x[t[0]] + x[t[1]] + x[t[2]]) / 3.0;
      r[i] = std::max({distance(x[t[0]], c[i]), distance(x[t[1]], c[i]), distance(x[t[2]], c[i])});
    }
    out.static_radii.push_back(r[0]);
    out.swept_radii.push_back(std::max({r[0], r[1], 0.5 * (distance(c[0], c[1]) + r[0] + r[1])}));
    out.mean_static += r[0];
    out.mean_swept += out.swept_radii.back();
  }
  if (!triangles.empty()) {
    out.mean_static /= static_cast<double>(triangles.size());
    out.mean_swept /= static_cast<double>(triangles.size());
  }
  return out;
}

void expect_matches_cpu(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                        const std::vector<Triangle>& triangles, const TriangleBounds& gpu) {
  const CpuBounds cpu = cpu_bounds(x_t0, x_t1, triangles);
  ASSERT_EQ(gpu.static_radii.size(), triangles.size());
  ASSERT_EQ(gpu.swept_radii.size(), triangles.size());
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const Triangle& t = triangles[f];
    // Bitwise against the shared host/device math, evaluated on the host.
    const TriangleSphere s_t0 = centroid_sphere(x_t0[t[0]], x_t0[t[1]], x_t0[t[2]]);
    const TriangleSphere swept =
        swept_centroid_sphere(x_t0[t[0]], x_t0[t[1]], x_t0[t[2]], x_t1[t[0]], x_t1[t[1]], x_t1[t[2]]);
    ASSERT_EQ(gpu.static_radii[f], s_t0.radius) << "triangle " << f;
    ASSERT_EQ(gpu.swept_radii[f], swept.radius) << "triangle " << f;
    // Against the independent oracle, to rounding.
    const double tolerance = 1e-12 * std::max(1.0, cpu.swept_radii[f]);
    ASSERT_NEAR(gpu.static_radii[f], cpu.static_radii[f], tolerance) << "triangle " << f;
    ASSERT_NEAR(gpu.swept_radii[f], cpu.swept_radii[f], tolerance) << "triangle " << f;
    // The swept sphere holds all six corners.
    for (int k = 0; k < 3; ++k) {
      ASSERT_LE(distance(x_t0[t[k]], swept.centre), swept.radius + tolerance) << "triangle " << f;
      ASSERT_LE(distance(x_t1[t[k]], swept.centre), swept.radius + tolerance) << "triangle " << f;
    }
  }
  EXPECT_EQ(gpu.scene_lo, cpu.lo);
  EXPECT_EQ(gpu.scene_hi, cpu.hi);
  EXPECT_NEAR(gpu.mean_static_radius, cpu.mean_static, 1e-12 * cpu.mean_static);
  EXPECT_NEAR(gpu.mean_swept_radius, cpu.mean_swept, 1e-12 * cpu.mean_swept);
}

struct RandomMesh {
  std::vector<Vec3> x_t0, x_t1;
  std::vector<Triangle> triangles;
};

RandomMesh random_mesh(std::size_t vertex_count, std::size_t triangle_count, double motion, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coordinate(-10.0, 10.0), step(-motion, motion);
  std::uniform_int_distribution<Index> vertex(0, static_cast<Index>(vertex_count - 1));
  RandomMesh m;
  for (std::size_t v = 0; v < vertex_count; ++v) {
    m.x_t0.push_back({coordinate(rng), coordinate(rng), coordinate(rng)});
    m.x_t1.push_back(m.x_t0.back() + Vec3{step(rng), step(rng), step(rng)});
  }
  for (std::size_t f = 0; f < triangle_count; ++f) m.triangles.push_back({vertex(rng), vertex(rng), vertex(rng)});
  return m;
}

using BoundsReduction = test::GpuTest;

TEST_F(BoundsReduction, MatchesCpuOnRandomMeshes) {
  // Sizes around the block size and the reductions' tile sizes, and one large mesh.
  const std::size_t sizes[][2] = {{3, 1}, {10, 255}, {100, 256}, {1000, 257}, {5000, 70001}, {300000, 1000003}};
  unsigned seed = 1;
  for (const auto& size : sizes) {
    SCOPED_TRACE("vertices " + std::to_string(size[0]) + ", triangles " + std::to_string(size[1]));
    const RandomMesh m = random_mesh(size[0], size[1], 0.5, seed++);
    const TriangleBounds gpu = compute_triangle_bounds_cuda(m.x_t0, m.x_t1, m.triangles, 1.2);
    expect_matches_cpu(m.x_t0, m.x_t1, m.triangles, gpu);
    EXPECT_DOUBLE_EQ(gpu.cell_size, 3.0 * 1.2 * gpu.mean_swept_radius);
  }
}

TEST_F(BoundsReduction, MatchesCpuOnClothBallStep) {
  const std::string dir = test::shared_data_dir() + "/meshes/";
  const test::PlyMesh t0 = test::read_binary_ply(dir + "cloth_ball92.ply");
  const test::PlyMesh t1 = test::read_binary_ply(dir + "cloth_ball93.ply");
  ASSERT_EQ(t0.positions.size(), 46598u);
  ASSERT_EQ(t0.triangles.size(), 92230u);
  ASSERT_EQ(t0.triangles, t1.triangles);
  compute_triangle_bounds_cuda(t0.positions, t1.positions, t0.triangles, 1.2);  // warm-up: context, pool
  const TriangleBounds gpu = compute_triangle_bounds_cuda(t0.positions, t1.positions, t0.triangles, 1.2);
  expect_matches_cpu(t0.positions, t1.positions, t0.triangles, gpu);
  EXPECT_GT(gpu.mean_swept_radius, 0.0);
  EXPECT_GE(gpu.mean_swept_radius, gpu.mean_static_radius);
  RecordProperty("upload_ms", std::to_string(gpu.timings.upload_ms));
  RecordProperty("kernels_ms", std::to_string(gpu.timings.kernels_ms));
  RecordProperty("download_ms", std::to_string(gpu.timings.download_ms));
  std::cout << "cloth_ball 92->93 (" << t0.triangles.size() << " triangles): upload " << gpu.timings.upload_ms
            << " ms, kernels " << gpu.timings.kernels_ms << " ms, download " << gpu.timings.download_ms
            << " ms; r_avg " << gpu.mean_swept_radius << ", cell size " << gpu.cell_size << "\n";
}

TEST_F(BoundsReduction, StaticFrameGivesSweptEqualToStatic) {
  const RandomMesh m = random_mesh(2000, 4000, 0.0, 7);
  const TriangleBounds gpu = compute_triangle_bounds_cuda(m.x_t0, m.x_t0, m.triangles, 1.2);
  EXPECT_EQ(gpu.static_radii, gpu.swept_radii);
  EXPECT_EQ(gpu.mean_static_radius, gpu.mean_swept_radius);
}

TEST_F(BoundsReduction, RigidTranslationAddsHalfTheDistance) {
  // A triangle translated by v: the swept sphere's radius is r + |v|/2.
  const std::vector<Vec3> x_t0 = {{0, 0, 0}, {3, 0, 0}, {0, 3, 0}};
  const Vec3 v{0, 0, 4};
  const std::vector<Vec3> x_t1 = {x_t0[0] + v, x_t0[1] + v, x_t0[2] + v};
  const TriangleBounds gpu = compute_triangle_bounds_cuda(x_t0, x_t1, {{0, 1, 2}}, 1.2);
  const double r = std::sqrt(5.0);  // centroid (1, 1, 0) to corner (3, 0, 0) or (0, 3, 0)
  EXPECT_DOUBLE_EQ(gpu.static_radii[0], r);
  EXPECT_DOUBLE_EQ(gpu.swept_radii[0], r + 2.0);
  EXPECT_EQ(gpu.scene_lo, (Vec3{0, 0, 0}));
  EXPECT_EQ(gpu.scene_hi, (Vec3{3, 3, 4}));
  EXPECT_DOUBLE_EQ(gpu.cell_size, 3.0 * 1.2 * (r + 2.0));
}

TEST_F(BoundsReduction, NoTrianglesGiveZeroMeanAndTheBoxOfThePoints) {
  const std::vector<Vec3> x_t0 = {{1, -2, 3}, {-4, 5, -6}};
  const std::vector<Vec3> x_t1 = {{7, 0, 0}, {0, 0, -8}};
  const TriangleBounds gpu = compute_triangle_bounds_cuda(x_t0, x_t1, {}, 1.2);
  EXPECT_TRUE(gpu.static_radii.empty());
  EXPECT_EQ(gpu.mean_swept_radius, 0.0);
  EXPECT_EQ(gpu.cell_size, 0.0);
  EXPECT_EQ(gpu.scene_lo, (Vec3{-4, -2, -8}));
  EXPECT_EQ(gpu.scene_hi, (Vec3{7, 5, 3}));
}

}  // namespace
}  // namespace snag
