// edge_edge_ccd on hand-made cases with known answers and on random
// configurations built to collide or to be far apart.
#include "libcd/narrow_phase/edge_edge_ccd.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "tests/libcd/narrow_phase/ccd_test_support.hpp"

namespace snag {
namespace {

// Edge b: static, along y through the origin.
const Vec3 kEb0{0, -1, 0}, kEb1{0, 1, 0};

// Edge a along x at height z_t0, moving straight to height z_t1, offset by `shift`.
CcdResult falling_edge(double z_t0, double z_t1, const CcdSettings& settings = {}, Vec3 shift = {}) {
  return edge_edge_ccd(Vec3{-1, 0, z_t0} + shift, Vec3{1, 0, z_t0} + shift, kEb0, kEb1, Vec3{-1, 0, z_t1} + shift,
                       Vec3{1, 0, z_t1} + shift, kEb0, kEb1, settings);
}

void expect_encloses(const CcdResult& r, double toi) {
  EXPECT_LE(r.toi_lo, toi);
  EXPECT_GE(r.toi_hi, toi);
}

TEST(EdgeEdgeCcd, ProvesAClearHitAndEnclosesItsTime) {
  const CcdSettings settings;
  for (double z_t1 : {-1.0, -2.0, -0.1}) {
    const CcdResult r = falling_edge(1, z_t1);
    EXPECT_EQ(r.answer, CcdAnswer::kYes);
    expect_encloses(r, 1.0 / (1.0 - z_t1));
    EXPECT_LE(r.toi_hi - r.toi_lo, 3 * settings.time_tolerance);
  }
}

TEST(EdgeEdgeCcd, RejectsClearMisses) {
  EXPECT_EQ(falling_edge(1, -1, {}, {0, 2, 0}).answer, CcdAnswer::kNo);   // passes beyond eb1
  EXPECT_EQ(falling_edge(1, 0.5).answer, CcdAnswer::kNo);                 // stops above
  EXPECT_EQ(falling_edge(1, 1e-9).answer, CcdAnswer::kNo);                // stops a hair above
  EXPECT_EQ(falling_edge(1, -1, {}, {5, 0, 0}).answer, CcdAnswer::kNo);   // passes beside
}

TEST(EdgeEdgeCcd, NeverRejectsContactAtTheStartOrTheEnd) {
  const CcdResult start = falling_edge(0, -1);
  EXPECT_NE(start.answer, CcdAnswer::kNo);
  EXPECT_EQ(start.toi_lo, 0);
  const CcdResult end = falling_edge(1, 0);
  EXPECT_NE(end.answer, CcdAnswer::kNo);
  expect_encloses(end, 1);
}

TEST(EdgeEdgeCcd, NeverRejectsTouchingWithoutCrossing) {
  // The end of edge a passes through the middle of edge b (a T touch).
  const CcdResult tee = edge_edge_ccd({0, 0, 1}, {1, 0, 1}, kEb0, kEb1, {0, 0, -1}, {1, 0, -1}, kEb0, kEb1, {});
  EXPECT_NE(tee.answer, CcdAnswer::kNo);
  expect_encloses(tee, 0.5);
  // End to end.
  const CcdResult ends = edge_edge_ccd({0, 1, 1}, {1, 1, 1}, kEb0, kEb1, {0, 1, -1}, {1, 1, -1}, kEb0, kEb1, {});
  EXPECT_NE(ends.answer, CcdAnswer::kNo);
  expect_encloses(ends, 0.5);
}

TEST(EdgeEdgeCcd, ParallelEdgesAreNeverRejectedWhenTheyMeet) {
  // Edge a parallel to b, falling onto it: the edges overlap at t = 1/2.
  const CcdResult meet = edge_edge_ccd({0, -0.5, 1}, {0, 0.5, 1}, kEb0, kEb1, {0, -0.5, -1}, {0, 0.5, -1}, kEb0,
                                       kEb1, {});
  EXPECT_NE(meet.answer, CcdAnswer::kNo);
  expect_encloses(meet, 0.5);
  // Parallel and one unit to the side: never meet.
  EXPECT_EQ(edge_edge_ccd({1, -0.5, 1}, {1, 0.5, 1}, kEb0, kEb1, {1, -0.5, -1}, {1, 0.5, -1}, kEb0, kEb1, {}).answer,
            CcdAnswer::kNo);
}

TEST(EdgeEdgeCcd, HandlesZeroMotion) {
  EXPECT_EQ(falling_edge(0.5, 0.5).answer, CcdAnswer::kNo);
  const CcdResult crossing = falling_edge(0, 0);
  EXPECT_NE(crossing.answer, CcdAnswer::kNo);
  EXPECT_EQ(crossing.toi_lo, 0);
}

TEST(EdgeEdgeCcd, HonoursThickness) {
  EXPECT_EQ(falling_edge(0.5, 0.5, CcdSettings{0.4}).answer, CcdAnswer::kNo);
  const CcdResult resting = falling_edge(0.5, 0.5, CcdSettings{0.6});
  EXPECT_EQ(resting.answer, CcdAnswer::kYes);
  EXPECT_EQ(resting.toi_lo, 0);
  const CcdSettings half{0.5};
  const CcdResult falling = falling_edge(2, 0, half);  // distance 0.5 at t = 3/4
  EXPECT_EQ(falling.answer, CcdAnswer::kYes);
  expect_encloses(falling, 0.75);
  // A grazing approach to the thickness is proven a little after it happens.
  EXPECT_LE(falling.toi_hi - falling.toi_lo, 1e-4);
}

TEST(EdgeEdgeCcd, ProvesHitsAtHugeAndTinyScales) {
  for (double scale : {1e8, 1e-8}) {
    const CcdResult r = edge_edge_ccd(scale * Vec3{-1, 0, 1}, scale * Vec3{1, 0, 1}, scale * kEb0, scale * kEb1,
                                      scale * Vec3{-1, 0, -2}, scale * Vec3{1, 0, -2}, scale * kEb0, scale * kEb1, {});
    EXPECT_EQ(r.answer, CcdAnswer::kYes) << scale;
    expect_encloses(r, 1.0 / 3.0);
  }
  const Vec3 offset{1e8, 1e8, -1e8};
  const CcdResult far = edge_edge_ccd(Vec3{-1, 0, 1} + offset, Vec3{1, 0, 1} + offset, kEb0 + offset, kEb1 + offset,
                                      Vec3{-1, 0, -1} + offset, Vec3{1, 0, -1} + offset, kEb0 + offset,
                                      kEb1 + offset, {});
  EXPECT_EQ(far.answer, CcdAnswer::kYes);
  expect_encloses(far, 0.5);
}

TEST(EdgeEdgeCcd, NeverRejectsRandomHitsBuiltByConstruction) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int proven = 0;
  const int trials = 2000;
  for (int i = 0; i < trials; ++i) {
    Vec3 x[8];
    for (Vec3& point : x) point = test::random_point(rng, 1.0);
    const double t_star = 0.05 + 0.9 * unit(rng);
    const double u_star = 0.05 + 0.9 * unit(rng), v_star = 0.05 + 0.9 * unit(rng);
    const Vec3 on_a = (1 - u_star) * test::at(x[0], x[4], t_star) + u_star * test::at(x[1], x[5], t_star);
    const Vec3 on_b = (1 - v_star) * test::at(x[2], x[6], t_star) + v_star * test::at(x[3], x[7], t_star);
    const Vec3 move = (on_a - on_b) / t_star;  // shifts edge b's path so that it meets a at t*
    x[6] = x[6] + move;
    x[7] = x[7] + move;
    const CcdResult r = edge_edge_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], {});
    ASSERT_NE(r.answer, CcdAnswer::kNo) << "trial " << i;
    EXPECT_LE(r.toi_lo, t_star + 1e-9) << "trial " << i;
    proven += r.answer == CcdAnswer::kYes;
  }
  std::printf("random edge-edge hits proven: %d of %d\n", proven, trials);
  EXPECT_GE(proven, trials * 99 / 100);  // measured: 1997 of 2000
}

TEST(EdgeEdgeCcd, RejectsRandomFarApartPairs) {
  std::mt19937_64 rng(13);
  for (int i = 0; i < 1000; ++i) {
    Vec3 x[8];
    for (Vec3& point : x) point = test::random_point(rng, 1.0);
    for (int k : {2, 3, 6, 7}) x[k] = x[k] + Vec3{0, 0, 3};  // edge b stays in z > 2
    EXPECT_EQ(edge_edge_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], {}).answer, CcdAnswer::kNo);
  }
}

}  // namespace
}  // namespace snag
