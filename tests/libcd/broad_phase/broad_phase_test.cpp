// Tests for broad_phase/: every grid against brute-force oracles.
//   T_leaf ⊆ VSS ⊆ T_root (virtual_subdivision_grid.hpp), largest-triangle
//   grid == brute force, box grid == brute force (static and CCD), outputs
//   sorted and unique, no VF/EE pair sharing a vertex, results independent
//   of the thread count; on random soups with very uneven triangles, fast
//   movers, and the reference meshes.
#include <gtest/gtest.h>

#include <memory>
#include <utility>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "bench/broad_phase/binary_ply.hpp"
#include "libcd/bounding_volume/float_box.hpp"
#include "libcd/bounding_volume/primitive_bounds.hpp"
#include "libcd/broad_phase/box_grid.hpp"
#include "libcd/broad_phase/brute_force.hpp"
#include "libcd/broad_phase/virtual_subdivision_grid.hpp"
#include "libcd/core/error.hpp"

namespace snag {
namespace {

struct Soup {
  Scene scene;
  std::vector<Vec3> x_t0, x_t1;
};

// n triangles of very uneven sizes: tiny, medium, huge, slivers, degenerate;
// some share vertices (strips). Moving ones get a random displacement, a few
// fast movers cross the scene.
Soup random_soup(unsigned seed, int n, bool moving) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> x;
  std::vector<Triangle> tris;
  auto point = [&] { return Vec3{u(rng) * 10, u(rng) * 10, u(rng) * 10}; };
  for (int k = 0; k < n; ++k) {
    const Index base = static_cast<Index>(x.size());
    const double kind = u(rng);
    const Vec3 c = point();
    double size = kind < 0.5 ? 0.05 : (kind < 0.85 ? 0.4 : (kind < 0.95 ? 2.5 : 6.0));
    Vec3 a = c, b = c + Vec3{size * (u(rng) - 0.5), size * (u(rng) - 0.5), size * (u(rng) - 0.5)};
    Vec3 d = c + Vec3{size * (u(rng) - 0.5), size * (u(rng) - 0.5), size * (u(rng) - 0.5)};
    if (k % 13 == 5) d = lerp(a, b, 0.3);                       // degenerate (collinear)
    if (k % 17 == 3) d = a + Vec3{1e-4, 0, 0};                  // thin sliver
    if (k % 7 == 2 && base >= 3) {                              // share an edge with the previous triangle
      x.push_back(d);
      tris.push_back({base - 1, base - 2, base});
      continue;
    }
    x.push_back(a);
    x.push_back(b);
    x.push_back(d);
    tris.push_back({base, base + 1, base + 2});
  }
  Soup soup{Scene({make_object("soup", static_cast<Index>(x.size()), tris)}), x, x};
  if (moving) {
    for (std::size_t v = 0; v < x.size(); ++v) {
      soup.x_t1[v] = x[v] + Vec3{0.3 * (u(rng) - 0.5), 0.3 * (u(rng) - 0.5), 0.3 * (u(rng) - 0.5)};
    }
    for (const Triangle& t : tris) {
      if (u(rng) < 0.03) {  // a fast mover: the whole triangle crosses the scene
        const Vec3 jump{8 * (u(rng) - 0.5), 8 * (u(rng) - 0.5), 8};
        for (Index v : t) soup.x_t1[v] = x[v] + jump;
      }
    }
  }
  return soup;
}

bool shares_vertex(const Scene& scene, const VertexFaceCandidate& c) {
  const Triangle& t = scene.triangles()[c.face];
  return t[0] == c.vertex || t[1] == c.vertex || t[2] == c.vertex;
}
bool shares_vertex(const Scene& scene, const EdgeEdgeCandidate& c) {
  const Edge& a = scene.edges()[c.edge_a];
  const Edge& b = scene.edges()[c.edge_b];
  return a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1];
}

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

struct CcdSets {
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
};

// Checks T_leaf ⊆ VSS ⊆ T_root for CCD and the largest-triangle grid == T_root.
void check_ccd_against_oracles(const Soup& soup, const BroadPhaseSettings& settings) {
  VirtualSubdivisionGrid vss(true), largest(false);
  BruteForceBroadPhase brute;
  vss.build(soup.scene, settings);
  largest.build(soup.scene, settings);
  brute.build(soup.scene, settings);
  CcdSets a, l, b, leaf;
  vss.detect_ccd(soup.x_t0, soup.x_t1, a.vf, a.ee);
  largest.detect_ccd(soup.x_t0, soup.x_t1, l.vf, l.ee);
  brute.detect_ccd(soup.x_t0, soup.x_t1, b.vf, b.ee);

  const std::vector<TrianglePair> leaf_pairs = brute_force_leaf_triangle_pairs(vss.leaves(), vss.bounds().triangles);
  // The oracle leaves out the triangle pairs the grids' feature stage proves apart.
  FeatureCounts counts;
  const TriangleSeparation separation{soup.x_t0.data(), soup.x_t1.data(), settings.thickness};
  representative_feature_pairs(soup.scene, assign_representative_triangles(soup.scene), vss.bounds(), leaf_pairs,
                               leaf.vf, leaf.ee, counts, &separation);

  for (const CcdSets* s : {&a, &l, &b}) {
    EXPECT_TRUE(sorted_unique(s->vf));
    EXPECT_TRUE(sorted_unique(s->ee));
    for (const auto& c : s->vf) ASSERT_FALSE(shares_vertex(soup.scene, c));
    for (const auto& c : s->ee) ASSERT_FALSE(shares_vertex(soup.scene, c));
    for (const auto& c : s->ee) ASSERT_LT(c.edge_a, c.edge_b);
  }
  EXPECT_TRUE(includes(a.vf, leaf.vf)) << "VSS misses a VF pair of overlapping leaves";
  EXPECT_TRUE(includes(a.ee, leaf.ee)) << "VSS misses an EE pair of overlapping leaves";
  EXPECT_TRUE(includes(b.vf, a.vf));
  EXPECT_TRUE(includes(b.ee, a.ee));
  EXPECT_EQ(l.vf.size(), b.vf.size());
  EXPECT_TRUE(l.vf == b.vf);
  EXPECT_TRUE(l.ee == b.ee);
  EXPECT_GT(leaf.vf.size() + leaf.ee.size(), 0u);  // the scenes do have candidates
  EXPECT_GT(vss.stats().triangles_subdivided, 0u);
  EXPECT_EQ(largest.stats().triangles_subdivided, 0u);
  EXPECT_LE(vss.stats().triangle_pairs + vss.stats().duplicate_root_pair_tests, vss.stats().tests_after_control_bits);
  // Every test is counted once: its roots' boxes apart, or one rule, or past the rules.
  const BroadPhaseStats& s = vss.stats();
  EXPECT_EQ(s.tests, s.culled_by_boxes + s.same_root_tests + s.removed_by_time_slots + s.removed_by_control_bits +
                         s.removed_by_extended_control_bits + s.tests_after_control_bits);
  EXPECT_GT(s.culled_by_boxes, 0u);
  EXPECT_EQ(s.tests_after_control_bits - s.culled_by_dop, s.triangle_pairs + s.duplicate_root_pair_tests);
}

TEST(VirtualSubdivisionGrid, CcdContainsLeafOracleOnUnevenMovingSoups) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const Soup soup = random_soup(seed, 300, true);
    check_ccd_against_oracles(soup, BroadPhaseSettings{});
  }
}

// Each cell is swept along y: its leaves ordered by their root's lower y,
// each tested against those after it up to the first whose lower y passes
// its upper y. Boxes that touch in y (one's upper y the other's lower y) or
// start at the same y still meet, so no test of these three triangles, which
// meet in x and z, is counted as culled by the boxes.
TEST(VirtualSubdivisionGrid, CellsSweptAlongYTestBoxesThatTouchOrTieInY) {
  const std::vector<Triangle> tris = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
  std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {0, 0.25, 1}};
  const Scene rising({make_object("rising", 3, {{0, 1, 2}})});
  const float top = float_box_of(compute_primitive_bounds(rising, x, x, 0).triangles[0]).hi[1];
  const double y = static_cast<double>(top) + 1e-12;  // the flat ones' lower y rounds down to `top`
  for (const Vec3& p : {Vec3{0, y, 0}, Vec3{1, y, 0}, Vec3{0, y, 1}}) x.push_back(p);
  for (const Vec3& p : {Vec3{0.1, y, 0.1}, Vec3{1, y, 0.2}, Vec3{0.2, y, 1}}) x.push_back(p);
  Soup soup{Scene({make_object("touching", 9, tris)}), x, x};
  const PrimitiveBounds bounds = compute_primitive_bounds(soup.scene, x, x, 0);
  ASSERT_EQ(float_box_of(bounds.triangles[0]).hi[1], float_box_of(bounds.triangles[1]).lo[1]);
  ASSERT_EQ(float_box_of(bounds.triangles[1]).lo[1], float_box_of(bounds.triangles[2]).lo[1]);

  VirtualSubdivisionGrid largest(false);
  BruteForceBroadPhase brute;
  largest.build(soup.scene, {});
  brute.build(soup.scene, {});
  CcdSets l, b;
  largest.detect_ccd(soup.x_t0, soup.x_t1, l.vf, l.ee);
  brute.detect_ccd(soup.x_t0, soup.x_t1, b.vf, b.ee);
  EXPECT_TRUE(l.vf == b.vf);
  EXPECT_TRUE(l.ee == b.ee);
  const BroadPhaseStats& s = largest.stats();
  EXPECT_GE(s.tests, 3u);
  EXPECT_EQ(s.culled_by_boxes, 0u);
  EXPECT_EQ(s.tests, s.same_root_tests + s.removed_by_time_slots + s.removed_by_control_bits +
                         s.removed_by_extended_control_bits + s.tests_after_control_bits);
}

TEST(VirtualSubdivisionGrid, FastMoversForceTimeHalving) {
  const Soup soup = random_soup(9, 300, true);
  VirtualSubdivisionGrid vss;
  vss.build(soup.scene, {});
  CcdSets s;
  vss.detect_ccd(soup.x_t0, soup.x_t1, s.vf, s.ee);
  EXPECT_GT(vss.stats().time_halvings, 0u);
  check_ccd_against_oracles(soup, BroadPhaseSettings{});
}

TEST(VirtualSubdivisionGrid, CcdWithThicknessContainsLeafOracle) {
  BroadPhaseSettings settings;
  settings.thickness = 0.05;
  check_ccd_against_oracles(random_soup(4, 250, true), settings);
}

TEST(VirtualSubdivisionGrid, StaticContainsLeafOracleAndLargestGridEqualsBruteForce) {
  for (unsigned seed : {5u, 6u}) {
    const Soup soup = random_soup(seed, 400, false);
    VirtualSubdivisionGrid vss(true), largest(false);
    BruteForceBroadPhase brute;
    for (BroadPhase* p : std::initializer_list<BroadPhase*>{&vss, &largest, &brute}) p->build(soup.scene, {});
    std::vector<TrianglePair> a, l, b;
    vss.detect_static(soup.x_t0, a);
    largest.detect_static(soup.x_t0, l);
    brute.detect_static(soup.x_t0, b);
    const std::vector<TrianglePair> leaf = brute_force_leaf_triangle_pairs(vss.leaves(), vss.bounds().triangles);
    EXPECT_TRUE(sorted_unique(a));
    EXPECT_TRUE(includes(a, leaf));
    EXPECT_TRUE(includes(b, a));
    EXPECT_TRUE(l == b);
    EXPECT_GT(leaf.size(), 0u);
    EXPECT_LT(a.size(), b.size()) << "subdivision should cull some root pairs";
  }
}

TEST(VirtualSubdivisionGrid, ResultsDoNotDependOnThreadCount) {
  const Soup soup = random_soup(8, 400, true);
  BroadPhaseSettings one, two;
  one.threads = 1;
  two.threads = 2;
  VirtualSubdivisionGrid a, b;
  a.build(soup.scene, one);
  b.build(soup.scene, two);
  CcdSets sa, sb;
  a.detect_ccd(soup.x_t0, soup.x_t1, sa.vf, sa.ee);
  b.detect_ccd(soup.x_t0, soup.x_t1, sb.vf, sb.ee);
  EXPECT_TRUE(sa.vf == sb.vf);
  EXPECT_TRUE(sa.ee == sb.ee);
  EXPECT_EQ(a.stats().tests, b.stats().tests);
  EXPECT_EQ(a.stats().duplicate_root_pair_tests, b.stats().duplicate_root_pair_tests);
  EXPECT_EQ(a.stats().removed_by_extended_control_bits, b.stats().removed_by_extended_control_bits);
}

TEST(VirtualSubdivisionGrid, CountingCulledDuplicatesChangesOnlyThatCount) {
  const Soup soup = random_soup(8, 400, true);
  BroadPhaseSettings counted;
  counted.count_culled_duplicates = true;
  VirtualSubdivisionGrid plain, counting;
  plain.build(soup.scene, BroadPhaseSettings{});
  counting.build(soup.scene, counted);
  CcdSets sa, sb;
  plain.detect_ccd(soup.x_t0, soup.x_t1, sa.vf, sa.ee);
  counting.detect_ccd(soup.x_t0, soup.x_t1, sb.vf, sb.ee);
  EXPECT_TRUE(sa.vf == sb.vf);
  EXPECT_TRUE(sa.ee == sb.ee);
  EXPECT_EQ(plain.stats().culled_by_dop, counting.stats().culled_by_dop);
  EXPECT_EQ(plain.stats().duplicate_root_pair_tests, counting.stats().duplicate_root_pair_tests);
  EXPECT_EQ(plain.stats().duplicate_culled_tests, 0u);
  EXPECT_GT(counting.stats().duplicate_culled_tests, 0u) << "the case must repeat culled root pairs";
  EXPECT_LT(counting.stats().duplicate_culled_tests, counting.stats().culled_by_dop);
  EXPECT_LT(plain.stats().memory_bytes, counting.stats().memory_bytes);
}

TEST(VirtualSubdivisionGrid, RejectsPositionsOfTheWrongSize) {
  const Soup soup = random_soup(1, 10, false);
  VirtualSubdivisionGrid vss;
  std::vector<TrianglePair> pairs;
  EXPECT_THROW(vss.detect_static(soup.x_t0, pairs), UsageError);
  vss.build(soup.scene, {});
  std::vector<Vec3> short_positions(soup.x_t0.begin(), soup.x_t0.end() - 1);
  EXPECT_THROW(vss.detect_static(short_positions, pairs), UsageError);
  BroadPhaseSettings bad;
  bad.lambda = 0.9;
  EXPECT_THROW(vss.build(soup.scene, bad), UsageError);
}

Soup load_pair(const std::string& t0, const std::string& t1) {
  const std::string dir = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/";
  bench::PlyMesh a = bench::read_binary_ply(dir + t0);
  bench::PlyMesh b = bench::read_binary_ply(dir + t1);
  const Index n = static_cast<Index>(a.vertices.size());
  return Soup{Scene({make_object(t0, n, a.triangles)}), a.vertices, b.vertices};
}

TEST(VirtualSubdivisionGrid, ThickClothStepMatchesOracles) {
  const Soup soup = load_pair("thick-cloth/t0.ply", "thick-cloth/t1.ply");
  VirtualSubdivisionGrid vss(true), largest(false);
  BruteForceBroadPhase brute;
  for (BroadPhase* p : std::initializer_list<BroadPhase*>{&vss, &largest, &brute}) p->build(soup.scene, {});
  CcdSets a, l, b, leaf;
  vss.detect_ccd(soup.x_t0, soup.x_t1, a.vf, a.ee);
  largest.detect_ccd(soup.x_t0, soup.x_t1, l.vf, l.ee);
  brute.detect_ccd(soup.x_t0, soup.x_t1, b.vf, b.ee);
  FeatureCounts counts;
  representative_feature_pairs(soup.scene, assign_representative_triangles(soup.scene), vss.bounds(),
                               brute_force_leaf_triangle_pairs(vss.leaves(), vss.bounds().triangles), leaf.vf,
                               leaf.ee, counts);
  EXPECT_TRUE(includes(a.vf, leaf.vf));
  EXPECT_TRUE(includes(a.ee, leaf.ee));
  EXPECT_TRUE(includes(b.vf, a.vf));
  EXPECT_TRUE(includes(b.ee, a.ee));
  EXPECT_TRUE(l.vf == b.vf);
  EXPECT_TRUE(l.ee == b.ee);
  EXPECT_GT(a.vf.size(), 0u);
}

TEST(VirtualSubdivisionGrid, StaticMeshesMatchOracles) {
  for (const char* name : {"bunny.ply", "cube.ply", "two-cubes-far.ply", "two-cubes-close.ply",
                           "two-cubes-intersecting.ply"}) {
    const Soup soup = load_pair(name, name);
    VirtualSubdivisionGrid vss(true), largest(false);
    BruteForceBroadPhase brute;
    for (BroadPhase* p : std::initializer_list<BroadPhase*>{&vss, &largest, &brute}) p->build(soup.scene, {});
    std::vector<TrianglePair> a, l, b;
    vss.detect_static(soup.x_t0, a);
    largest.detect_static(soup.x_t0, l);
    brute.detect_static(soup.x_t0, b);
    const std::vector<TrianglePair> leaf = brute_force_leaf_triangle_pairs(vss.leaves(), vss.bounds().triangles);
    EXPECT_TRUE(includes(a, leaf)) << name;
    EXPECT_TRUE(includes(b, a)) << name;
    EXPECT_TRUE(l == b) << name;
  }
}

// The box grid returns T_root exactly: brute force's sets, static and CCD.
void expect_box_grid_equals_brute_force(const Soup& soup, const BroadPhaseSettings& settings, const std::string& what,
                                        BroadPhaseMethod method = BroadPhaseMethod::kBoxGrid) {
  std::unique_ptr<BroadPhase> phase = make_broad_phase(method);
  BroadPhase& grid = *phase;
  BruteForceBroadPhase brute;
  grid.build(soup.scene, settings);
  brute.build(soup.scene, settings);
  std::vector<TrianglePair> g, b;
  grid.detect_static(soup.x_t0, g);
  brute.detect_static(soup.x_t0, b);
  EXPECT_TRUE(sorted_unique(g)) << what;
  EXPECT_TRUE(g == b) << what << ": static, box grid " << g.size() << " pairs, brute force " << b.size();
  EXPECT_EQ(grid.stats().triangle_pairs, b.size()) << what;
  EXPECT_LE(grid.stats().registrations, 16 * soup.scene.triangle_count() + 64) << what;
  CcdSets gc, bc;
  grid.detect_ccd(soup.x_t0, soup.x_t1, gc.vf, gc.ee);
  brute.detect_ccd(soup.x_t0, soup.x_t1, bc.vf, bc.ee);
  EXPECT_TRUE(gc.vf == bc.vf) << what << ": CCD VF, box grid " << gc.vf.size() << ", brute force " << bc.vf.size();
  EXPECT_TRUE(gc.ee == bc.ee) << what << ": CCD EE, box grid " << gc.ee.size() << ", brute force " << bc.ee.size();
  EXPECT_GT(b.size(), 0u) << what;
}

TEST(BoxGrid, EqualsBruteForceOnUnevenSoups) {
  for (unsigned seed : {11u, 12u, 13u}) {
    expect_box_grid_equals_brute_force(random_soup(seed, 400, true), {}, "soup " + std::to_string(seed));
    BroadPhaseSettings thick;
    thick.thickness = 0.05;
    expect_box_grid_equals_brute_force(random_soup(seed, 300, true), thick, "thick soup " + std::to_string(seed));
  }
}

TEST(BoxGrid, OneHugeTriangleAmongTinyOnesKeepsTheGridBounded) {
  // Many tiny triangles spread over a large box and one triangle as large as
  // the scene: the mean size asks for fine cells, which the huge triangle
  // would register in by the million; the grid coarsens instead.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 100);
  std::vector<Vec3> x;
  std::vector<Triangle> tris;
  for (Index k = 0; k < 3000; ++k) {
    const Vec3 c{u(rng), u(rng), u(rng)};
    x.insert(x.end(), {c, c + Vec3{0.01, 0, 0}, c + Vec3{0, 0.01, 0.005}});
    tris.push_back({3 * k, 3 * k + 1, 3 * k + 2});
  }
  const Index base = static_cast<Index>(x.size());
  x.insert(x.end(), {Vec3{0, 0, 0}, Vec3{100, 0, 100}, Vec3{0, 100, 100}});
  tris.push_back({base, base + 1, base + 2});
  Soup soup{Scene({make_object("huge", static_cast<Index>(x.size()), tris)}), x, x};
  expect_box_grid_equals_brute_force(soup, {}, "one huge triangle");
}

TEST(BoxGrid, BoxesFinerThanTheQuantisationGiveBruteForceSets) {
  // Two triangles a million units apart stretch the scene, so one step of
  // the quantised boxes is about 30 units; a cluster of tiny triangles
  // (0.01 across, many touching exactly along x) all quantise to the same
  // box. No overlapping pair may be lost, and those that only share a
  // quantum are culled by the DOP test.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 0.2);
  std::vector<Vec3> x{{-5e5, -5e5, -5e5}, {-5e5 + 1, -5e5, -5e5}, {-5e5, -5e5 + 1, -5e5},
                      {5e5, 5e5, 5e5},    {5e5 - 1, 5e5, 5e5},    {5e5, 5e5 - 1, 5e5}};
  std::vector<Triangle> tris{{0, 1, 2}, {3, 4, 5}};
  for (Index k = 0; k < 1500; ++k) {
    const Index base = static_cast<Index>(x.size());
    if (k % 3 == 0) {  // a row whose boxes touch: x from 0.01·k to 0.01·(k + 1)
      const double x0 = 0.01 * (k / 3), y = 1000.0 + u(rng), z = -2000.0 + u(rng);
      x.insert(x.end(), {Vec3{x0, y, z}, Vec3{x0 + 0.01, y + 0.003, z}, Vec3{x0 + 0.005, y, z + 0.004}});
    } else {
      const Vec3 c{u(rng), 1000.0 + u(rng), -2000.0 + u(rng)};
      x.insert(x.end(), {c, c + Vec3{0.01, 0.002, 0}, c + Vec3{0, 0.01, 0.006}});
    }
    tris.push_back({base, base + 1, base + 2});
  }
  Soup soup{Scene({make_object("cluster", static_cast<Index>(x.size()), tris)}), x, x};
  expect_box_grid_equals_brute_force(soup, {}, "tiny cluster in a huge scene");
}

// Box grids a (one thread) and b (two), built on soup: the same static pairs
// on both frames, the same CCD sets and the same number of box tests.
void expect_same_for_one_and_two_threads(const Soup& soup, BoxGridBroadPhase& a, BoxGridBroadPhase& b) {
  BroadPhaseSettings one, two;
  one.threads = 1;
  two.threads = 2;
  a.build(soup.scene, one);
  b.build(soup.scene, two);
  for (const std::vector<Vec3>* frame : {&soup.x_t0, &soup.x_t1}) {
    std::vector<TrianglePair> pa, pb;
    a.detect_static(*frame, pa);
    b.detect_static(*frame, pb);
    EXPECT_TRUE(pa == pb);
  }
  CcdSets sa, sb;
  a.detect_ccd(soup.x_t0, soup.x_t1, sa.vf, sa.ee);
  b.detect_ccd(soup.x_t0, soup.x_t1, sb.vf, sb.ee);
  EXPECT_TRUE(sa.vf == sb.vf);
  EXPECT_TRUE(sa.ee == sb.ee);
  EXPECT_EQ(a.stats().tests, b.stats().tests);
}

TEST(BoxGrid, ResultsDoNotDependOnThreadCountAndReuseAcrossFrames) {
  const Soup soup = random_soup(8, 400, true);
  BoxGridBroadPhase a, b;
  expect_same_for_one_and_two_threads(soup, a, b);
  // The same instance on the step's end frame, then again on its start: the
  // arrays kept from the last detection must not leak into the next.
  std::vector<TrianglePair> first, end_frame, again;
  a.detect_static(soup.x_t0, first);
  a.detect_static(soup.x_t1, end_frame);
  a.detect_static(soup.x_t0, again);
  BoxGridBroadPhase fresh;
  fresh.build(soup.scene, {});
  std::vector<TrianglePair> fresh_end;
  fresh.detect_static(soup.x_t1, fresh_end);
  EXPECT_TRUE(first == again);
  EXPECT_TRUE(end_frame == fresh_end);
  EXPECT_FALSE(first == end_frame) << "the two frames should differ";
}

// Enough small triangles in random order that the grid queries them in its
// spatial order (over 16,384, few near their predecessor): the pairs still
// equal brute force's, sorted, for every thread count and frame.
TEST(BoxGrid, SpatialQueryOrderGivesBruteForceSetsForEveryThreadCount) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  auto jitter = [&](double size) { return Vec3{size * u(rng), size * u(rng), size * u(rng)}; };
  Soup soup;
  std::vector<Triangle> shuffled;
  for (Index k = 0; k < 20000; ++k) {
    const Vec3 c = Vec3{15, 15, 15} + jitter(30);
    const double size = u(rng) < 0.4 ? 0.4 : 2.0;
    soup.x_t0.insert(soup.x_t0.end(), {c, c + jitter(size), c + jitter(size)});
    shuffled.push_back({3 * k, 3 * k + 1, 3 * k + 2});
  }
  for (const Vec3& p : soup.x_t0) soup.x_t1.push_back(p + jitter(0.2));
  soup.scene = Scene({make_object("shuffled", static_cast<Index>(soup.x_t0.size()), shuffled)});
  expect_box_grid_equals_brute_force(soup, {}, "shuffled soup");
  BoxGridBroadPhase a, b;
  expect_same_for_one_and_two_threads(soup, a, b);
}

// A side × side grid of vertices 1 apart, each moved by jitter·u along x and
// y and bump·u along z (u uniform in [-0.5, 0.5)), two triangles per quad,
// appended to x and tris.
void add_sheet(std::mt19937& rng, Index side, double jitter, double bump, std::vector<Vec3>& x,
               std::vector<Triangle>& tris) {
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  const Index base = static_cast<Index>(x.size());
  for (Index j = 0; j < side; ++j)
    for (Index i = 0; i < side; ++i) x.push_back({double(i) + jitter * u(rng), double(j) + jitter * u(rng), bump * u(rng)});
  for (Index j = 0; j + 1 < side; ++j) {
    for (Index i = 0; i + 1 < side; ++i) {
      const Index v = base + j * side + i;
      tris.push_back({v, v + 1, v + side});
      tris.push_back({v + 1, v + side + 1, v + side});
    }
  }
}

// Triangles that share vertices skip the DOP test (their DOPs always
// overlap): a crumpled sheet, a fan of 300 triangles around one vertex, a
// duplicated face and a triangle with a repeated vertex id still give brute
// force's sets, for every thread count, and after the same instance was
// built on another scene (its neighbour marks are not carried over).
TEST(BoxGrid, TrianglesSharingVerticesGiveBruteForceSets) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  Soup soup;
  std::vector<Triangle> tris;
  add_sheet(rng, 40, 0.3, 0.8, soup.x_t0, tris);
  const Index centre = static_cast<Index>(soup.x_t0.size());
  soup.x_t0.push_back({20, 20, 0});
  const Index fan = 300;
  for (Index k = 0; k < fan; ++k) {
    const double angle = 6.283185307179586 * k / fan;
    soup.x_t0.push_back({20 + 3 * std::cos(angle), 20 + 3 * std::sin(angle), u(rng)});
  }
  for (Index k = 0; k < fan; ++k) tris.push_back({centre, centre + 1 + k, centre + 1 + (k + 1) % fan});
  tris.push_back(tris[10]);
  tris.push_back({tris[50][0], tris[50][0], tris[50][2]});
  for (const Vec3& p : soup.x_t0) soup.x_t1.push_back(p + Vec3{0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng)});
  soup.scene = Scene({make_object("sheet and fan", static_cast<Index>(soup.x_t0.size()), tris)});
  expect_box_grid_equals_brute_force(soup, {}, "sheet and fan");
  BoxGridBroadPhase a, b;
  expect_same_for_one_and_two_threads(random_soup(4, 300, true), a, b);
  expect_same_for_one_and_two_threads(soup, a, b);
  BruteForceBroadPhase brute;
  brute.build(soup.scene, {});
  std::vector<TrianglePair> ours, theirs;
  a.detect_static(soup.x_t1, ours);
  brute.detect_static(soup.x_t1, theirs);
  EXPECT_TRUE(ours == theirs) << "box grid " << ours.size() << " pairs, brute force " << theirs.size();
}

// detect_static_leaving_out gives brute force's set without the pairs that
// share a flagged vertex (whatever the flags, given or filled by its
// callback), for every thread count and in the spatial query order: a
// crumpled sheet with a fan and odd faces, and the same sheet's triangles
// shuffled (over 16,384 of them, out of spatial order).
TEST(BoxGrid, LeavingOutApartVerticesGivesBruteForceSetsWithoutTheirPairs) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  auto sheet = [&](Index side) {
    Soup soup;
    std::vector<Triangle> tris;
    add_sheet(rng, side, 0.3, 2.0, soup.x_t0, tris);
    tris.push_back(tris[10]);
    tris.push_back({tris[50][0], tris[50][0], tris[50][2]});
    soup.x_t1 = soup.x_t0;
    soup.scene = Scene({make_object("sheet", static_cast<Index>(soup.x_t0.size()), tris)});
    return soup;
  };
  const Soup small = sheet(40);
  Soup shuffled = sheet(95);
  std::vector<Triangle> tris = shuffled.scene.triangles();
  std::shuffle(tris.begin(), tris.end(), rng);
  shuffled.scene = Scene({make_object("shuffled sheet", static_cast<Index>(shuffled.x_t0.size()), tris)});
  for (const Soup* soup : {&small, static_cast<const Soup*>(&shuffled)}) {
    BruteForceBroadPhase brute;
    brute.build(soup->scene, {});
    std::vector<TrianglePair> all;
    brute.detect_static(soup->x_t0, all);
    for (const double share : {0.0, 0.3, 1.0}) {
      std::vector<unsigned char> apart(soup->x_t0.size());
      for (unsigned char& flag : apart) flag = u(rng) < share;
      std::vector<TrianglePair> expected;
      for (const TrianglePair& p : all) {
        bool shares_apart = false;
        for (const Index va : soup->scene.triangles()[p.a])
          for (const Index vb : soup->scene.triangles()[p.b]) shares_apart = shares_apart || (va == vb && apart[va]);
        if (!shares_apart) expected.push_back(p);
      }
      for (const auto [threads, method] : {std::pair{1u, BroadPhaseMethod::kBoxGrid},
                                           std::pair{2u, BroadPhaseMethod::kBoxGrid},
                                           std::pair{1u, BroadPhaseMethod::kSweepAndPrune},
                                           std::pair{2u, BroadPhaseMethod::kSweepAndPrune}}) {
        BroadPhaseSettings settings;
        settings.threads = threads;
        std::unique_ptr<BroadPhase> phase = make_broad_phase(method);
        BroadPhase& grid = *phase;
        grid.build(soup->scene, settings);
        std::vector<TrianglePair> pairs;
        grid.detect_static_leaving_out(soup->x_t0, apart, pairs);
        EXPECT_TRUE(pairs == expected) << broad_phase_method_name(method) << ", " << soup->scene.objects()[0].name
                                       << ", share " << share << ", threads " << threads << ": " << pairs.size()
                                       << " pairs, expected " << expected.size();
        EXPECT_EQ(grid.stats().left_out_apart, all.size() - expected.size());
        // The flags filled by the callback, alongside the registration.
        std::vector<unsigned char> filled(apart.size(), 0);
        int calls = 0;
        grid.detect_static_leaving_out(soup->x_t0, filled, pairs, [&] {
          ++calls;
          filled = apart;
        });
        EXPECT_EQ(calls, 1);
        EXPECT_TRUE(pairs == expected) << "flags filled alongside the registration";
        // The plain detection after it leaves nothing out.
        grid.detect_static(soup->x_t0, pairs);
        EXPECT_TRUE(pairs == all);
      }
      if (share == 1.0) EXPECT_LT(expected.size(), all.size() / 4);
    }
  }
}

TEST(SweepAndPrune, EqualsBruteForceOnUnevenSoupsAndStackedBoxes) {
  for (unsigned seed : {21u, 22u}) {
    for (unsigned threads : {1u, 2u}) {
      BroadPhaseSettings settings;
      settings.threads = threads;
      expect_box_grid_equals_brute_force(random_soup(seed, 400, true), settings, "soup " + std::to_string(seed),
                                         BroadPhaseMethod::kSweepAndPrune);
      settings.thickness = 0.05;
      expect_box_grid_equals_brute_force(random_soup(seed, 300, true), settings, "thick soup " + std::to_string(seed),
                                         BroadPhaseMethod::kSweepAndPrune);
    }
  }
  // Boxes that start together along every axis (ties in the sort): a
  // stack of equal triangles, some shifted along one axis only.
  std::vector<Vec3> x;
  std::vector<Triangle> tris;
  for (Index k = 0; k < 60; ++k) {
    const double shift = (k % 3) * 0.5;
    x.insert(x.end(), {Vec3{0, 0, shift}, Vec3{1, 0, shift}, Vec3{0, 1, shift + 0.25}});
    tris.push_back({3 * k, 3 * k + 1, 3 * k + 2});
  }
  Soup stack{Scene({make_object("stack", static_cast<Index>(x.size()), tris)}), x, x};
  expect_box_grid_equals_brute_force(stack, {}, "stack", BroadPhaseMethod::kSweepAndPrune);
}

// Over 32,768 triangles two threads register them in two ranges, each with
// its own cursors: the same pairs, tests and cell use as one thread (whose
// sets equal brute force's above), and leaving out apart vertices too.
TEST(BoxGrid, RegistrationInRangesGivesTheOneThreadArrays) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0, 1);
  Soup soup;
  std::vector<Triangle> tris;
  add_sheet(rng, 140, 0.3, 3.0, soup.x_t0, tris);  // 38,642 triangles
  soup.x_t1 = soup.x_t0;
  soup.scene = Scene({make_object("large sheet", static_cast<Index>(soup.x_t0.size()), tris)});
  std::vector<unsigned char> apart(soup.x_t0.size());
  for (unsigned char& flag : apart) flag = u(rng) < 0.5;
  BroadPhaseSettings one, two;
  one.threads = 1;
  two.threads = 2;
  BoxGridBroadPhase a, b;
  a.build(soup.scene, one);
  b.build(soup.scene, two);
  std::vector<TrianglePair> pa, pb;
  a.detect_static(soup.x_t0, pa);
  b.detect_static(soup.x_t0, pb);
  EXPECT_TRUE(pa == pb) << pa.size() << " pairs on one thread, " << pb.size() << " on two";
  EXPECT_EQ(a.stats().tests, b.stats().tests);
  EXPECT_EQ(a.stats().cells_used, b.stats().cells_used);
  EXPECT_EQ(a.stats().registrations, b.stats().registrations);
  EXPECT_GT(pa.size(), tris.size());
  a.detect_static_leaving_out(soup.x_t0, apart, pa);
  b.detect_static_leaving_out(soup.x_t0, apart, pb);
  EXPECT_TRUE(pa == pb);
  EXPECT_EQ(a.stats().left_out_apart, b.stats().left_out_apart);
}

TEST(BoxGrid, RejectsPositionsOfTheWrongSize) {
  const Soup soup = random_soup(1, 10, false);
  BoxGridBroadPhase grid;
  std::vector<TrianglePair> pairs;
  EXPECT_THROW(grid.detect_static(soup.x_t0, pairs), UsageError);
  grid.build(soup.scene, {});
  std::vector<Vec3> short_positions(soup.x_t0.begin(), soup.x_t0.end() - 1);
  EXPECT_THROW(grid.detect_static(short_positions, pairs), UsageError);
  BroadPhaseSettings bad;
  bad.thickness = -1;
  EXPECT_THROW(grid.build(soup.scene, bad), UsageError);
}

TEST(BoxGrid, EqualsBruteForceOnReferenceMeshes) {
  for (const BroadPhaseMethod method : {BroadPhaseMethod::kBoxGrid, BroadPhaseMethod::kSweepAndPrune}) {
    expect_box_grid_equals_brute_force(load_pair("thick-cloth/t0.ply", "thick-cloth/t1.ply"), {}, "thick cloth",
                                       method);
    for (const char* name : {"bunny.ply", "two-cubes-close.ply", "two-cubes-intersecting.ply"})
      expect_box_grid_equals_brute_force(load_pair(name, name), {}, name, method);
  }
}

}  // namespace
}  // namespace snag
