// Virtual subdivision, level by level, on the GPU: the CUDA twin of
// libcd/subdivision/virtual_subdivision.cpp, with the same SNAG_HD math
// (virtual_triangle.hpp, bounding_sphere.hpp, dop18.hpp, control_bits.hpp).
// Wong, Leach, Zambetta, virtual subdivision chapter, Algorithm 1 and section
// 5.3.2: one thread per triangle per level, a new triangle list per level.
#include "libcd/cuda/virtual_subdivision.cuh"

#include <cub/device/device_scan.cuh>

#include <algorithm>
#include <functional>

#include "libcd/bounding_volume/bounding_sphere.hpp"
#include "libcd/bounding_volume/primitive_bounds.hpp"
#include "libcd/core/error.hpp"
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

__global__ void root_items_kernel(std::size_t n, DeviceLevelItem* items, LevelState* first) {
  __shared__ detail::WarpRunStage<DeviceLevelItem, detail::kBlockSize> stage;  // 48 bytes a thread, in one piece
  const std::uint64_t f = thread_item();
  if (f == 0) *first = LevelState{SplitTally{}, n, 0, 0};
  DeviceLevelItem item;
  item.triangle = virtual_root(static_cast<Index>(f));
  item.group_first = static_cast<std::uint32_t>(f);
  stage.write(item, f, n, items);
}

struct AddTallies {
  __device__ SplitTally operator()(const SplitTally& a, const SplitTally& b) const {
    return {a.children + b.children, a.leaves + b.leaves, a.halved + b.halved, a.oversized + b.oversized};
  }
};

/// The items of a level given `room` for them: none when they overflowed it.
__device__ __forceinline__ std::uint64_t items_within(const LevelState& level, std::size_t room) {
  return level.items <= room ? level.items : 0;
}

/// Pass 1: decision, home cell, and what the triangle adds (tally[i] for i in
/// [items, room]: nothing).
__global__ void examine_kernel(const DeviceLevelItem* items, const LevelState* level, std::size_t room,
                               const Triangle* tris, const Vec3* x_t0, const Vec3* x_t1, GridSpec grid,
                               double thickness, std::uint32_t max_levels, std::uint32_t max_halvings,
                               std::uint8_t* decision, CellCoord* home, SplitTally* tally) {
  const std::uint64_t i = thread_item();
  if (i > room) return;
  const std::uint64_t n = items_within(*level, room);
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

/// write_kernel's block: its warps' leaves staged in shared memory (128 of
/// them, 33 kB) before they are written.
constexpr unsigned kWriteBlock = 128;

/// Pass 3: leaves and children, as the CPU's third pass, within the rooms
/// (leaves: all levels'; next: the next level's items). The first thread
/// records the level's total and the next level's state (level[1]), with
/// `overflow` set when a room was short. A warp's leaves are consecutive in
/// `leaves`: each lane builds its leaf in shared memory, and the warp writes
/// them in one piece, 8 bytes a lane (a leaf a thread wrote 264 bytes apart
/// from its neighbours').
__global__ void __launch_bounds__(kWriteBlock)
    write_kernel(const DeviceLevelItem* items, LevelState* level, std::size_t room, const Triangle* tris,
                 const Vec3* x_t0, const Vec3* x_t1, GridSpec grid, double thickness, const std::uint8_t* decision,
                 const CellCoord* home, const SplitTally* offset, Leaf* leaves, std::size_t leaf_room,
                 DeviceLevelItem* next, std::size_t next_room) {
  __shared__ detail::WarpRunStage<Leaf, kWriteBlock> stage;
  const unsigned lane = threadIdx.x & 31u;
  Leaf* const staged = stage.warp_records();
  const std::uint64_t i = thread_item();
  const std::uint64_t n = items_within(*level, room), leaf_base = level->leaf_base;
  if (i == 0) {
    const SplitTally total = offset[n];
    level->total = total;
    level[1] = LevelState{
        SplitTally{}, total.children, leaf_base + total.leaves,
        level->overflow || level->items > room || total.children > next_room || leaf_base + total.leaves > leaf_room};
  }
  const bool valid = i < n;
  DeviceLevelItem item;
  SplitDecision d = SplitDecision::kAccept;
  if (valid) {
    item = items[i];
    d = static_cast<SplitDecision>(decision[i]);
  }
  const bool is_leaf_here = valid && is_leaf(d);
  const unsigned leaf_lanes = __ballot_sync(0xffffffffu, is_leaf_here);
  if (is_leaf_here) {
    Leaf& leaf = staged[__popc(leaf_lanes & ((1u << lane) - 1u))];
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
  }
  if (leaf_lanes != 0) {
    // The warp's leaves start at its first leaf lane's; those past the room are left out.
    const std::uint64_t first =
        leaf_base + __shfl_sync(0xffffffffu, is_leaf_here ? offset[i].leaves : 0, __ffs(leaf_lanes) - 1);
    const std::uint64_t count = __popc(leaf_lanes);
    detail::warp_copy_run(staged, first < leaf_room ? (count < leaf_room - first ? count : leaf_room - first) : 0,
                          leaves + first);
  }
  if (!valid || is_leaf(d)) return;
  if (d == SplitDecision::kSubdivide) {
    const std::uint64_t o = offset[i].children;
    if (o + 4 > next_room) return;
    VirtualTriangle child[4];
    loop_children(item.triangle, child);
    for (int q = 0; q < 4; ++q) next[o + q] = {child[q], static_cast<std::uint32_t>(o), 4};
  } else {
    const std::uint64_t o = offset[i].children;
    if (o + 2 > next_room) return;
    VirtualTriangle child[2];
    halve_time(item.triangle, child);
    for (int h = 0; h < 2; ++h) next[o + h] = {child[h], static_cast<std::uint32_t>(o + h), 1};
  }
}

SubdivisionLevelCounts level_counts(std::size_t items, const SplitTally& total) {
  SubdivisionLevelCounts counts;
  counts.triangles = items;
  counts.accepted = total.leaves;
  counts.subdivided = (total.children - 2 * total.halved) / 4;
  counts.halved = total.halved;
  counts.oversized = total.oversized;
  return counts;
}

/// The stage's inputs, passed on to each level's passes.
struct SubdivisionInputs {
  const Triangle* triangles;
  std::size_t triangle_count;
  const Vec3* x_t0;
  const Vec3* x_t1;
  GridSpec grid;
  double thickness;
  std::uint32_t max_levels, max_halvings;
};

/// One level's passes: examine `room` + 1 items (those past the level's own
/// count add nothing), scan their tallies, and, when `total` is given, read
/// the level's sum into it (the host then sizes next_room and leaf_room
/// with it); write leaves and children within the rooms. The level's state
/// is state[0], the next's state[1].
void run_level(const SubdivisionInputs& in, std::size_t room, LevelState* state, SplitTally* total,
               const std::function<void(const SplitTally&)>& size_rooms, DeviceSubdivision& b, cudaStream_t stream,
               const GrowthCheck& check) {
  check_growth(check, b.decision.growth_bytes(room) + b.home.growth_bytes(room) + b.tally.growth_bytes(room + 1));
  b.decision.resize(room);
  b.home.resize(room);
  b.tally.resize(room + 1);
  examine_kernel<<<blocks_for(room + 1), detail::kBlockSize, 0, stream>>>(
      b.items.data(), state, room, in.triangles, in.x_t0, in.x_t1, in.grid, in.thickness, in.max_levels,
      in.max_halvings, b.decision.data(), b.home.data(), b.tally.data());
  SNAG_CUDA_CHECK_LAUNCH();
  exclusive_scan(b.tally.data(), b.tally.data(), room + 1, AddTallies{}, b.temp, stream, check);
  if (total != nullptr) {
    ReadBack(stream).add(total, b.tally.data() + room).wait();
    size_rooms(*total);
  }
  const auto write_blocks = static_cast<unsigned>((std::max<std::size_t>(room, 1) + kWriteBlock - 1) / kWriteBlock);
  write_kernel<<<write_blocks, kWriteBlock, 0, stream>>>(
      b.items.data(), state, room, in.triangles, in.x_t0, in.x_t1, in.grid, in.thickness, b.decision.data(),
      b.home.data(), b.tally.data(), b.leaves.data(), b.leaves.size(), b.next.data(), b.next.size());
  SNAG_CUDA_CHECK_LAUNCH();
  std::swap(b.items, b.next);
}

/// The levels as the last call's (b.plan), each in a quarter more room,
/// waiting for the stream once at the end. Returns false, the leaves and
/// `levels` undefined, when a level outgrew its room or the plan ended
/// before the levels did.
bool subdivide_as_planned(const SubdivisionInputs& in, DeviceSubdivision& b, cudaStream_t stream,
                          std::vector<SubdivisionLevelCounts>& levels, std::size_t& leaf_count,
                          const GrowthCheck& check) {
  const std::vector<std::size_t> plan = b.plan;
  auto room_of = [&](std::size_t level) {
    if (level == 0) return in.triangle_count;
    const std::size_t planned = level < plan.size() ? plan[level] : 0;
    return planned + planned / 4 + 256;
  };
  std::size_t most_items = 0;
  for (std::size_t level = 0; level <= plan.size(); ++level) most_items = std::max(most_items, room_of(level));
  const std::size_t leaf_room = b.planned_leaves + b.planned_leaves / 4 + 256;
  check_growth(check, b.items.growth_bytes(most_items) + b.next.growth_bytes(most_items) +
                          b.state.growth_bytes(plan.size() + 1) + b.leaves.growth_bytes(leaf_room));
  b.items.resize(most_items);
  b.next.resize(most_items);
  b.state.resize(plan.size() + 1);
  b.leaves.resize(leaf_room);
  root_items_kernel<<<blocks_for(in.triangle_count), detail::kBlockSize, 0, stream>>>(in.triangle_count, b.items.data(),
                                                                                      b.state.data());
  SNAG_CUDA_CHECK_LAUNCH();
  for (std::size_t level = 0; level < plan.size(); ++level) {
    b.next.resize(room_of(level + 1));
    run_level(in, room_of(level), b.state.data() + level, nullptr, {}, b, stream, check);
  }
  std::vector<LevelState> states(plan.size() + 1);
  ReadBack(stream).add(states.data(), b.state.data(), states.size()).wait();
  const LevelState& after = states.back();
  if (after.overflow != 0 || after.items != 0) return false;
  levels.clear();  // the levels with items (fewer than planned when they ended sooner)
  for (std::size_t level = 0; level < plan.size() && states[level].items > 0; ++level)
    levels.push_back(level_counts(states[level].items, states[level].total));
  leaf_count = after.leaf_base;
  return true;
}

}  // namespace

std::size_t subdivide_virtually_on_device(const Triangle* triangles, std::size_t triangle_count, const Vec3* x_t0,
                                          const Vec3* x_t1, const GridSpec& grid, double thickness,
                                          std::uint32_t max_levels, std::uint32_t max_halvings,
                                          DeviceSubdivision& b, cudaStream_t stream,
                                          std::vector<SubdivisionLevelCounts>& levels, const GrowthCheck& check) {
  levels.clear();
  const SubdivisionInputs in{triangles, triangle_count, x_t0, x_t1, grid, thickness, max_levels, max_halvings};
  std::size_t leaf_count = 0;
  bool planned = false;
  if (!b.plan.empty() && b.plan.front() == triangle_count) {
    try {
      planned = subdivide_as_planned(in, b, stream, levels, leaf_count, check);
    } catch (const UsageError&) {
      // The plan's rooms did not fit the memory limit: its buffers go, and
      // the levels run in exactly the room they need.
      b.release();
    }
  }
  if (!planned) {
    // Level by level, each sized by the one before (read back).
    levels.clear();
    std::size_t n = triangle_count;
    check_growth(check, b.items.growth_bytes(n) + b.state.growth_bytes(2));
    b.items.resize(n);
    b.state.resize(2);
    root_items_kernel<<<blocks_for(std::max<std::size_t>(n, 1)), detail::kBlockSize, 0, stream>>>(n, b.items.data(),
                                                                                                  b.state.data());
    SNAG_CUDA_CHECK_LAUNCH();
    for (std::size_t level = 0; n > 0; ++level) {
      // state[0] is this level's: the next one's, written by the level before.
      if (level > 0)
        SNAG_CUDA_CHECK(
            cudaMemcpyAsync(b.state.data(), b.state.data() + 1, sizeof(LevelState), cudaMemcpyDeviceToDevice, stream));
      SplitTally total;
      run_level(
          in, n, b.state.data(), &total,
          [&](const SplitTally& sum) {
            // Room for this level's leaves after the previous ones (grow, keeping them).
            grow_keeping(b.leaves, b.spare, leaf_count, leaf_count + sum.leaves, check);
            check_growth(check, b.next.growth_bytes(sum.children));
            b.next.resize(sum.children);
          },
          b, stream, check);
      levels.push_back(level_counts(n, total));
      leaf_count += total.leaves;
      n = total.children;
    }
  }
  b.plan.clear();
  for (const SubdivisionLevelCounts& level : levels) b.plan.push_back(level.triangles);
  b.planned_leaves = leaf_count;
  return leaf_count;
}

}  // namespace snag
