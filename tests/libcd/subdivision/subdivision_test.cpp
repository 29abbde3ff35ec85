// Tests for subdivision/: Loop children tile their parent with exact dyadic
// barycentrics, time halving partitions the slot, and the level loop leaves
// only triangles that meet the cell rule.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "libcd/grid/cell_size.hpp"
#include "libcd/subdivision/virtual_subdivision.hpp"

namespace snag {
namespace {

// Twice the signed area of a virtual triangle in barycentric numerator space.
std::int64_t doubled_area(const VirtualTriangle& t) {
  const std::int64_t ux = std::int64_t(t.bary[1][0]) - t.bary[0][0], uy = std::int64_t(t.bary[1][1]) - t.bary[0][1];
  const std::int64_t vx = std::int64_t(t.bary[2][0]) - t.bary[0][0], vy = std::int64_t(t.bary[2][1]) - t.bary[0][1];
  return ux * vy - uy * vx;
}

bool contains(const VirtualTriangle& t, std::int64_t px, std::int64_t py, int depth) {
  // p given at `depth` >= t.depth; scale t's numerators up.
  const int shift = depth - static_cast<int>(t.depth);
  std::int64_t sign = 0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const std::int64_t ax = std::int64_t(t.bary[i][0]) << shift, ay = std::int64_t(t.bary[i][1]) << shift;
    const std::int64_t bx = std::int64_t(t.bary[j][0]) << shift, by = std::int64_t(t.bary[j][1]) << shift;
    const std::int64_t c = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
    if (c != 0) {
      if (sign != 0 && (c > 0) != (sign > 0)) return false;
      sign = c;
    }
  }
  return true;
}

TEST(LoopSubdivision, ChildrenTileTheParentExactly) {
  VirtualTriangle parent = virtual_root(4);
  VirtualTriangle level[4];
  loop_children(parent, level);
  VirtualTriangle grand[4];
  loop_children(level[3], grand);  // the middle child, reversed orientation
  for (const VirtualTriangle* family : {level, grand}) {
    const VirtualTriangle& p = family == level ? parent : level[3];
    std::int64_t sum = 0;
    for (int q = 0; q < 4; ++q) {
      EXPECT_EQ(family[q].depth, p.depth + 1);
      EXPECT_EQ(family[q].root, 4u);
      sum += doubled_area(family[q]);
      EXPECT_EQ(doubled_area(family[q]), doubled_area(p));  // four equal children, same orientation
    }
    EXPECT_EQ(sum, doubled_area(p) * 4);  // numerators double: areas scale by 4
  }
  // Every lattice point of the parent at depth 4 lies in some child.
  const int depth = 4;
  const std::int64_t full = 1 << depth;
  for (std::int64_t u = 0; u <= full; ++u)
    for (std::int64_t v = 0; u + v <= full; ++v) {
      bool in_child = false;
      for (int q = 0; q < 4; ++q) in_child = in_child || contains(level[q], u, v, depth);
      EXPECT_TRUE(in_child) << u << "," << v;
    }
}

TEST(LoopSubdivision, InterpolatedCornersAreExactMidpoints) {
  const Vec3 p[3] = {{0, 0, 0}, {8, 0, 0}, {0, 8, 4}};
  VirtualTriangle child[4];
  loop_children(virtual_root(0), child);
  EXPECT_EQ(virtual_corner(child[0], 0, p), p[0]);
  EXPECT_EQ(virtual_corner(child[0], 1, p), (Vec3{4, 0, 0}));
  EXPECT_EQ(virtual_corner(child[0], 2, p), (Vec3{0, 4, 2}));
  EXPECT_EQ(virtual_corner(child[3], 0, p), (Vec3{4, 4, 2}));
}

TEST(TimeHalving, HalvesPartitionTheSlotAndNestWithTheParent) {
  VirtualTriangle half[2], quarter[2];
  halve_time(virtual_root(1), half);
  halve_time(half[1], quarter);
  EXPECT_EQ(slot_start(half[0]), 0.0);
  EXPECT_EQ(slot_end(half[0]), 0.5);
  EXPECT_EQ(slot_start(half[1]), 0.5);
  EXPECT_EQ(slot_start(quarter[1]), 0.75);
  EXPECT_EQ(slot_end(quarter[1]), 1.0);
  EXPECT_TRUE(slots_nested(virtual_root(0), quarter[0]));
  EXPECT_TRUE(slots_nested(half[1], quarter[0]));
  EXPECT_FALSE(slots_nested(half[0], quarter[0]));  // [0,.5] and [.5,.75] touch only
  EXPECT_FALSE(slots_nested(half[0], half[1]));
}

TEST(VirtualSubdivision, LeavesMeetTheCellRuleAndCoverTheirRoots) {
  // One large triangle, one small one, and a fast mover that forces halving.
  const std::vector<Vec3> x_t0 = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {1, 1, 1}, {1.2, 1, 1}, {1, 1.2, 1},
                                  {5, 5, 5}, {5.1, 5, 5}, {5, 5.1, 5}};
  std::vector<Vec3> x_t1 = x_t0;
  for (int i = 6; i < 9; ++i) x_t1[i] = x_t0[i] + Vec3{-6, 0, 0};
  const Scene scene({make_object("soup", 9, {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}})});
  const GridSpec grid = make_grid({-7, -1, -1}, {11, 11, 6}, 0.9);
  std::vector<SubdivisionLevelCounts> levels;
  const std::vector<Leaf> leaves = subdivide_virtually(scene, x_t0, x_t1, grid, 0.0, 16, 12, levels);
  ASSERT_GT(levels.size(), 3u);
  std::size_t halved = 0, accepted = 0;
  for (const auto& l : levels) halved += l.halved, accepted += l.accepted;
  EXPECT_GT(halved, 0u);
  EXPECT_EQ(accepted, leaves.size());
  double area[3] = {0, 0, 0};
  for (const Leaf& leaf : leaves) {
    for (int a = 0; a < 3; ++a) {
      const int lo = (&leaf.cells.block.lo.x)[a], hi = (&leaf.cells.block.hi.x)[a];
      EXPECT_LE(hi - lo, 1) << "a leaf overlaps more than 2 cells along an axis";
    }
    EXPECT_TRUE(block_contains(leaf.cells.block, leaf.cells.home));
    if (leaf.triangle.slot_index == 0) area[leaf.triangle.root] += std::ldexp(1.0, -2 * int(leaf.triangle.depth));
  }
  EXPECT_DOUBLE_EQ(area[0], 1.0);  // the children of slot 0 tile the root
  EXPECT_DOUBLE_EQ(area[1], 1.0);
  // Leaves of one root in one level are adjacent in the list.
  for (std::size_t i = 2; i < leaves.size(); ++i) {
    const auto& a = leaves[i - 2].triangle;
    const auto& c = leaves[i].triangle;
    if (a.root == c.root && a.depth == c.depth && a.slot_depth == c.slot_depth && a.slot_index == c.slot_index) {
      EXPECT_EQ(leaves[i - 1].triangle.root, a.root);
    }
  }
}

}  // namespace
}  // namespace snag
