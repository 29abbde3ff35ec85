// The candidate tests on the GPU, mirroring step 5-6 of
// libcd/broad_phase/virtual_subdivision_grid.cpp: each cell's tests are cut
// into square tiles (grid/pair_index.hpp) whose per-cell counts are
// prefix-summed; a block finds its tile's cell from the sums, reads the
// tile's two runs of leaves (from a copy of them in cell order, coalesced)
// and their roots' float boxes into shared memory once, and its threads run
// the tile's tests from there with the same filters as the CPU (same root,
// time slots, control bits and extended control bits, root 18-DOPs),
// appending the root pairs; a device sort + unique gives the exact set of
// triangle pairs, ordered as the CPU's. The adaptive grid's test cells
// (adaptive_cells.cuh) run through the same tiles, with the CPU adaptive
// grid's rule (the cell that owns a pair tests it; leaf and root DOPs).
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "libcd/bounding_volume/dop18.hpp"
#include "libcd/bounding_volume/float_box.hpp"
#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/cuda/adaptive_cells.cuh"
#include "libcd/cuda/cell_registration.cuh"
#include "libcd/culling/representative_triangles.hpp"
#include "libcd/grid/control_bits.hpp"

namespace snag {

/// A registration as the uniform grid's pair tests read it for every test
/// of its cell: its root, its time slot and its cells as masks around the
/// cell it is registered in (LocalCells). A registration lies in one cell,
/// so it is worked out once, when the registrations are ordered, not by
/// every tile of the cell that loads it (and in 28 bytes, not 92).
struct UniformTileMember {
  Index root;
  std::uint16_t slot_depth;  ///< at most BroadPhaseSettings::max_time_halvings (32: slot_index's bits)
  /// 1 when the leaf is its root whole (no subdivision, no time halving): a
  /// pair of two such leaves is tested once (control_bits.hpp), so its key
  /// needs no sort to be unique.
  std::uint16_t whole_root;
  std::uint32_t slot_index;
  LocalCells cells;
};
static_assert(sizeof(UniformTileMember) == 28, "UniformTileMember: 7 words");

/// Buffers of the pair stage, reused across calls (they only grow).
struct DevicePairs {
  DeviceBuffer<RegisteredLeaf> registered;  ///< cell by cell, each cell's by root triangle
  /// registered[r] in its cell, and its root's float box (both in the order of registered).
  DeviceBuffer<UniformTileMember> tile_members;
  DeviceBuffer<FloatBox> tile_boxes;
  DeviceBuffer<std::uint64_t> order_keys, order_keys_spare;  ///< the registrations' sort
  DeviceBuffer<std::uint32_t> order_ids, order_ids_spare;
  DeviceBuffer<std::uint64_t> cell_tests, test_total;  ///< a chunk's tests per cell, and their sum (one value)
  DeviceBuffer<std::uint64_t> cell_tiles, first_tile;  ///< a chunk's tiles per cell (grid/pair_index.hpp)
  DeviceBuffer<std::uint64_t> row_begin, row_end;      ///< a chunk's rows [begin, end) of each cell
  /// kept: a pass's keys, those of whole roots' pairs from the front and the
  /// rest from the back; the back ones and sorted are the sort's two halves.
  DeviceBuffer<std::uint64_t> kept, culled, sorted;
  DeviceBuffer<TrianglePair> pairs;  ///< the result of a chunk: unique root pairs (ascending when asked)
  DeviceBuffer<unsigned long long> counters;
  DeviceBuffer<unsigned> histogram;  ///< kept tests per root bucket of the last pass
  DeviceBuffer<unsigned char> temp;

  explicit DevicePairs(cudaStream_t stream)
      : registered(0, stream), tile_members(0, stream), tile_boxes(0, stream), order_keys(0, stream),
        order_keys_spare(0, stream), order_ids(0, stream), order_ids_spare(0, stream), cell_tests(0, stream),
        test_total(0, stream), cell_tiles(0, stream), first_tile(0, stream), row_begin(0, stream),
        row_end(0, stream), kept(0, stream), culled(0, stream), sorted(0, stream), pairs(0, stream),
        counters(0, stream), histogram(0, stream), temp(0, stream) {}

  /// Bytes of the per-cell numbering of a chunk's tests and tiles.
  std::size_t cell_test_bytes() const {
    return cell_tests.capacity_bytes() + test_total.capacity_bytes() + cell_tiles.capacity_bytes() +
           first_tile.capacity_bytes() + row_begin.capacity_bytes() + row_end.capacity_bytes();
  }
};

/// Device bytes per kept test of a chunk: its key, the sort's second half,
/// its unique pair (the sort's scratch is small beside them).
constexpr std::size_t kPairChunkBytesPerTest = 3 * sizeof(std::uint64_t);

/// The triangles [first, end) whose pairs (with a larger triangle) one chunk holds.
struct RootRange {
  std::uint32_t first = 0, end = 0;
};

/// The pair tests of the registered cells, run chunk by chunk.
///
/// Memory: the kept tests of a pass are at most `key_room` (the caller's share
/// of the device memory over kPairChunkBytesPerTest); when one pass would keep
/// more, the tests are split by the smaller root triangle of each pair into
/// ranges (RootRange) of at most key_room kept tests each, read from a
/// histogram of the kept tests over the range, and every range runs as a pass
/// of its own: every test, only those of the range kept. Ranges are disjoint
/// and ascending, so the chunks' unique pairs, one after the other, are the
/// unique pairs of the whole set (sorted, when each chunk's are), and every
/// count is the sum over chunks. `plan` holds the ranges of the last call and is tried first (a scan's
/// steps are alike); on return it holds this call's.
/// Throws UsageError when the kept tests of one triangle exceed key_room.
struct PairChunkPlan {
  std::size_t key_room = ~std::size_t{0};
  std::vector<RootRange> ranges;
};

/// Receives a chunk's unique triangle pairs (a device array, valid until it
/// returns, which it may overwrite) and their count.
using PairChunkVisitor = std::function<void(TrianglePair*, std::size_t)>;

/// What a chunk's unique pairs are made into before `visit` gets them.
struct ChunkPairs {
  /// True: each chunk's pairs ascend (unless `separation` is set, which
  /// writes them in any order). False: the pairs of two whole roots
  /// (UniformTileMember::whole_root), each kept once, come as the tests kept
  /// them and only the others are sorted to be made unique (cloth_ball ×16,
  /// CCD and static: device time a step 59.3 -> 54.9 ms, H100).
  bool ascending = true;
  /// When set (with `triangles`, #F device triangles), the pairs it proves
  /// apart over its step are left out (in any order; triangle_separation.cuh)
  /// and counted in stats.separated_triangle_pairs.
  const TriangleSeparation* separation = nullptr;
  const Triangle* triangles = nullptr;
};

/// Copies the registered leaves into pairs.registered, cell by cell and each
/// cell's by root triangle (stable; roots below triangle_count), with each
/// one's UniformTileMember in the grid's cell it is registered in and its
/// root's float box (triangle_boxes, #F) beside it, which is all the pair
/// tests read of them: the leaves and the registration's scratch may be
/// given back after it (in stream order). `check` is told what its buffers
/// add before they allocate (it may throw). Throws CudaError, or what `check`
/// throws.
void order_registrations_on_device(const Leaf* leaves, std::size_t triangle_count, const FloatBox* triangle_boxes,
                                   const DeviceCellLists& lists, const GridSpec& grid, DevicePairs& pairs,
                                   cudaStream_t stream, const GrowthCheck& check = {});

/// Runs every test of the registered cells (pairs.registered and the rest,
/// from order_registrations_on_device with the same grid and boxes) and
/// hands the unique triangle pairs to `visit` chunk by chunk (see PairChunkPlan), the chunks in ascending
/// order, each chunk's made as `out` says; the device array passed to
/// visit is valid until it returns. Fills stats' test counters,
/// culled_by_dop, duplicate_root_pair_tests, duplicate_culled_tests (when
/// count_culled: the culled tests' keys are then kept, see
/// BroadPhaseSettings; their room is not bounded by the plan) and
/// triangle_pairs (and separated_triangle_pairs), and the seconds of the tests and sorts in
/// stats.seconds_pairs (CUDA events, visit's time left out). Waits for the
/// stream. Throws CudaError, UsageError.
/// @param triangle_dops  #F device root swept DOPs; triangle_count = #F
/// @param triangle_boxes #F device float_box_of(triangle_dops[f]): a pair whose
///                       boxes are apart is culled without reading its DOPs
void enumerate_pairs_on_device(const DeviceCellLists& lists, const GridSpec& grid, const Dop18* triangle_dops,
                               const FloatBox* triangle_boxes, std::size_t triangle_count, bool count_culled,
                               const ChunkPairs& out, PairChunkPlan& plan, DevicePairs& pairs, cudaStream_t stream,
                               BroadPhaseStats& stats, const PairChunkVisitor& visit);

/// As enumerate_pairs_on_device for the adaptive grid's test cells (from
/// build_adaptive_cells_on_device): each cell tests the pairs with a stuck
/// member that it owns, kept when the leaves' DOPs and the roots' DOPs
/// overlap (the CPU's adaptive grid, broad_phase/virtual_subdivision_grid.cpp).
/// A pass over a root range runs every tile and skips the tests of other ranges.
/// All its kept keys are sorted (its members never mark a whole root, whatever out.ascending says).
void enumerate_adaptive_pairs_on_device(const DeviceAdaptiveCells& tree, const Dop18* triangle_dops,
                                        const FloatBox* triangle_boxes, std::size_t triangle_count, bool count_culled,
                                        const ChunkPairs& out, PairChunkPlan& plan, DevicePairs& p, cudaStream_t stream,
                                        BroadPhaseStats& stats,
                                        const PairChunkVisitor& visit);

}  // namespace snag
