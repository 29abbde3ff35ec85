// The adaptive grid's hierarchy of crowded cells on the GPU, the CUDA twin of
// libcd/grid/adaptive_cells.cpp: the same test cells, in the same order
// (level by level, by key), with the same members (stuck ones first), and
// the same counts.
//
// Level by level, over (key, leaf) registrations generated in leaf order
// within each key: one stable radix sort by key, the runs of equal keys (the
// cells of the level), then per registration whether its leaf stays (the cell
// is final, or the leaf spans more than two children on an axis) or goes down
// into the children it meets, with prefix sums placing every output: the
// test cells and their members, the crowded cells (the next level's parents)
// and the next level's registrations (key = crowded index · 8 + octant).
// The levels place the members' leaf ids; at the end each cell's stuck and
// pushed members are ordered by root (the CPU's are by leaf id) and their
// records built: the tests are the same, and a pass of the pair tests over a
// root range skips the tiles whose rows and columns hold none of its.
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>

#include "libcd/bounding_volume/float_box.hpp"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/grid/adaptive_cells.hpp"

namespace snag {

/// What the pair tests read of a member of an adaptive test cell: 17 4-byte
/// words, copied word by word into shared memory. The odd count matters
/// there: the threads of a warp read consecutive members, and a stride of an
/// odd number of words puts the 32 reads in 32 different banks (16 words
/// would put them in 2, a 16-way conflict on every read).
struct AdaptiveMember {
  Index root;
  std::uint32_t slot_depth, slot_index;  ///< its time slot
  std::uint32_t leaf;                    ///< its leaf id (for the leaf's DOP)
  FineBlock block;
  /// float_box_of the leaf's DOP, as its corners (a FloatBox is aligned to 8
  /// bytes): most pairs are apart there, before the DOPs are read.
  float box_lo[3], box_hi[3];
  std::uint32_t unused = 0;  ///< the 17th word
};
static_assert(sizeof(AdaptiveMember) == 17 * 4 && alignof(AdaptiveMember) == 4, "AdaptiveMember: 17 words");

/// True unless the two members' leaf float boxes are apart on an axis (then their DOPs are).
SNAG_HD_INLINE bool leaf_boxes_may_overlap(const AdaptiveMember& a, const AdaptiveMember& b) {
  for (int k = 0; k < 3; ++k)
    if (a.box_lo[k] > b.box_hi[k] || b.box_lo[k] > a.box_hi[k]) return false;
  return true;
}

/// slots_nested of the two members' time slots.
SNAG_HD_INLINE bool slots_nested(const AdaptiveMember& a, const AdaptiveMember& b) {
  return slots_nested(a.slot_depth, a.slot_index, b.slot_depth, b.slot_index);
}

/// What a registration of a level leaves to the prefix sums: 1 when its leaf
/// stays in the cell (stuck, or the cell is final), and the children it goes
/// down into.
struct RegistrationFate {
  std::uint64_t stuck, children;
};

/// What a cell of a level leaves to the prefix sums: 1 when it is crowded
/// (split), 1 when it is a test cell, and its members when it is one.
struct CellFate {
  std::uint64_t crowded, cells, members;
};

/// The hierarchy on the device (as AdaptiveCells, members as records), and scratch.
struct DeviceAdaptiveCells {
  int depth = 0;
  DeviceBuffer<FineBlock> blocks;         ///< #leaves fine blocks
  DeviceBuffer<Dop18> leaf_dops;          ///< #leaves: the leaves' DOPs, which the tests compare
  DeviceBuffer<TestCell> cells, cells_spare;  ///< cells with at least one test
  DeviceBuffer<AdaptiveMember> members;       ///< cell by cell, each cell's stuck and pushed ones by root
  std::size_t cell_count = 0, member_count = 0;
  std::size_t registrations = 0, cells_subdivided = 0, stuck_registrations = 0;
  int deepest_level = 0;
  // scratch
  DeviceBuffer<std::uint32_t> member_leaves, member_leaves_spare;  ///< the members' leaf ids, level by level
  DeviceBuffer<std::uint64_t> keys, keys_sorted, run_keys, run_length, run_first;
  DeviceBuffer<std::uint32_t> values, values_sorted;
  DeviceBuffer<CellCoord> run_coord, parents, next_parents;
  DeviceBuffer<RegistrationFate> reg_counts, reg_offset;
  DeviceBuffer<CellFate> cell_counts, cell_offset;
  DeviceBuffer<unsigned long long> counters;
  DeviceBuffer<unsigned char> temp;

  explicit DeviceAdaptiveCells(cudaStream_t stream)
      : blocks(0, stream), leaf_dops(0, stream), cells(0, stream), cells_spare(0, stream), members(0, stream),
        member_leaves(0, stream), member_leaves_spare(0, stream), keys(0, stream), keys_sorted(0, stream), run_keys(0, stream),
        run_length(0, stream), run_first(0, stream), values(0, stream), values_sorted(0, stream),
        run_coord(0, stream), parents(0, stream), next_parents(0, stream), reg_counts(0, stream),
        reg_offset(0, stream), cell_counts(0, stream), cell_offset(0, stream), counters(0, stream), temp(0, stream) {}

  /// Bytes of what the pair tests read (blocks, leaf DOPs, cells, members).
  std::size_t test_bytes() const {
    return blocks.capacity_bytes() + leaf_dops.capacity_bytes() + cells.capacity_bytes() +
           members.capacity_bytes();
  }
  /// Bytes of the build's scratch.
  std::size_t scratch_bytes() const;
  /// Gives back the build's scratch (in stream order).
  void release_scratch();
};

/// Builds the hierarchy over `grid` for leaf_count device leaves as
/// build_adaptive_cells does, each cell's stuck and pushed members then
/// ordered by root, leaf order among equal roots (max_depth in [0, kMaxAdaptiveDepth], cell_limit
/// ≥ 1). Waits for the stream (sizes). `check` is told what each allocation
/// adds before it is made (it may throw). Throws CudaError, UsageError.
void build_adaptive_cells_on_device(const Leaf* leaves, std::size_t leaf_count, const GridSpec& grid, int max_depth,
                                    std::size_t cell_limit, DeviceAdaptiveCells& out, cudaStream_t stream,
                                    const GrowthCheck& check = {});

}  // namespace snag
