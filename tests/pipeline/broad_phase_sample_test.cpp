// The VSS broad phase on two Blender-baked caches against brute force: the
// cloth_ball sample, and a self-colliding cloth lying bunched in a funnel
// (tests/real_assets/data/cloth_funnel, scripts/make-samples.sh), whose folds
// the solver holds a few millimetres apart, layer on layer: tight contact. With
// the set relation virtual_subdivision_grid.hpp documents:
//   T_leaf ⊆ T_vss ⊆ T_root
// (T_root: brute force over root triangles, T_leaf: brute force over the
// leaves of the virtual subdivision), for static detection and for CCD
// features; outputs sorted and unique. And the part that matters to users:
// every triangle pair that really intersects (exact-sign test over all of
// T_root) and every feature pair of T_root that really collides (the proven
// floating-point filter, exact where it is uncertain: exact_collision.hpp) is
// in the VSS output.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <iostream>
#include <string>
#include <vector>

#include "libcd/broad_phase/brute_force.hpp"
#include "libcd/broad_phase/virtual_subdivision_grid.hpp"
#include "libcd/narrow_phase/triangle_triangle.hpp"
#include "tests/pipeline/exact_collision.hpp"
#include "tests/pipeline/sample_cache.hpp"

namespace snag::test {
namespace {

template <class T>
bool sorted_unique(const std::vector<T>& v) {
  for (std::size_t i = 1; i < v.size(); ++i)
    if (!(v[i - 1] < v[i])) return false;
  return true;
}

template <class T>
bool includes(const std::vector<T>& big, const std::vector<T>& small) {
  return std::includes(big.begin(), big.end(), small.begin(), small.end());
}

BroadPhaseSettings two_threads() {
  BroadPhaseSettings settings;
  settings.threads = 2;
  return settings;
}

struct CacheCase {
  const char* name;
  const char* dir;                       ///< relative to the source tree
  std::vector<std::size_t> static_frames;
  std::vector<std::size_t> ccd_steps;    ///< steps f -> f + 1 with collisions
};

const CacheCase kCaches[] = {
    // The free fall, the first folds, the ball inside the cloth, the end;
    // steps with folds forming and the ball tunnelling through.
    {"cloth_ball", "samples/cloth_ball/", {2, 17, 25, 29, 39}, {16, 27, 30}},
    // Frames 33, 38 and 44 of the bake; steps from frames 33, 39 and 43.
    {"cloth_funnel", "tests/real_assets/data/cloth_funnel/", {0, 5, 11}, {0, 6, 10}},
};

class CacheBroadPhase : public ::testing::TestWithParam<CacheCase> {};

TEST_P(CacheBroadPhase, StaticVssLiesBetweenLeafAndRootBruteForceAndKeepsEveryIntersection) {
  auto source = open_cloth_body_cache(GetParam().dir);
  const Scene& scene = source->scene();
  VirtualSubdivisionGrid vss(true);
  BruteForceBroadPhase brute;
  vss.build(scene, two_threads());
  brute.build(scene, two_threads());
  std::size_t intersecting_frames = 0;
  for (std::size_t frame : GetParam().static_frames) {
    SCOPED_TRACE("frame " + std::to_string(frame));
    const std::vector<Vec3> x = read_positions(*source, frame);
    std::vector<TrianglePair> t_vss, t_root;
    vss.detect_static(x, t_vss);
    brute.detect_static(x, t_root);
    const std::vector<TrianglePair> t_leaf = brute_force_leaf_triangle_pairs(vss.leaves(), vss.bounds().triangles);
    EXPECT_TRUE(sorted_unique(t_vss));
    EXPECT_TRUE(sorted_unique(t_root));
    EXPECT_TRUE(sorted_unique(t_leaf));
    EXPECT_TRUE(includes(t_vss, t_leaf)) << "VSS misses a pair of overlapping leaves";
    EXPECT_TRUE(includes(t_root, t_vss)) << "VSS returns a pair whose root DOPs do not overlap";
    for (const TrianglePair& p : t_vss) ASSERT_LT(p.a, p.b);

    // Every pair of T_root that intersects is in T_vss.
    std::size_t intersecting = 0;
    for (const TrianglePair& p : t_root) {
      const Triangle& ta = scene.triangles()[p.a];
      const Triangle& tb = scene.triangles()[p.b];
      const Vec3 a[3] = {x[ta[0]], x[ta[1]], x[ta[2]]};
      const Vec3 b[3] = {x[tb[0]], x[tb[1]], x[tb[2]]};
      if (!triangles_intersect(a, ta.data(), b, tb.data())) continue;
      ++intersecting;
      ASSERT_TRUE(std::binary_search(t_vss.begin(), t_vss.end(), p))
          << "intersecting pair (" << p.a << ", " << p.b << ") missed";
    }
    intersecting_frames += intersecting > 0;
    std::cout << "[ frame " << frame << " ] T_leaf " << t_leaf.size() << "  T_vss " << t_vss.size() << "  T_root "
              << t_root.size() << "  intersecting " << intersecting << "  leaves " << vss.leaves().size() << "\n";
  }
  EXPECT_GT(intersecting_frames, 0u);  // the frames were picked for their intersections too
}

// The brute force here keeps every feature pair whose DOPs overlap, the
// triangle pairs proved apart included (separate_triangles off), so that a
// colliding pair the VSS grid's separation dropped would show.
TEST_P(CacheBroadPhase, CcdVssLiesBetweenLeafAndRootBruteForceAndKeepsEveryCollision) {
  auto source = open_cloth_body_cache(GetParam().dir);
  const Scene& scene = source->scene();
  VirtualSubdivisionGrid vss(true);
  BruteForceBroadPhase brute;
  vss.build(scene, two_threads());
  BroadPhaseSettings unseparated = two_threads();
  unseparated.separate_triangles = false;
  brute.build(scene, unseparated);
  const RepresentativeTriangles reps = assign_representative_triangles(scene);
  for (std::size_t step : GetParam().ccd_steps) {
    SCOPED_TRACE("step " + std::to_string(step));
    const std::vector<Vec3> x_t0 = read_positions(*source, step), x_t1 = read_positions(*source, step + 1);
    std::vector<VertexFaceCandidate> vf_vss, vf_root, vf_leaf;
    std::vector<EdgeEdgeCandidate> ee_vss, ee_root, ee_leaf;
    vss.detect_ccd(x_t0, x_t1, vf_vss, ee_vss);
    brute.detect_ccd(x_t0, x_t1, vf_root, ee_root);
    const std::vector<TrianglePair> leaf_pairs = brute_force_leaf_triangle_pairs(vss.leaves(), vss.bounds().triangles);
    FeatureCounts counts;
    const TriangleSeparation separation{x_t0.data(), x_t1.data(), 0};
    representative_feature_pairs(scene, reps, vss.bounds(), leaf_pairs, vf_leaf, ee_leaf, counts, &separation);
    EXPECT_GT(vss.stats().separated_triangle_pairs, 0u);
    EXPECT_EQ(brute.stats().separated_triangle_pairs, 0u);

    EXPECT_TRUE(sorted_unique(vf_vss));
    EXPECT_TRUE(sorted_unique(ee_vss));
    EXPECT_TRUE(includes(vf_vss, vf_leaf)) << "VSS misses a VF pair of overlapping leaves";
    EXPECT_TRUE(includes(ee_vss, ee_leaf)) << "VSS misses an EE pair of overlapping leaves";
    EXPECT_TRUE(includes(vf_root, vf_vss));
    EXPECT_TRUE(includes(ee_root, ee_vss));

    // Every brute-force feature pair that collides exactly is a VSS candidate.
    std::size_t vf_colliding = 0, ee_colliding = 0;
    for (const VertexFaceCandidate& c : vf_root) {
      if (!collides_screened(PairKind::kVertexFace,
                             pair_points(scene, x_t0, x_t1, PairKind::kVertexFace, c.vertex, c.face))) {
        continue;
      }
      ++vf_colliding;
      EXPECT_TRUE(std::binary_search(vf_vss.begin(), vf_vss.end(), c))
          << "colliding VF (" << c.vertex << ", " << c.face << ") missed";
    }
    for (const EdgeEdgeCandidate& c : ee_root) {
      if (!collides_screened(PairKind::kEdgeEdge,
                             pair_points(scene, x_t0, x_t1, PairKind::kEdgeEdge, c.edge_a, c.edge_b))) {
        continue;
      }
      ++ee_colliding;
      EXPECT_TRUE(std::binary_search(ee_vss.begin(), ee_vss.end(), c))
          << "colliding EE (" << c.edge_a << ", " << c.edge_b << ") missed";
    }
    EXPECT_GT(vf_colliding + ee_colliding, 0u);  // the steps were picked for their collisions
    std::cout << "[ step " << step << " ] VF leaf/vss/root " << vf_leaf.size() << "/" << vf_vss.size() << "/"
              << vf_root.size() << "  EE " << ee_leaf.size() << "/" << ee_vss.size() << "/" << ee_root.size()
              << "  colliding VF " << vf_colliding << " EE " << ee_colliding << "  triangle pairs "
              << vss.stats().triangle_pairs << ", separated " << vss.stats().separated_triangle_pairs << "\n";
  }
}

INSTANTIATE_TEST_SUITE_P(BlenderCaches, CacheBroadPhase, ::testing::ValuesIn(kCaches),
                         [](const ::testing::TestParamInfo<CacheCase>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace snag::test
