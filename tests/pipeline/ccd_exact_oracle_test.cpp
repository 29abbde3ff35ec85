// Oracle tests of the CPU pipeline's collisions (CCD) on the cloth_ball
// sample, in certified mode:
//   - every reported collision is confirmed by the exact CCD
//     (validate/exact_ccd.hpp), and its time of impact agrees;
//   - on a few steps, an exhaustive search finds nothing the pipeline missed
//     and nothing it added: every vertex-face and edge-edge pair of the scene
//     (not sharing a vertex) whose swept boxes overlap is decided, and the
//     colliding ones must be exactly the reported events. On one step every
//     such pair is decided exactly (12,500 pairs, the costly part); on two
//     more, with the ball in the cloth, the proven floating-point filter
//     screens the pairs first and the exact test decides what it leaves
//     uncertain (exact_collision.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <iostream>
#include <iterator>
#include <utility>
#include <vector>

#include "libcd/narrow_phase/ccd_swept_aabb.hpp"
#include "libcd/pipeline/backend.hpp"
#include "tests/pipeline/exact_collision.hpp"
#include "tests/pipeline/sample_cache.hpp"
#include "validate/exact_certifier.hpp"

namespace snag::test {
namespace {

using ElementPair = std::pair<Index, Index>;

/// A back end bound to the sample's scene in certified mode.
struct CertifiedBackend {
  std::unique_ptr<Certifier> certifier = validate::make_exact_certifier();
  std::unique_ptr<Backend> backend = make_cpu_backend();
  explicit CertifiedBackend(const Scene& scene) {
    BackendSettings settings;
    settings.threads = 2;
    settings.certifier = certifier.get();
    backend->bind(scene, settings);
  }
};

TEST(PipelineCollisions, EveryCertifiedCollisionOfTheSampleIsConfirmedExactly) {
  auto source = open_sample_cache();
  const Scene& scene = source->scene();
  CertifiedBackend cpu(scene);
  std::vector<Vec3> x_t0 = read_positions(*source, 0), x_t1;
  std::size_t total = 0, vf = 0, ee = 0;
  for (std::size_t step = 0; step + 1 < source->frame_count(); ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    source->read_frame(step + 1, x_t1);
    std::vector<Event> events;
    cpu.backend->collisions(x_t0, x_t1, events);
    EXPECT_TRUE(std::is_sorted(events.begin(), events.end(), event_order));
    for (const Event& e : events) {
      ASSERT_EQ(e.kind, EventKind::kCollision);
      EXPECT_EQ(e.certainty, Certainty::kProven);
      const bool is_vf = e.type == ContactType::kVertexFace;
      const PairKind kind = is_vf ? PairKind::kVertexFace : PairKind::kEdgeEdge;
      const validate::ExactCcdResult exact = exact_collision(kind, pair_points(scene, x_t0, x_t1, kind, e.a, e.b));
      EXPECT_TRUE(exact.collides) << (is_vf ? "VF " : "EE ") << e.a << " " << e.b << " is not a collision";
      // Both intervals enclose the earliest time of impact: they overlap.
      EXPECT_LE(e.toi_lo, e.toi_hi);
      EXPECT_LE(e.toi_lo, exact.toi_hi) << (is_vf ? "VF " : "EE ") << e.a << " " << e.b;
      EXPECT_LE(exact.toi_lo, e.toi_hi) << (is_vf ? "VF " : "EE ") << e.a << " " << e.b;
      EXPECT_GE(e.toi_lo, 0.0);
      EXPECT_LE(e.toi_hi, 1.0);
      vf += is_vf;
      ee += !is_vf;
    }
    total += events.size();
    std::swap(x_t0, x_t1);
  }
  EXPECT_GT(total, 0u);
  std::cout << "[ sample ] " << total << " certified collisions over 39 steps (" << vf << " VF, " << ee << " EE)\n";
}

/// The collisions of one step over all pairs of the scene whose swept boxes
/// overlap: VF (vertex, face) and EE (edge_a < edge_b), sorted; decided
/// exactly, or screened by the floating-point filter when `screened`.
struct ExhaustiveResult {
  std::vector<ElementPair> vf, ee;
  std::size_t vf_boxes = 0, ee_boxes = 0;  ///< pairs left by the swept-box filter
};

ExhaustiveResult exhaustive_ccd(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                bool screened) {
  ExhaustiveResult result;
  auto collides = [&](PairKind kind, Index a, Index b) {
    const std::array<Vec3, 8> points = pair_points(scene, x_t0, x_t1, kind, a, b);
    return screened ? collides_screened(kind, points) : exact_collision(kind, points, 1.0).collides;
  };
  const std::size_t n = scene.vertex_count();
  std::vector<SweptBox> vertex_box(n), face_box(scene.triangle_count()), edge_box(scene.edge_count());
  for (std::size_t v = 0; v < n; ++v) {
    const Vec3 p[2] = {x_t0[v], x_t1[v]};
    vertex_box[v] = swept_box(p, 2);
  }
  for (std::size_t f = 0; f < scene.triangle_count(); ++f) {
    const Triangle& t = scene.triangles()[f];
    const Vec3 p[6] = {x_t0[t[0]], x_t0[t[1]], x_t0[t[2]], x_t1[t[0]], x_t1[t[1]], x_t1[t[2]]};
    face_box[f] = swept_box(p, 6);
  }
  for (std::size_t e = 0; e < scene.edge_count(); ++e) {
    const Edge& d = scene.edges()[e];
    const Vec3 p[4] = {x_t0[d[0]], x_t0[d[1]], x_t1[d[0]], x_t1[d[1]]};
    edge_box[e] = swept_box(p, 4);
  }
  for (Index v = 0; v < n; ++v) {
    for (Index f = 0; f < scene.triangle_count(); ++f) {
      const Triangle& t = scene.triangles()[f];
      if (t[0] == v || t[1] == v || t[2] == v) continue;
      if (!swept_boxes_overlap(vertex_box[v], face_box[f], 0)) continue;
      ++result.vf_boxes;
      if (collides(PairKind::kVertexFace, v, f)) {
        result.vf.emplace_back(v, f);
      }
    }
  }
  for (Index a = 0; a < scene.edge_count(); ++a) {
    const Edge& ea = scene.edges()[a];
    for (Index b = a + 1; b < scene.edge_count(); ++b) {
      const Edge& eb = scene.edges()[b];
      if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) continue;
      if (!swept_boxes_overlap(edge_box[a], edge_box[b], 0)) continue;
      ++result.ee_boxes;
      if (collides(PairKind::kEdgeEdge, a, b)) {
        result.ee.emplace_back(a, b);
      }
    }
  }
  return result;
}

void expect_same_pairs(const std::vector<ElementPair>& expected, const std::vector<ElementPair>& found,
                       const char* what) {
  std::vector<ElementPair> missed, extra;
  std::set_difference(expected.begin(), expected.end(), found.begin(), found.end(), std::back_inserter(missed));
  std::set_difference(found.begin(), found.end(), expected.begin(), expected.end(), std::back_inserter(extra));
  EXPECT_TRUE(missed.empty()) << missed.size() << " " << what << " collisions missed, first (" << missed[0].first
                              << ", " << missed[0].second << ")";
  EXPECT_TRUE(extra.empty()) << extra.size() << " " << what << " events not confirmed, first (" << extra[0].first
                             << ", " << extra[0].second << ")";
}

/// Runs the exhaustive search on `step` and compares it with the pipeline.
void expect_exhaustive_search_matches_pipeline(std::size_t step, bool screened) {
  auto source = open_sample_cache();
  const Scene& scene = source->scene();
  CertifiedBackend cpu(scene);
  {
    SCOPED_TRACE("step " + std::to_string(step));
    const std::vector<Vec3> x_t0 = read_positions(*source, step), x_t1 = read_positions(*source, step + 1);
    std::vector<Event> events;
    cpu.backend->collisions(x_t0, x_t1, events);
    std::vector<ElementPair> vf, ee;
    for (const Event& e : events) (e.type == ContactType::kVertexFace ? vf : ee).emplace_back(e.a, e.b);
    const auto start = std::chrono::steady_clock::now();
    const ExhaustiveResult exhaustive = exhaustive_ccd(scene, x_t0, x_t1, screened);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_GT(exhaustive.vf.size() + exhaustive.ee.size(), 0u) << "the step was picked for its collisions";
    expect_same_pairs(exhaustive.vf, vf, "VF");
    expect_same_pairs(exhaustive.ee, ee, "EE");
    std::cout << "[ step " << step << " ] exhaustive" << (screened ? " (screened)" : " (all exact)") << ": " << exhaustive.vf_boxes << " VF and " << exhaustive.ee_boxes
              << " EE pairs with overlapping swept boxes, " << exhaustive.vf.size() << " VF and "
              << exhaustive.ee.size() << " EE collisions (" << seconds << " s); pipeline " << vf.size() << " VF, "
              << ee.size() << " EE\n";
  }
}

// Step 14: the first contacts of the falling cloth's folds; every pair exact.
TEST(PipelineCollisions, ExhaustiveExactSearchFindsExactlyTheReportedCollisionsOfStep14) {
  expect_exhaustive_search_matches_pipeline(14, false);
}

// Steps 16 (folds forming) and 31 (the ball leaving the cloth): screened.
TEST(PipelineCollisions, ExhaustiveScreenedSearchFindsExactlyTheReportedCollisionsOfSteps16And31) {
  expect_exhaustive_search_matches_pipeline(16, true);
  expect_exhaustive_search_matches_pipeline(31, true);
}

}  // namespace
}  // namespace snag::test
