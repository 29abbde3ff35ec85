// Tests for the adaptive grid (grid/adaptive_cells.hpp, the kAdaptiveGrid
// broad phase): every pair of leaves whose fine blocks meet is owned by
// exactly one test cell (counted by brute force over the leaf pairs); the
// triangle pairs equal T_leaf (brute_force_leaf_triangle_pairs), CCD and
// static; the CPU back end gives the events of the uniform grid and of brute
// force with one thread and two; depth and registrations stay bounded when
// every triangle lies in one point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>

#include "bench/broad_phase/binary_ply.hpp"
#include "libcd/broad_phase/brute_force.hpp"
#include "libcd/broad_phase/virtual_subdivision_grid.hpp"
#include "libcd/cpu/cpu_backend.hpp"
#include "libcd/core/error.hpp"
#include "libcd/grid/adaptive_cells.hpp"

namespace snag {
namespace {

struct Step {
  Scene scene;
  std::vector<Vec3> x_t0, x_t1;
};

// A dense cluster of tiny triangles (a hundredth of the scene) beside big
// sparse ones: the mean radius gives cells that the cluster crowds.
Step uneven_scene(unsigned seed, int tiny, int big) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> x;
  std::vector<Triangle> tris;
  auto add = [&](Vec3 c, double size) {
    const Index base = static_cast<Index>(x.size());
    for (int k = 0; k < 3; ++k) x.push_back(c + Vec3{size * (u(rng) - 0.5), size * (u(rng) - 0.5), size * (u(rng) - 0.5)});
    tris.push_back({base, base + 1, base + 2});
  };
  for (int k = 0; k < tiny; ++k) add(Vec3{0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng)}, 0.01);
  for (int k = 0; k < big; ++k) add(Vec3{10 * u(rng), 10 * u(rng), 10 * u(rng)}, 3.0);
  Step step{Scene({make_object("uneven", static_cast<Index>(x.size()), tris)}), x, x};
  for (Vec3& p : step.x_t1) p = p + Vec3{0.004 * (u(rng) - 0.5), 0.004 * (u(rng) - 0.5), 0.004 * (u(rng) - 0.5)};
  return step;
}

// A sheet of n×n quads folded into a small box: many layers of small
// triangles stacked in few cells, moving closer over the step.
Step crumpled_sheet(int n) {
  std::vector<Vec3> x0, x1;
  std::vector<Triangle> tris;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double s = double(i) / n, t = double(j) / n;
      const Vec3 p{0.2 * std::sin(12 * s) + 0.05 * t, 0.2 * std::sin(9 * t) + 0.03 * s, 0.1 * std::sin(20 * (s + t))};
      x0.push_back(p);
      x1.push_back(p * 0.97 + Vec3{0.002 * std::sin(31 * s), 0.002 * std::cos(27 * t), 0});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Index a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      tris.push_back({a, b, d});
      tris.push_back({a, d, c});
    }
  return {Scene({make_object("sheet", static_cast<Index>(x0.size()), tris)}), x0, x1};
}

Step cloth_ball_step() {
  const std::string dir = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/";
  bench::PlyMesh a = bench::read_binary_ply(dir + "cloth_ball92.ply");
  bench::PlyMesh b = bench::read_binary_ply(dir + "cloth_ball93.ply");
  return {Scene({make_object("cloth_ball", static_cast<Index>(a.vertices.size()), a.triangles)}), a.vertices,
          b.vertices};
}

BroadPhaseSettings small_cells(unsigned threads) {
  BroadPhaseSettings s;
  s.adaptive_cell_limit = 8;
  s.threads = threads;
  return s;
}

// Each pair of leaves (distinct roots, nested slots) whose fine blocks meet is
// listed and owned by exactly one test cell; no other pair is owned.
void expect_each_leaf_pair_owned_once(const std::vector<Leaf>& leaves, const GridSpec& grid, int depth,
                                      std::size_t limit, const std::string& what) {
  const AdaptiveCells tree = build_adaptive_cells(leaves, grid, depth, limit);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> owned;
  for (const TestCell& cell : tree.cells)
    for (std::uint32_t i = 0; i < cell.stuck; ++i)
      for (std::uint32_t j = i + 1; j < cell.count; ++j) {
        std::uint32_t a = tree.members[cell.first + i], b = tree.members[cell.first + j];
        if (a > b) std::swap(a, b);
        if (adaptive_cell_owns_pair(tree.blocks[a], tree.blocks[b], tree.depth, cell.level, cell.coord))
          ++owned[{a, b}];
      }
  std::size_t meeting = 0;
  for (std::uint32_t a = 0; a < leaves.size(); ++a)
    for (std::uint32_t b = a + 1; b < leaves.size(); ++b) {
      const FineBlock &p = tree.blocks[a], &q = tree.blocks[b];
      if (std::max(p.lo.x, q.lo.x) > std::min(p.hi.x, q.hi.x) || std::max(p.lo.y, q.lo.y) > std::min(p.hi.y, q.hi.y) ||
          std::max(p.lo.z, q.lo.z) > std::min(p.hi.z, q.hi.z))
        continue;
      ++meeting;
      const auto it = owned.find({a, b});
      ASSERT_TRUE(it != owned.end()) << what << ": leaves " << a << ", " << b << " meet and are tested nowhere";
      ASSERT_EQ(it->second, 1) << what << ": leaves " << a << ", " << b << " tested " << it->second << " times";
    }
  EXPECT_EQ(owned.size(), meeting) << what;
  EXPECT_GT(tree.cells_subdivided, 0u) << what << ": the scene should crowd some cell";
}

// Adaptive triangle pairs == T_leaf of the same leaves (static), and CCD
// features == the features of T_leaf; both within the uniform grid's.
void expect_adaptive_equals_leaf_oracle(const Step& step, const BroadPhaseSettings& settings, const std::string& what) {
  VirtualSubdivisionGrid adaptive(true, VirtualSubdivisionGrid::Cells::kAdaptive), uniform(true);
  adaptive.build(step.scene, settings);
  uniform.build(step.scene, settings);
  std::vector<TrianglePair> pa, pu;
  adaptive.detect_static(step.x_t0, pa);
  uniform.detect_static(step.x_t0, pu);
  EXPECT_TRUE(pa == brute_force_leaf_triangle_pairs(adaptive.leaves(), adaptive.bounds().triangles)) << what;
  EXPECT_TRUE(std::includes(pu.begin(), pu.end(), pa.begin(), pa.end())) << what;
  EXPECT_GT(adaptive.stats().cells_subdivided, 0u) << what;
  EXPECT_EQ(adaptive.stats().tests_after_control_bits - adaptive.stats().culled_by_dop,
            pa.size() + adaptive.stats().duplicate_root_pair_tests)
      << what;

  std::vector<VertexFaceCandidate> vf, leaf_vf;
  std::vector<EdgeEdgeCandidate> ee, leaf_ee;
  adaptive.detect_ccd(step.x_t0, step.x_t1, vf, ee);
  FeatureCounts counts;
  const TriangleSeparation separation{step.x_t0.data(), step.x_t1.data(), settings.thickness};
  representative_feature_pairs(step.scene, assign_representative_triangles(step.scene), adaptive.bounds(),
                               brute_force_leaf_triangle_pairs(adaptive.leaves(), adaptive.bounds().triangles),
                               leaf_vf, leaf_ee, counts, &separation);
  EXPECT_EQ(adaptive.stats().separated_triangle_pairs, counts.separated) << what;
  EXPECT_TRUE(vf == leaf_vf) << what << ": CCD VF " << vf.size() << ", oracle " << leaf_vf.size();
  EXPECT_TRUE(ee == leaf_ee) << what << ": CCD EE " << ee.size() << ", oracle " << leaf_ee.size();
  EXPECT_GT(vf.size() + ee.size(), 0u) << what;
}

bool same_events(const std::vector<Event>& a, const std::vector<Event>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].type != b[i].type || a[i].a != b[i].a || a[i].b != b[i].b || a[i].toi_lo != b[i].toi_lo ||
        a[i].toi_hi != b[i].toi_hi || a[i].certainty != b[i].certainty)
      return false;
  return true;
}

// The CPU back end's collisions and intersections with `method`.
void events_of(const Step& step, BroadPhaseMethod method, unsigned threads, std::vector<Event>& ccd,
               std::vector<Event>& dcd) {
  CpuBackendOptions options;
  options.broad_phase = method;
  auto backend = make_cpu_backend(options);
  BackendSettings settings;
  settings.threads = threads;
  backend->bind(step.scene, settings);
  backend->collisions(step.x_t0, step.x_t1, ccd);
  backend->intersections(step.x_t1, dcd);
}

void expect_same_events(const Step& step, std::vector<BroadPhaseMethod> references, const std::string& what) {
  std::vector<Event> ccd1, dcd1, ccd2, dcd2;
  events_of(step, BroadPhaseMethod::kAdaptiveGrid, 1, ccd1, dcd1);
  events_of(step, BroadPhaseMethod::kAdaptiveGrid, 2, ccd2, dcd2);
  EXPECT_TRUE(same_events(ccd1, ccd2)) << what << ": collisions differ between 1 and 2 threads";
  EXPECT_TRUE(same_events(dcd1, dcd2)) << what << ": intersections differ between 1 and 2 threads";
  for (BroadPhaseMethod method : references) {
    std::vector<Event> ccd, dcd;
    events_of(step, method, 2, ccd, dcd);
    EXPECT_TRUE(same_events(ccd, ccd2)) << what << ": collisions " << ccd2.size() << ", reference " << ccd.size();
    EXPECT_TRUE(same_events(dcd, dcd2)) << what << ": intersections " << dcd2.size() << ", reference " << dcd.size();
  }
  EXPECT_GT(ccd2.size() + dcd2.size(), 0u) << what;
}

TEST(AdaptiveCells, EachLeafPairIsOwnedByExactlyOneCell) {
  for (const auto& [step, name] : {std::pair{uneven_scene(3, 400, 30), "uneven"}, std::pair{crumpled_sheet(24), "sheet"}}) {
    VirtualSubdivisionGrid uniform(true);
    uniform.build(step.scene, {});
    std::vector<VertexFaceCandidate> vf;
    std::vector<EdgeEdgeCandidate> ee;
    uniform.detect_ccd(step.x_t0, step.x_t1, vf, ee);
    for (int depth : {1, 4}) expect_each_leaf_pair_owned_once(uniform.leaves(), uniform.grid(), depth, 8, name);
  }
}

TEST(AdaptiveGrid, EqualsLeafOracleOnUnevenScenes) {
  for (unsigned threads : {1u, 2u}) {
    expect_adaptive_equals_leaf_oracle(uneven_scene(7, 700, 40), small_cells(threads), "uneven");
    expect_adaptive_equals_leaf_oracle(crumpled_sheet(28), small_cells(threads), "crumpled sheet");
  }
}

TEST(AdaptiveGrid, GivesTheEventsOfTheUniformGridAndBruteForce) {
  expect_same_events(uneven_scene(5, 1500, 60),
                     {BroadPhaseMethod::kVirtualSubdivisionGrid, BroadPhaseMethod::kBruteForce}, "uneven");
  expect_same_events(crumpled_sheet(40), {BroadPhaseMethod::kVirtualSubdivisionGrid, BroadPhaseMethod::kBruteForce},
                     "crumpled sheet");
}

TEST(AdaptiveGrid, GivesTheEventsOfTheUniformGridOnTheClothBall) {
  expect_same_events(cloth_ball_step(), {BroadPhaseMethod::kVirtualSubdivisionGrid, BroadPhaseMethod::kBoxGrid},
                     "cloth_ball 92-93");
}

TEST(AdaptiveGrid, AllTrianglesInOnePointStayBounded) {
  std::vector<Vec3> x(3 * 500, Vec3{1, 2, 3});
  std::vector<Triangle> tris;
  for (Index k = 0; k < 500; ++k) tris.push_back({3 * k, 3 * k + 1, 3 * k + 2});
  const Step step{Scene({make_object("point", static_cast<Index>(x.size()), tris)}), x, x};
  for (int depth : {0, 3, 8}) {
    BroadPhaseSettings settings = small_cells(2);
    settings.adaptive_max_depth = depth;
    VirtualSubdivisionGrid adaptive(true, VirtualSubdivisionGrid::Cells::kAdaptive);
    adaptive.build(step.scene, settings);
    std::vector<TrianglePair> pairs;
    adaptive.detect_static(step.x_t0, pairs);
    const BroadPhaseStats& s = adaptive.stats();
    EXPECT_EQ(pairs.size(), 500u * 499 / 2) << depth;
    EXPECT_LE(s.deepest_level, depth);
    EXPECT_LE(s.registrations, 8 * (depth + 1) * s.leaf_triangles) << depth;
    EXPECT_EQ(s.tests_after_control_bits, 500u * 499 / 2) << depth << ": each pair owned by one cell";
    EXPECT_LE(s.tests, 8 * s.tests_after_control_bits) << depth;
    EXPECT_LE(s.memory_bytes, 2000 * s.leaf_triangles + 64 * pairs.size()) << depth;
  }
  BroadPhaseSettings bad;
  bad.adaptive_max_depth = 9;
  VirtualSubdivisionGrid adaptive(true, VirtualSubdivisionGrid::Cells::kAdaptive);
  EXPECT_THROW(adaptive.build(step.scene, bad), UsageError);
  bad = {};
  bad.adaptive_cell_limit = 1;
  EXPECT_THROW(adaptive.build(step.scene, bad), UsageError);
}

}  // namespace
}  // namespace snag
