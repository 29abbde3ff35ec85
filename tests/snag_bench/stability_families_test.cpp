// The stability families (tools/bench/stability_families.hpp): each gives
// queries of its kind with both answers along its knob, the same queries for
// the same seed, and the truth that its construction implies where the
// construction is exact (whole-step coplanar motion in the plane z = 0).
#include <gtest/gtest.h>

#include "tools/bench/stability_families.hpp"

namespace snag::bench {
namespace {

TEST(StabilityFamilies, EachHasBothAnswersAlongItsKnob) {
  const std::vector<StabilityFamily> families = stability_families();
  ASSERT_GE(families.size(), 10u);
  for (const StabilityFamily& family : families) {
    ASSERT_FALSE(family.knob_values.empty()) << family.name;
    std::size_t positives = 0, queries = 0;
    for (double knob : family.knob_values) {
      EXPECT_GT(knob, 0) << family.name;
      for (const LabelledQuery& q : family_queries(family, knob, 6, 11)) {
        EXPECT_EQ(q.query.edge_edge, family.edge_edge) << family.name;
        positives += q.truth;
        ++queries;
      }
    }
    EXPECT_GT(positives, 0u) << family.name;
    EXPECT_LT(positives, queries) << family.name;
  }
}

TEST(StabilityFamilies, SameSeedSameQueries) {
  const StabilityFamily family = stability_families().front();
  const auto a = family_queries(family, 1e-3, 5, 3), b = family_queries(family, 1e-3, 5, 3);
  ASSERT_EQ(a.size(), 5u);
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < 8; ++k) EXPECT_EQ(a[i].query.points[k].y, b[i].query.points[k].y);
}

TEST(StabilityFamilies, CoplanarVertexCollidesExactlyWhenItReachesTheEdge) {
  for (const StabilityFamily& family : stability_families()) {
    if (family.name != "vf-coplanar") continue;
    for (double knob : {1e-15, 1e-6, 1e-1}) {
      for (const LabelledQuery& q : family_queries(family, knob, 20, 5)) {
        for (const Vec3& p : q.query.points) EXPECT_EQ(p.z, 0.0);
        // The vertex rises from y = -1 toward the edge on y = 0 and ends +-knob from it.
        EXPECT_EQ(q.truth, q.query.points[4].y >= 0) << knob;
      }
    }
    return;
  }
  FAIL() << "no vf-coplanar family";
}

}  // namespace
}  // namespace snag::bench
