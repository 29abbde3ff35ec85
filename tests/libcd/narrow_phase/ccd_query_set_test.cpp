// The CCD kernels against the exact ground truth of the reference query set
// (Wang et al. 2021, ../shared/data/ccd-queries/): no false negative and no
// false "yes" on any query, and the undecided counts stay where they were
// measured.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "io/ccd_query_csv.hpp"
#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"

namespace snag {
namespace {

const std::string kQueryRoot = std::string(SNAG_SHARED_DATA_DIR) + "/ccd-queries";

struct Counts {
  int queries = 0, colliding = 0;
  int false_negatives = 0;   // kNo on truth 1
  int false_yes = 0;         // kYes on truth 0
  int false_positives = 0;   // kYes or kUncertain on truth 0
  int uncertain = 0;         // kUncertain, either truth
  int toi_mismatch = 0;      // kYes with toi_lo > toi_hi
};

CcdResult run(const io::CcdQuery& q, const CcdSettings& settings) {
  const auto& x = q.points;
  return q.is_edge_edge ? edge_edge_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings)
                        : vertex_face_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings);
}

void count_all(const CcdSettings& settings, Counts& vf, Counts& ee) {
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(kQueryRoot);
  for (const io::CcdQuery& q : queries) {
    Counts& c = q.is_edge_edge ? ee : vf;
    const CcdResult r = run(q, settings);
    ++c.queries;
    c.colliding += q.truth;
    if (q.truth && r.answer == CcdAnswer::kNo) {
      ++c.false_negatives;
      ADD_FAILURE() << "false negative: " << q.file << ":" << q.line;
    }
    if (!q.truth && r.answer == CcdAnswer::kYes) {
      ++c.false_yes;
      ADD_FAILURE() << "false yes: " << q.file << ":" << q.line;
    }
    if (!q.truth && r.answer != CcdAnswer::kNo) ++c.false_positives;
    if (r.answer == CcdAnswer::kUncertain) ++c.uncertain;
    if (r.answer != CcdAnswer::kNo && !(0 <= r.toi_lo && r.toi_lo <= r.toi_hi && r.toi_hi <= 1)) ++c.toi_mismatch;
  }
}

void print(const char* kind, const Counts& c) {
  std::printf("%s: %d queries (%d colliding), false negatives %d, false yes %d, false positives %d, uncertain %d\n",
              kind, c.queries, c.colliding, c.false_negatives, c.false_yes, c.false_positives, c.uncertain);
}

TEST(CcdQuerySet, NeverMissesAContactNorProvesAFalseOne) {
  Counts vf, ee;
  count_all(CcdSettings{}, vf, ee);
  print("vertex-face", vf);
  print("edge-edge", ee);
  // Every file of the set is read: 2000 vertex-face and 1824 edge-edge queries.
  EXPECT_EQ(vf.queries, 2000);
  EXPECT_EQ(ee.queries, 1824);
  EXPECT_EQ(vf.false_negatives, 0);
  EXPECT_EQ(ee.false_negatives, 0);
  EXPECT_EQ(vf.false_yes, 0);
  EXPECT_EQ(ee.false_yes, 0);
  EXPECT_EQ(vf.toi_mismatch, 0);
  EXPECT_EQ(ee.toi_mismatch, 0);
  // Measured with the default settings; a regression makes more queries
  // undecided and sends them to exact arithmetic. (Before the early exits:
  // 85, 137, 162 and 234; the coplanarity cubic and the separating
  // directions prove 38 vertex-face and 60 edge-edge non-contacts that the
  // inclusion search left undecided. The decisions by structure prove the 3
  // edge-edge contacts at t = 0; a cap of 100,000 boxes instead of
  // CcdSettings' decides none of these queries more.)
  EXPECT_LE(vf.false_positives, 47);
  EXPECT_LE(ee.false_positives, 77);
  EXPECT_LE(vf.uncertain, 111);
  EXPECT_LE(ee.uncertain, 165);
}

}  // namespace
}  // namespace snag
