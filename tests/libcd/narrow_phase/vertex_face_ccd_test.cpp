// vertex_face_ccd on hand-made cases with known answers and on random
// configurations built to collide or to be far apart.
#include "libcd/narrow_phase/vertex_face_ccd.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

#include "tests/libcd/narrow_phase/ccd_test_support.hpp"

namespace snag {
namespace {

// The unit right triangle in z = 0, static.
const Vec3 kA{0, 0, 0}, kB{1, 0, 0}, kC{0, 1, 0};

CcdResult static_face(const Vec3& p_t0, const Vec3& p_t1, const CcdSettings& settings = {}) {
  return vertex_face_ccd(p_t0, kA, kB, kC, p_t1, kA, kB, kC, settings);
}

void expect_encloses(const CcdResult& r, double toi) {
  EXPECT_LE(r.toi_lo, toi);
  EXPECT_GE(r.toi_hi, toi);
}

TEST(VertexFaceCcd, ProvesAClearHitAndEnclosesItsTime) {
  const CcdSettings settings;
  for (double z_t1 : {-1.0, -2.0, -0.1}) {  // crossing times 1/2, 1/3, 1/1.1
    const CcdResult r = static_face({0.25, 0.25, 1}, {0.25, 0.25, z_t1});
    const double toi = 1.0 / (1.0 - z_t1);
    EXPECT_EQ(r.answer, CcdAnswer::kYes);
    expect_encloses(r, toi);
    EXPECT_LE(r.toi_hi - r.toi_lo, 3 * settings.time_tolerance);
  }
}

TEST(VertexFaceCcd, ProvesAHitOfAMovingFace) {
  // The face rises from z = -1 to z = 1 while the vertex falls from 1 to -1.
  const Vec3 down{0, 0, -1}, up{0, 0, 1};
  const CcdResult r = vertex_face_ccd({0.2, 0.3, 1}, kA + down, kB + down, kC + down, {0.2, 0.3, -1}, kA + up,
                                      kB + up, kC + up, {});
  EXPECT_EQ(r.answer, CcdAnswer::kYes);
  expect_encloses(r, 0.5);
}

TEST(VertexFaceCcd, RejectsClearMisses) {
  EXPECT_EQ(static_face({2, 2, 1}, {2, 2, -1}).answer, CcdAnswer::kNo);       // beside the face
  EXPECT_EQ(static_face({0.2, 0.2, 1}, {0.2, 0.2, 0.5}).answer, CcdAnswer::kNo);  // stops above it
  EXPECT_EQ(static_face({0.2, 0.2, 1}, {0.2, 0.2, 1e-9}).answer, CcdAnswer::kNo);  // stops a hair above
  EXPECT_EQ(static_face({0.6, 0.6, 1}, {0.6, 0.6, -1}).answer, CcdAnswer::kNo);    // past the hypotenuse
}

TEST(VertexFaceCcd, NeverRejectsContactAtTheStartOrTheEnd) {
  const CcdResult start = static_face({0.25, 0.25, 0}, {0.25, 0.25, -1});
  EXPECT_NE(start.answer, CcdAnswer::kNo);
  EXPECT_EQ(start.toi_lo, 0);
  const CcdResult end = static_face({0.25, 0.25, 1}, {0.25, 0.25, 0});
  EXPECT_NE(end.answer, CcdAnswer::kNo);
  expect_encloses(end, 1);
}

TEST(VertexFaceCcd, NeverRejectsTouchingWithoutCrossing) {
  // Through a point of the hypotenuse at t = 1/2.
  const CcdResult edge = static_face({0.5, 0.5, 1}, {0.5, 0.5, -1});
  EXPECT_NE(edge.answer, CcdAnswer::kNo);
  expect_encloses(edge, 0.5);
  // Sliding in the face's plane along the hypotenuse's line: on it from t = 1/3.
  const CcdResult sliding = static_face({2, -1, 0}, {-1, 2, 0});
  EXPECT_NE(sliding.answer, CcdAnswer::kNo);
  EXPECT_LE(sliding.toi_lo, 1.0 / 3.0);
  // Through the corner b.
  const CcdResult corner = static_face({1, 0, 1}, {1, 0, -1});
  EXPECT_NE(corner.answer, CcdAnswer::kNo);
  expect_encloses(corner, 0.5);
}

TEST(VertexFaceCcd, HandlesZeroMotion) {
  EXPECT_EQ(static_face({0.25, 0.25, 0.5}, {0.25, 0.25, 0.5}).answer, CcdAnswer::kNo);
  const CcdResult resting = static_face({0.25, 0.25, 0}, {0.25, 0.25, 0});
  EXPECT_NE(resting.answer, CcdAnswer::kNo);
  EXPECT_EQ(resting.toi_lo, 0);
}

TEST(VertexFaceCcd, DegenerateFaceIsNeverRejectedWhenHit) {
  // a == b: the face is the segment from a to c.
  const CcdResult hit = vertex_face_ccd({0, 0.5, 1}, kA, kA, kC, {0, 0.5, -1}, kA, kA, kC, {});
  EXPECT_NE(hit.answer, CcdAnswer::kNo);
  expect_encloses(hit, 0.5);
  EXPECT_EQ(vertex_face_ccd({3, 0.5, 1}, kA, kA, kC, {3, 0.5, -1}, kA, kA, kC, {}).answer, CcdAnswer::kNo);
}

TEST(VertexFaceCcd, HonoursThickness) {
  CcdSettings thin, thick;
  thin.thickness = 0.4;
  thick.thickness = 0.6;
  EXPECT_EQ(static_face({0.25, 0.25, 0.5}, {0.25, 0.25, 0.5}, thin).answer, CcdAnswer::kNo);
  const CcdResult resting = static_face({0.25, 0.25, 0.5}, {0.25, 0.25, 0.5}, thick);
  EXPECT_EQ(resting.answer, CcdAnswer::kYes);
  EXPECT_EQ(resting.toi_lo, 0);
  // Falling from 2 to 0 reaches distance 0.5 at t = 3/4.
  CcdSettings half;
  half.thickness = 0.5;
  const CcdResult falling = static_face({0.25, 0.25, 2}, {0.25, 0.25, 0}, half);
  EXPECT_EQ(falling.answer, CcdAnswer::kYes);
  expect_encloses(falling, 0.75);
  // A grazing approach to the thickness is proven a little after it happens.
  EXPECT_LE(falling.toi_hi - falling.toi_lo, 1e-4);
  // Passing beside the face at distance 0.3 (in x, beyond b).
  EXPECT_EQ(static_face({1.3, 0, 1}, {1.3, 0, -1}, CcdSettings{0.29}).answer, CcdAnswer::kNo);
  EXPECT_NE(static_face({1.3, 0, 1}, {1.3, 0, -1}, CcdSettings{0.31}).answer, CcdAnswer::kNo);
}

TEST(VertexFaceCcd, ProvesHitsAtHugeAndTinyScales) {
  for (double scale : {1e8, 1e-8}) {
    const CcdResult r = vertex_face_ccd(scale * Vec3{0.25, 0.25, 1}, scale * kA, scale * kB, scale * kC,
                                        scale * Vec3{0.25, 0.25, -2}, scale * kA, scale * kB, scale * kC, {});
    EXPECT_EQ(r.answer, CcdAnswer::kYes) << scale;
    expect_encloses(r, 1.0 / 3.0);
    EXPECT_EQ(vertex_face_ccd(scale * Vec3{2, 2, 1}, scale * kA, scale * kB, scale * kC, scale * Vec3{2, 2, -2},
                              scale * kA, scale * kB, scale * kC, {})
                  .answer,
              CcdAnswer::kNo);
  }
  // Far from the origin: everything offset by 1e8.
  const Vec3 offset{1e8, -1e8, 1e8};
  const CcdResult far = vertex_face_ccd(Vec3{0.25, 0.25, 1} + offset, kA + offset, kB + offset, kC + offset,
                                        Vec3{0.25, 0.25, -1} + offset, kA + offset, kB + offset, kC + offset, {});
  EXPECT_EQ(far.answer, CcdAnswer::kYes);
  expect_encloses(far, 0.5);
}

TEST(VertexFaceCcd, AnswersUncertainForNonFiniteInput) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(static_face({nan, 0, 0}, {0, 0, 0}).answer, CcdAnswer::kUncertain);
}

TEST(VertexFaceCcd, NeverRejectsRandomHitsBuiltByConstruction) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int proven = 0;
  const int trials = 2000;
  for (int i = 0; i < trials; ++i) {
    Vec3 x[8];
    for (Vec3& point : x) point = test::random_point(rng, 1.0);
    // Contact at t* at barycentric (u*, v*) inside the face, away from its edges.
    const double t_star = 0.05 + 0.9 * unit(rng);
    double u_star = 0.05 + 0.9 * unit(rng), v_star = 0.05 + 0.9 * unit(rng);
    if (u_star + v_star > 0.95) {
      u_star = 0.95 - u_star;
      v_star = 0.95 - v_star;
      u_star = u_star < 0.05 ? 0.05 : u_star;
      v_star = v_star < 0.05 ? 0.05 : v_star;
    }
    const Vec3 a = test::at(x[1], x[5], t_star), b = test::at(x[2], x[6], t_star), c = test::at(x[3], x[7], t_star);
    const Vec3 target = (1 - u_star - v_star) * a + u_star * b + v_star * c;
    x[4] = x[0] + (target - x[0]) / t_star;  // p(t*) = target
    const CcdResult r = vertex_face_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], {});
    ASSERT_NE(r.answer, CcdAnswer::kNo) << "trial " << i;
    EXPECT_LE(r.toi_lo, t_star + 1e-9) << "trial " << i;
    proven += r.answer == CcdAnswer::kYes;
  }
  std::printf("random vertex-face hits proven: %d of %d\n", proven, trials);
  EXPECT_GE(proven, trials * 99 / 100);  // measured: 1998 of 2000
}

TEST(VertexFaceCcd, RejectsRandomFarApartPairs) {
  std::mt19937_64 rng(11);
  for (int i = 0; i < 1000; ++i) {
    Vec3 x[8];
    for (Vec3& point : x) point = test::random_point(rng, 1.0);
    const Vec3 away{3, 0, 0};  // the vertex stays in x > 2, the face in x < 1
    x[0] = x[0] + away;
    x[4] = x[4] + away;
    EXPECT_EQ(vertex_face_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], {}).answer, CcdAnswer::kNo);
  }
}

}  // namespace
}  // namespace snag
