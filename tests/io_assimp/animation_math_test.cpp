// The interpolation and matrix helpers of io/assimp_animation against closed forms.
#include <cmath>

#include <gtest/gtest.h>

#include "io/assimp_animation.hpp"

namespace snag::io::assimp_detail {
namespace {

const double kPi = std::acos(-1.0);

TEST(AnimationMath, SlerpOfQuarterTurnGivesEighthTurn) {
  const Quat a{1, 0, 0, 0};
  const Quat b{std::cos(kPi / 4), 0, 0, std::sin(kPi / 4)};  // 90 degrees about Z
  const Quat h = slerp(a, b, 0.5);
  EXPECT_NEAR(h.w, std::cos(kPi / 8), 1e-15);
  EXPECT_NEAR(h.z, std::sin(kPi / 8), 1e-15);
  EXPECT_NEAR(h.x, 0, 1e-15);
}

TEST(AnimationMath, SlerpTakesTheShorterArc) {
  const Quat a{1, 0, 0, 0};
  const Quat b{-std::cos(kPi / 4), 0, 0, -std::sin(kPi / 4)};  // the same 90 degree turn, negated
  const Quat h = slerp(a, b, 0.5);
  EXPECT_NEAR(std::abs(h.w), std::cos(kPi / 8), 1e-15);
  EXPECT_NEAR(std::abs(h.z), std::sin(kPi / 8), 1e-15);
}

TEST(AnimationMath, ComposeThenDecomposeRoundTrips) {
  const Quat r{std::cos(0.3), std::sin(0.3) * 0.6, 0, std::sin(0.3) * 0.8};
  const Mat4 m = compose({1, -2, 3}, r, {2, 0.5, 3});
  Vec3 t, s;
  Quat q;
  decompose(m, t, q, s);
  EXPECT_NEAR(t.x, 1, 1e-14);
  EXPECT_NEAR(t.y, -2, 1e-14);
  EXPECT_NEAR(t.z, 3, 1e-14);
  EXPECT_NEAR(s.x, 2, 1e-14);
  EXPECT_NEAR(s.y, 0.5, 1e-14);
  EXPECT_NEAR(s.z, 3, 1e-14);
  const double sign = q.w * r.w < 0 ? -1 : 1;
  EXPECT_NEAR(sign * q.w, r.w, 1e-14);
  EXPECT_NEAR(sign * q.x, r.x, 1e-14);
  EXPECT_NEAR(sign * q.z, r.z, 1e-14);
  // A point goes through the same as with T * R * S applied by hand.
  const Vec3 p = transform_point(m, {1, 1, 1});
  const Vec3 back = transform_point(compose(t, q, s), {1, 1, 1});
  EXPECT_NEAR(p.x, back.x, 1e-14);
  EXPECT_NEAR(p.y, back.y, 1e-14);
  EXPECT_NEAR(p.z, back.z, 1e-14);
}

TEST(AnimationMath, VectorKeysInterpolateLinearlyAndClamp) {
  aiVectorKey keys[3];
  keys[0] = aiVectorKey(10.0, aiVector3D(0, 0, 0));
  keys[1] = aiVectorKey(20.0, aiVector3D(4, 0, 0));
  keys[2] = aiVectorKey(40.0, aiVector3D(4, 8, 0));
  EXPECT_EQ(interpolate_vector_keys(keys, 3, 0.0), (Vec3{0, 0, 0}));
  EXPECT_EQ(interpolate_vector_keys(keys, 3, 15.0), (Vec3{2, 0, 0}));
  EXPECT_EQ(interpolate_vector_keys(keys, 3, 30.0), (Vec3{4, 4, 0}));
  EXPECT_EQ(interpolate_vector_keys(keys, 3, 99.0), (Vec3{4, 8, 0}));
}

}  // namespace
}  // namespace snag::io::assimp_detail
