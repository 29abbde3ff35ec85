#include "libcd/subdivision/virtual_subdivision.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_scan.h>

#include "libcd/bounding_volume/bounding_sphere.hpp"
#include "libcd/bounding_volume/primitive_bounds.hpp"

namespace snag {

namespace {

/// A virtual triangle in a level's list, with the slice of the list that holds
/// its siblings (the children of its parent's Loop split; itself otherwise).
struct LevelItem {
  VirtualTriangle triangle;
  std::uint32_t group_first = 0;
  std::uint32_t group_size = 1;
};

/// Per item results of the examining pass.
struct ItemInfo {
  SplitDecision decision = SplitDecision::kAccept;
  CellCoord home;
};

void root_corners(const Scene& scene, const std::vector<Vec3>& x, Index root, Vec3 out[3]) {
  const Triangle& t = scene.triangles()[root];
  for (int i = 0; i < 3; ++i) out[i] = x[t[i]];
}

std::size_t children_of(SplitDecision d) {
  return d == SplitDecision::kSubdivide ? 4 : (d == SplitDecision::kHalveTime ? 2 : 0);
}

bool is_leaf(SplitDecision d) { return d == SplitDecision::kAccept || d == SplitDecision::kAcceptOversized; }

/// Exclusive prefix sum, in parallel; returns the total.
template <class Count>
std::size_t exclusive_scan(std::size_t n, Count count, std::vector<std::size_t>& offsets) {
  offsets.resize(n + 1);
  const std::size_t total = tbb::parallel_scan(
      tbb::blocked_range<std::size_t>(0, n, 4096), std::size_t(0),
      [&](const tbb::blocked_range<std::size_t>& r, std::size_t sum, bool final) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          if (final) offsets[i] = sum;
          sum += count(i);
        }
        return sum;
      },
      [](std::size_t a, std::size_t b) { return a + b; });
  offsets[n] = total;
  return total;
}

}  // namespace

std::vector<Leaf> subdivide_virtually(const Scene& scene, const std::vector<Vec3>& x_t0,
                                      const std::vector<Vec3>& x_t1, const GridSpec& grid, double thickness,
                                      std::uint32_t max_levels, std::uint32_t max_halvings,
                                      std::vector<SubdivisionLevelCounts>& levels) {
  levels.clear();
  std::vector<Leaf> leaves;
  std::vector<LevelItem> items(scene.triangle_count());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, items.size(), 4096), [&](const auto& r) {
    for (std::size_t f = r.begin(); f != r.end(); ++f) {
      items[f].triangle = virtual_root(static_cast<Index>(f));
      items[f].group_first = static_cast<std::uint32_t>(f);
    }
  });
  std::vector<ItemInfo> info;
  std::vector<std::size_t> child_offset, leaf_offset;

  while (!items.empty()) {
    const std::size_t n = items.size();
    info.assign(n, ItemInfo{});
    // Pass 1: bound each item, decide whether it is split, find its home cell.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        const VirtualTriangle& t = items[i].triangle;
        Vec3 p_t0[3], p_t1[3], points[6];
        root_corners(scene, x_t0, t.root, p_t0);
        root_corners(scene, x_t1, t.root, p_t1);
        virtual_swept_points(t, p_t0, p_t1, points);
        const Sphere sphere = sphere_of_points(points, 6);
        info[i].decision = decide_split(t, points, sphere.radius, thickness, grid.cell_size, max_levels, max_halvings);
        info[i].home = grid_cell_of(grid, sphere.centre);
      }
    });
    // Pass 2: where each item's children and leaf go (prefix sums).
    const std::size_t child_total = exclusive_scan(n, [&](std::size_t i) { return children_of(info[i].decision); }, child_offset);
    const std::size_t leaf_total = exclusive_scan(n, [&](std::size_t i) { return std::size_t(is_leaf(info[i].decision)); }, leaf_offset);

    SubdivisionLevelCounts counts;
    counts.triangles = n;
    counts.accepted = leaf_total;
    for (std::size_t i = 0; i < n; ++i) {
      counts.subdivided += info[i].decision == SplitDecision::kSubdivide;
      counts.halved += info[i].decision == SplitDecision::kHalveTime;
      counts.oversized += info[i].decision == SplitDecision::kAcceptOversized;
    }
    levels.push_back(counts);

    // Pass 3: write leaves (DOP, cells, control bits with siblings) and children.
    const std::size_t leaf_base = leaves.size();
    leaves.resize(leaf_base + leaf_total);
    std::vector<LevelItem> next(child_total);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        const LevelItem& item = items[i];
        const SplitDecision d = info[i].decision;
        if (is_leaf(d)) {
          Leaf& leaf = leaves[leaf_base + leaf_offset[i]];
          leaf.triangle = item.triangle;
          Vec3 p_t0[3], p_t1[3], points[6];
          root_corners(scene, x_t0, item.triangle.root, p_t0);
          root_corners(scene, x_t1, item.triangle.root, p_t1);
          virtual_swept_points(item.triangle, p_t0, p_t1, points);
          const Vec3 sources[6] = {p_t0[0], p_t0[1], p_t0[2], p_t1[0], p_t1[1], p_t1[2]};
          leaf.dop = dop_of_points(points, 6, rounding_pad(sources, 6), thickness);
          Vec3 lo, hi;
          dop_box(leaf.dop, lo, hi);
          leaf.cells.block = grid_block_of(grid, lo, hi);
          leaf.cells.home = info[i].home;
          leaf.cells.sibling_count = 0;
          for (std::uint32_t s = item.group_first; s < item.group_first + item.group_size; ++s) {
            if (s != i && is_leaf(info[s].decision)) leaf.cells.sibling_home[leaf.cells.sibling_count++] = info[s].home;
          }
          leaf.cells.control_bits = make_control_bits(leaf.cells);
        } else if (d == SplitDecision::kSubdivide) {
          VirtualTriangle child[4];
          loop_children(item.triangle, child);
          const std::size_t o = child_offset[i];
          for (int q = 0; q < 4; ++q) next[o + q] = {child[q], static_cast<std::uint32_t>(o), 4};
        } else {
          VirtualTriangle child[2];
          halve_time(item.triangle, child);
          const std::size_t o = child_offset[i];
          for (int h = 0; h < 2; ++h) next[o + h] = {child[h], static_cast<std::uint32_t>(o + h), 1};
        }
      }
    });
    items.swap(next);
  }
  return leaves;
}

}  // namespace snag
