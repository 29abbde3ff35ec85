// The floating-point CCD kernels (vertex_face_ccd, edge_edge_ccd) and the
// exact method (validate/exact_ccd) on the degenerate families of
// ccd_degenerate_families.hpp: the float answer never contradicts the exact
// one, contacts at t = 0 are decided by structure, and every query finishes
// quickly. Prints the worst single-query time of each method per family.
// Times are the thread's CPU time, so that a loaded machine does not make
// the bounds flaky.
#include <gtest/gtest.h>
#include <time.h>

#include <algorithm>
#include <cstdio>

#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "tests/validate/ccd_degenerate_families.hpp"
#include "validate/exact_ccd.hpp"

namespace snag {
namespace {

using test::DegenerateFamily;
using test::DegenerateQuery;

// Generous bounds (a Release build needs a small fraction of them): the
// whole family, both methods, and one query of the float kernels. Under
// AddressSanitizer (scripts/sanitizer-build.sh) every memory access is
// checked and the same work takes several times longer; the bounds scale with
// it there, and stay as they are in every other build.
#if defined(__SANITIZE_ADDRESS__)
constexpr double kInstrumentationFactor = 10;
#else
constexpr double kInstrumentationFactor = 1;
#endif
constexpr double kFamilySeconds = 2.0 * kInstrumentationFactor;
constexpr double kFloatQuerySeconds = 0.01 * kInstrumentationFactor;

/// CPU seconds of the calling thread.
double cpu_now() {
  timespec now;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

double seconds_since(double start) { return cpu_now() - start; }

CcdResult float_ccd(const DegenerateQuery& q) {
  const auto& x = q.points;
  CcdSettings settings;
  settings.thickness = q.thickness;
  return q.edge_edge ? edge_edge_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings)
                     : vertex_face_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings);
}

validate::ExactCcdResult exact_ccd(const DegenerateQuery& q, double thickness) {
  return q.edge_edge ? validate::exact_edge_edge_ccd(q.points, thickness)
                     : validate::exact_vertex_face_ccd(q.points, thickness);
}

struct FamilyRun {
  int no = 0, yes = 0, uncertain = 0, colliding = 0;
  int started_in_contact = 0;  // exact: touching at t = 0 at thickness 0
  double float_worst = 0, exact_worst = 0, total = 0;
};

FamilyRun check_family(const DegenerateFamily& family, bool expect_all_decided = false) {
  FamilyRun run;
  // One untimed call first: the exact method's one-time set-up is not a query's time.
  if (!family.queries.empty()) (void)exact_ccd(family.queries.front(), 0);
  const double family_start = cpu_now();
  for (std::size_t i = 0; i < family.queries.size(); ++i) {
    const DegenerateQuery& q = family.queries[i];
    const std::string where = family.name + " query " + std::to_string(i) + (q.edge_edge ? " (EE" : " (VF") +
                              ", thickness " + std::to_string(q.thickness) + ")";
    double start = cpu_now();
    const CcdResult r = float_ccd(q);
    const double float_seconds = seconds_since(start);
    start = cpu_now();
    const validate::ExactCcdResult truth = exact_ccd(q, q.thickness);
    run.exact_worst = std::max(run.exact_worst, seconds_since(start));
    run.float_worst = std::max(run.float_worst, float_seconds);
    EXPECT_LT(float_seconds, kFloatQuerySeconds) << where;

    run.colliding += truth.collides;
    run.no += r.answer == CcdAnswer::kNo;
    run.yes += r.answer == CcdAnswer::kYes;
    run.uncertain += r.answer == CcdAnswer::kUncertain;
    if (r.answer == CcdAnswer::kNo) {
      EXPECT_FALSE(truth.collides) << "float kNo on a contact: " << where;
    } else if (truth.collides) {
      // kYes encloses the earliest contact; kUncertain encloses it if any.
      EXPECT_LE(r.toi_lo, truth.toi_hi) << where;
      EXPECT_GE(r.toi_hi, truth.toi_lo) << where;
    }
    if (r.answer == CcdAnswer::kYes) EXPECT_TRUE(truth.collides) << "float kYes on no contact: " << where;
    if (expect_all_decided && q.thickness == 0) EXPECT_NE(r.answer, CcdAnswer::kUncertain) << where;

    // Touching at t = 0 (thickness 0, exactly): decided by structure, at
    // every thickness.
    const validate::ExactCcdResult touching = q.thickness == 0 ? truth : exact_ccd(q, 0);
    if (touching.collides && touching.toi_hi == 0) {
      ++run.started_in_contact;
      EXPECT_EQ(r.answer, CcdAnswer::kYes) << "contact at t = 0 not decided: " << where;
      EXPECT_EQ(r.toi_lo, 0) << where;
      EXPECT_EQ(r.toi_hi, 0) << where;
    }
  }
  run.total = seconds_since(family_start);
  std::printf("%-48s %4zu queries: %3d colliding (%3d at t = 0); float no %3d yes %3d uncertain %3d; worst query "
              "float %7.1f us, exact %7.1f us; family %6.1f ms\n",
              family.name.c_str(), family.queries.size(), run.colliding, run.started_in_contact, run.no, run.yes,
              run.uncertain, 1e6 * run.float_worst, 1e6 * run.exact_worst, 1e3 * run.total);
  EXPECT_LT(run.total, kFamilySeconds) << family.name;
  return run;
}

TEST(CcdDegenerateFamilies, CoincidentVerticesAreDecidedAtTheStart) {
  const FamilyRun run = check_family(test::coincident_vertices_family());
  // Every query starts in contact: the float kernels decide all of them.
  EXPECT_EQ(run.started_in_contact, static_cast<int>(test::coincident_vertices_family().queries.size()));
  EXPECT_EQ(run.uncertain, 0);
}

TEST(CcdDegenerateFamilies, VertexOnEdgeIsDecidedAtTheStart) {
  const FamilyRun run = check_family(test::vertex_on_edge_family());
  EXPECT_EQ(run.started_in_contact, static_cast<int>(test::vertex_on_edge_family().queries.size()));
  EXPECT_EQ(run.uncertain, 0);
}

TEST(CcdDegenerateFamilies, CoplanarMotionNeverContradictsExact) {
  const FamilyRun run = check_family(test::coplanar_motion_family());
  EXPECT_GT(run.colliding, 0);
}

TEST(CcdDegenerateFamilies, OverlappingCoplanarFacesMovingTogetherNeverContradictExact) {
  const FamilyRun run = check_family(test::overlapping_faces_family());
  EXPECT_GT(run.started_in_contact, 0);
}

TEST(CcdDegenerateFamilies, ZeroLengthEdgesNeverContradictExact) {
  const FamilyRun run = check_family(test::zero_length_edges_family());
  EXPECT_GT(run.colliding, 0);
}

TEST(CcdDegenerateFamilies, CollapsedTrianglesNeverContradictExact) {
  const FamilyRun run = check_family(test::collapsed_triangles_family());
  EXPECT_GT(run.colliding, 0);
}

TEST(CcdDegenerateFamilies, ZeroMotionIsDecidedByTheStart) {
  const FamilyRun run = check_family(test::zero_motion_family(), /*expect_all_decided=*/true);
  EXPECT_GT(run.colliding, 0);
  EXPECT_GT(run.no, 0);
}

TEST(CcdDegenerateFamilies, TinyMotionNeverContradictsExact) {
  const FamilyRun run = check_family(test::tiny_motion_family());
  EXPECT_GT(run.started_in_contact, 0);
}

TEST(CcdDegenerateFamilies, HugeAndSmallCoordinatesNeverContradictExact) {
  const FamilyRun run = check_family(test::scales_family());
  EXPECT_GT(run.colliding, 0);
}

}  // namespace
}  // namespace snag
