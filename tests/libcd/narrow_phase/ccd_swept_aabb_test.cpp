// The swept-box filter: never rejects a pair in contact, rejects separated ones.
#include "libcd/narrow_phase/ccd_swept_aabb.hpp"

#include <gtest/gtest.h>

#include <random>

#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "tests/libcd/narrow_phase/ccd_test_support.hpp"

namespace snag {
namespace {

TEST(CcdSweptBox, TouchingBoxesOverlapAndSeparatedOnesDoNot) {
  const SweptBox a{{0, 0, 0}, {1, 1, 1}};
  const SweptBox touching{{1, 0, 0}, {2, 1, 1}};
  const SweptBox gap{{2, 0, 0}, {3, 1, 1}};  // one unit apart in x
  EXPECT_TRUE(swept_boxes_overlap(a, touching, 0));
  EXPECT_FALSE(swept_boxes_overlap(a, gap, 0));
  EXPECT_FALSE(swept_boxes_overlap(gap, a, 0.999));
  EXPECT_TRUE(swept_boxes_overlap(a, gap, 1.0));
  EXPECT_TRUE(swept_boxes_overlap(gap, a, 1.0));
}

TEST(CcdSweptBox, NeverRejectsAPairTheKernelsFindInContact) {
  std::mt19937_64 rng(17);
  int contacts = 0;
  for (int i = 0; i < 1000; ++i) {
    Vec3 x[8];
    for (Vec3& point : x) point = test::random_point(rng, 1.0);
    for (int k : {0, 4}) x[k] = x[k] + Vec3{1.2, 0, 0};  // a near-miss offset keeps both outcomes common
    const CcdSettings settings;
    const CcdResult vf = vertex_face_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings);
    const CcdResult ee = edge_edge_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings);
    if (vf.answer != CcdAnswer::kNo) {
      ++contacts;
      EXPECT_TRUE(vertex_face_swept_overlap(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings.thickness));
    }
    if (ee.answer != CcdAnswer::kNo) {
      ++contacts;
      EXPECT_TRUE(edge_edge_swept_overlap(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings.thickness));
    }
  }
  EXPECT_GT(contacts, 50);
}

}  // namespace
}  // namespace snag
