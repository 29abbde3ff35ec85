// Virtual subdivision on the GPU, mirroring libcd/subdivision/virtual_subdivision.cpp:
// level by level, one thread per virtual triangle decides (accept, Loop split,
// time halving) and finds its home cell; one prefix scan places children in
// the next level's list and leaves after the previous levels' leaves; a second
// pass writes leaves (DOP, cells, control bits with siblings) and children.
// Same order as the CPU, so the leaf list is identical.
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "libcd/cuda/device_buffer.cuh"
#include "libcd/subdivision/virtual_subdivision.hpp"

namespace snag {

/// A virtual triangle in a level's list with the slice holding its siblings.
struct DeviceLevelItem {
  VirtualTriangle triangle;
  std::uint32_t group_first = 0;
  std::uint32_t group_size = 1;
};

/// What one virtual triangle of a level adds, and after an exclusive scan in
/// place what those before it add: children and leaves (their places in the
/// next list and after the earlier levels' leaves), time halvings and
/// oversized leaves (the level's counts; Loop splits are the children that
/// halvings leave, by four).
struct SplitTally {
  std::uint64_t children = 0, leaves = 0, halved = 0, oversized = 0;
};

/// A level as the device knows it: its items and the leaves of the levels
/// before it (written by the pass before), what it adds (its write pass), and
/// whether a level ran out of the room it was given (carried on).
struct LevelState {
  SplitTally total;
  std::uint64_t items = 0, leaf_base = 0;
  std::uint32_t overflow = 0;
};

/// Buffers of the subdivision stage, reused across calls (they only grow),
/// and the item counts of the last call's levels (its plan).
struct DeviceSubdivision {
  DeviceBuffer<DeviceLevelItem> items, next;
  DeviceBuffer<std::uint8_t> decision;
  DeviceBuffer<CellCoord> home;
  DeviceBuffer<SplitTally> tally;  ///< room + 1 per level, scanned in place: tally[items] is the level's sum
  DeviceBuffer<LevelState> state;  ///< one per level of a planned call and one after; two else
  DeviceBuffer<Leaf> leaves, spare;
  DeviceBuffer<unsigned char> temp;
  std::vector<std::size_t> plan;  ///< items per level of the last call
  std::size_t planned_leaves = 0;

  explicit DeviceSubdivision(cudaStream_t stream)
      : items(0, stream),
        next(0, stream),
        decision(0, stream),
        home(0, stream),
        tally(0, stream),
        state(0, stream),
        leaves(0, stream),
        spare(0, stream),
        temp(0, stream) {}

  /// Gives every buffer back; the plan stays.
  void release() noexcept {
    items.release();
    next.release();
    decision.release();
    home.release();
    tally.release();
    state.release();
    leaves.release();
    spare.release();
    temp.release();
  }
};

/// Subdivides every triangle as subdivide_virtually does; the leaves are left
/// in buffers.leaves (the returned count, level by level, in list order).
/// When the last call had as many triangles, its levels are the plan: each
/// level gets a quarter more room than the last call's had, the passes read
/// their sizes on the device, and the stream is waited for once at the end;
/// a level that outgrows its room, or a level more, and the levels are run
/// again as below. Otherwise it waits for the stream once per level (the
/// sizes of the next level).
/// @param triangles  #F device triangles; x_t0, x_t1: #V device positions
/// @param[out] levels  one entry per level examined
/// @param check  told what each allocation adds before it is made (it may throw)
/// Throws CudaError, or what `check` throws.
std::size_t subdivide_virtually_on_device(const Triangle* triangles, std::size_t triangle_count, const Vec3* x_t0,
                                          const Vec3* x_t1, const GridSpec& grid, double thickness,
                                          std::uint32_t max_levels, std::uint32_t max_halvings,
                                          DeviceSubdivision& buffers, cudaStream_t stream,
                                          std::vector<SubdivisionLevelCounts>& levels,
                                          const GrowthCheck& check = {});

}  // namespace snag
