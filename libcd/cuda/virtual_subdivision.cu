// Virtual subdivision, level by level, on the GPU: the CUDA twin of
// libcd/subdivision/virtual_subdivision.cpp, with the same SNAG_HD math
// (virtual_triangle.hpp, bounding_sphere.hpp, dop18.hpp, control_bits.hpp).
// Wong, Leach, Zambetta, virtual subdivision chapter, Algorithm 1 and section
// 5.3.2: one thread per triangle per level, a new triangle list per level.
#include "libcd/cuda/virtual_subdivision.cuh"

#include <cub/device/device_scan.cuh>

#include <algorithm>

#include "libcd/bounding_volume/bounding_sphere.hpp"
#include "libcd/bounding_volume/primitive_bounds.hpp"
#include "libcd/cuda/device_scan.cuh"
#include "libcd/cuda/launch.cuh"

namespace snag {
namespace {

using detail::blocks_for;
using detail::exclusive_scan;
using detail::thread_item;

__device__ __forceinline__ bool is_leaf(SplitDecision d) {
  return d == SplitDecision::kAccept || d == SplitDecision::kAcceptOversized;
}

__device__ __forceinline__ void swept_points_of(const VirtualTriangle& t, const Triangle* tris, const Vec3* x_t0,
                                                const Vec3* x_t1, Vec3 p_t0[3], Vec3 p_t1[3], Vec3 points[6]) {
  const Triangle root = tris[t.root];
  for (int i = 0; i < 3; ++i) {
    p_t0[i] = x_t0[root[i]];
    p_t1[i] = x_t1[root[i]];
  }
  virtual_swept_points(t, p_t0, p_t1, points);
}

__global__ void root_items_kernel(std::size_t n, DeviceLevelItem* items) {
  const std::uint64_t f = thread_item();
  if (f >= n) return;
  items[f].triangle = virtual_root(static_cast<Index>(f));
  items[f].group_first = static_cast<std::uint32_t>(f);
  items[f].group_size = 1;
}

struct AddTallies {
  __device__ SplitTally operator()(const SplitTally& a, const SplitTally& b) const {
    return {a.children + b.children, a.leaves + b.leaves, a.halved + b.halved, a.oversized + b.oversized};
  }
};

/// Pass 1: decision, home cell, and what the triangle adds (tally[n]: nothing).
__global__ void examine_kernel(const DeviceLevelItem* items, std::size_t n, const Triangle* tris, const Vec3* x_t0,
                               const Vec3* x_t1, GridSpec grid, double thickness, std::uint32_t max_levels,
                               std::uint32_t max_halvings, std::uint8_t* decision, CellCoord* home, SplitTally* tally) {
  const std::uint64_t i = thread_item();
  if (i > n) return;
  SplitTally t;
  if (i < n) {
    const VirtualTriangle triangle = items[i].triangle;
    Vec3 p_t0[3], p_t1[3], points[6];
    swept_points_of(triangle, tris, x_t0, x_t1, p_t0, p_t1, points);
    const Sphere sphere = sphere_of_points(points, 6);
    const SplitDecision d =
        decide_split(triangle, points, sphere.radius, thickness, grid.cell_size, max_levels, max_halvings);
    decision[i] = static_cast<std::uint8_t>(d);
    home[i] = grid_cell_of(grid, sphere.centre);
    t.children = d == SplitDecision::kSubdivide ? 4 : (d == SplitDecision::kHalveTime ? 2 : 0);
    t.leaves = is_leaf(d) ? 1 : 0;
    t.halved = d == SplitDecision::kHalveTime;
    t.oversized = d == SplitDecision::kAcceptOversized;
  }
  tally[i] = t;
}

/// Pass 3: leaves and children, as the CPU's third pass.
__global__ void write_kernel(const DeviceLevelItem* items, std::size_t n, const Triangle* tris, const Vec3* x_t0,
                             const Vec3* x_t1, GridSpec grid, double thickness, const std::uint8_t* decision,
                             const CellCoord* home, const SplitTally* offset, Leaf* leaves, DeviceLevelItem* next) {
  const std::uint64_t i = thread_item();
  if (i >= n) return;
  const DeviceLevelItem item = items[i];
  const SplitDecision d = static_cast<SplitDecision>(decision[i]);
  if (is_leaf(d)) {
    Leaf& leaf = leaves[offset[i].leaves];
    leaf.triangle = item.triangle;
    Vec3 p_t0[3], p_t1[3], points[6];
    swept_points_of(item.triangle, tris, x_t0, x_t1, p_t0, p_t1, points);
    const Vec3 sources[6] = {p_t0[0], p_t0[1], p_t0[2], p_t1[0], p_t1[1], p_t1[2]};
    leaf.dop = dop_of_points(points, 6, rounding_pad(sources, 6), thickness);
    Vec3 lo, hi;
    dop_box(leaf.dop, lo, hi);
    LeafCells cells;
    cells.block = grid_block_of(grid, lo, hi);
    cells.home = home[i];
    cells.sibling_count = 0;
    for (std::uint32_t s = item.group_first; s < item.group_first + item.group_size; ++s) {
      if (s != i && is_leaf(static_cast<SplitDecision>(decision[s]))) cells.sibling_home[cells.sibling_count++] = home[s];
    }
    cells.control_bits = make_control_bits(cells);
    leaf.cells = cells;
  } else if (d == SplitDecision::kSubdivide) {
    VirtualTriangle child[4];
    loop_children(item.triangle, child);
    const std::uint64_t o = offset[i].children;
    for (int q = 0; q < 4; ++q) next[o + q] = {child[q], static_cast<std::uint32_t>(o), 4};
  } else {
    VirtualTriangle child[2];
    halve_time(item.triangle, child);
    const std::uint64_t o = offset[i].children;
    for (int h = 0; h < 2; ++h) next[o + h] = {child[h], static_cast<std::uint32_t>(o + h), 1};
  }
}

}  // namespace

std::size_t subdivide_virtually_on_device(const Triangle* triangles, std::size_t triangle_count, const Vec3* x_t0,
                                          const Vec3* x_t1, const GridSpec& grid, double thickness,
                                          std::uint32_t max_levels, std::uint32_t max_halvings,
                                          DeviceSubdivision& b, cudaStream_t stream,
                                          std::vector<SubdivisionLevelCounts>& levels, const GrowthCheck& check) {
  levels.clear();
  std::size_t n = triangle_count, leaf_total_so_far = 0;
  check_growth(check, b.items.growth_bytes(n));
  b.items.resize(n);
  if (n > 0) {
    root_items_kernel<<<blocks_for(n), detail::kBlockSize, 0, stream>>>(n, b.items.data());
    SNAG_CUDA_CHECK_LAUNCH();
  }
  while (n > 0) {
    check_growth(check, b.decision.growth_bytes(n) + b.home.growth_bytes(n) + b.tally.growth_bytes(n + 1));
    b.decision.resize(n);
    b.home.resize(n);
    b.tally.resize(n + 1);
    examine_kernel<<<blocks_for(n + 1), detail::kBlockSize, 0, stream>>>(
        b.items.data(), n, triangles, x_t0, x_t1, grid, thickness, max_levels, max_halvings, b.decision.data(),
        b.home.data(), b.tally.data());
    SNAG_CUDA_CHECK_LAUNCH();
    exclusive_scan(b.tally.data(), b.tally.data(), n + 1, AddTallies{}, b.temp, stream, check);
    SplitTally total;
    ReadBack(stream).add(&total, b.tally.data() + n).wait();
    const std::size_t child_total = total.children, leaf_total = total.leaves;

    SubdivisionLevelCounts counts;
    counts.triangles = n;
    counts.accepted = leaf_total;
    counts.subdivided = (total.children - 2 * total.halved) / 4;
    counts.halved = total.halved;
    counts.oversized = total.oversized;
    levels.push_back(counts);

    // Room for this level's leaves after the previous ones (grow, keeping them).
    const std::size_t leaf_end = leaf_total_so_far + leaf_total;
    grow_keeping(b.leaves, b.spare, leaf_total_so_far, leaf_end, check);
    check_growth(check, b.next.growth_bytes(child_total));
    b.next.resize(child_total);
    write_kernel<<<blocks_for(n), detail::kBlockSize, 0, stream>>>(
        b.items.data(), n, triangles, x_t0, x_t1, grid, thickness, b.decision.data(), b.home.data(), b.tally.data(),
        b.leaves.data() + leaf_total_so_far, b.next.data());
    SNAG_CUDA_CHECK_LAUNCH();
    std::swap(b.items, b.next);
    leaf_total_so_far = leaf_end;
    n = child_total;
  }
  return leaf_total_so_far;
}

}  // namespace snag
