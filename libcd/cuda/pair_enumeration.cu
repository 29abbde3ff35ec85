// One test per thread, then sort + unique of root pairs, on the GPU.
// Pabst, Koch, Straßer, "Fast and scalable CPU/GPU collision detection for
// rigid and deformable surfaces", CGF 2010; Fan, Wang, Dong, Sun, "Efficient
// GPU-based collision detection for deformable models", 2011 (one thread per
// test, prefix sums); Grand, GPU Gems 3 ch. 32 and the virtual subdivision
// chapter, section 5.3.3 (control bits, extended control bits).
// Primitives: CUB DeviceScan, DeviceRadixSort, DeviceSelect::Unique.
//
// Chunks: each cell's leaves are ordered by root triangle (the tests' filters
// and keys do not depend on which leaf of a pair comes first), so that the
// tests of a cell whose smaller root lies in a range [lo, hi) are the rows
// i0..i1-1 of its triangular numbering: one contiguous run of work items. A
// chunk's pass runs exactly its own tests; all chunks together run each test once.
//
// Root order is also the order the pairs are found and handed on in, which
// the narrow phase reads best (neighbours in the mesh share vertices).
// Ordering a large cell's members along y instead, to skip the tiles whose
// boxes lie apart in y as the CPU's cells sweep, was measured on an H100
// (cloth_ball x16 with intersections): the box tests took 15% less, but the
// narrow phase's first kernels, the longer sort key and the tiles' bounds
// took nearly as much more, and the device's time a step did not change;
// with y only in 8 bands of a cell and root order within each, x16's took
// 3% less, but x4's and cloth_ball's up to 3% more, and x4's step through
// snag-scan up to 9% more.
#include "libcd/cuda/pair_enumeration.cuh"

#include <cub/device/device_reduce.cuh>
#include <cub/device/device_scan.cuh>
#include <cub/device/device_select.cuh>

#include <algorithm>
#include <deque>
#include <string>

#include "libcd/core/error.hpp"
#include "libcd/cuda/cuda_event.cuh"

#include "libcd/cuda/device_scan.cuh"
#include "libcd/cuda/launch.cuh"
#include "libcd/cuda/triangle_separation.cuh"
#include "libcd/grid/control_bits.hpp"
#include "libcd/grid/pair_index.hpp"

namespace snag {
namespace {

using detail::blocks_for;
using detail::ensure_scratch;
using detail::exclusive_sum;
using detail::pack_key;
using detail::radix_bits;
using detail::radix_sort_keys;
using detail::radix_sort_pairs;
using detail::thread_item;
using detail::unpack_key;

/// Counter slots of the test kernel: kKeptOnce the kept keys of two whole
/// roots' pairs (written from the front), kKept the others (from the back).
enum Counter {
  kBoxesApart, kSameRoot, kTimeSlots, kControlBits, kExtended, kFallback, kPassed, kKeptOnce, kKept, kCulled, kCounters
};

/// The bit of a waiting or kept key that marks a pair of two whole roots
/// (set only when keys take at most 63 bits).
constexpr std::uint64_t kOnceBit = std::uint64_t{1} << 63;

/// Sort keys of the registrations: cell rank above, root triangle below
/// (pack_key); the values are the leaf ids.
__global__ void registration_keys_kernel(const Leaf* leaves, const std::uint64_t* first, std::size_t cells,
                                         const std::uint32_t* cell_leaves, std::size_t count, int root_bits,
                                         std::uint64_t* keys, std::uint32_t* ids) {
  const std::uint64_t r = thread_item();
  if (r >= count) return;
  const std::uint64_t c = cell_of_work_item(first, cells, r);
  keys[r] = pack_key(c, leaves[cell_leaves[r]].triangle.root, root_bits);
  ids[r] = cell_leaves[r];
}

/// out[r] = registered_leaf(leaves[ids[r]]) and beside it the registration
/// as its cell's tiles read it (the cell's rank in the high bits of keys[r],
/// pack_key) and its root's float box, each a warp's records written in one
/// piece (a record stored by itself lies 92, 28 or 24 bytes from its
/// neighbours').
__global__ void gather_registered_kernel(const Leaf* leaves, const std::uint32_t* ids, const std::uint64_t* keys,
                                         int root_bits, const std::uint64_t* cell_ids, GridSpec grid,
                                         const FloatBox* triangle_boxes, std::size_t count, RegisteredLeaf* out,
                                         UniformTileMember* tile_members, FloatBox* tile_boxes) {
  __shared__ detail::WarpRunStage<RegisteredLeaf, detail::kBlockSize> stage;
  __shared__ detail::WarpRunStage<UniformTileMember, detail::kBlockSize> member_stage;
  __shared__ detail::WarpRunStage<FloatBox, detail::kBlockSize> box_stage;
  const std::uint64_t r = thread_item();
  RegisteredLeaf record;
  UniformTileMember member{};
  FloatBox box{};
  if (r < count) {
    record = registered_leaf(leaves[ids[r]]);
    const CellCoord cell = grid_cell_coord(grid, cell_ids[keys[r] >> root_bits]);
    const bool whole = record.slot_depth == 0 && leaves[ids[r]].triangle.depth == 0;
    member = {record.root, static_cast<std::uint16_t>(record.slot_depth), static_cast<std::uint16_t>(whole),
              record.slot_index, local_cells(record.cells, cell)};
    box = triangle_boxes[record.root];
  }
  stage.write(record, r, count, out);
  member_stage.write(member, r, count, tile_members);
  box_stage.write(box, r, count, tile_boxes);
}

/// The first of a cell's leaves (ordered by root) whose root is at least `root`.
__device__ std::uint64_t first_with_root(const UniformTileMember* registered, std::uint64_t begin, std::uint64_t end,
                                         std::uint32_t root) {
  while (begin < end) {
    const std::uint64_t mid = begin + (end - begin) / 2;
    if (registered[mid].root < root) begin = mid + 1; else end = mid;
  }
  return begin;
}

/// Tests of each cell whose smaller root lies in [lo, hi): rows [i0, i1) of
/// the cell's numbering, tests[c] of them in tiles[c] tiles; tests[cells] =
/// tiles[cells] = 0.
__global__ void chunk_tests_kernel(const std::uint64_t* first, std::size_t cells, const UniformTileMember* registered,
                                   std::uint32_t lo, std::uint32_t hi, std::uint64_t* tests, std::uint64_t* tiles,
                                   std::uint64_t* row_begin, std::uint64_t* row_end) {
  const std::uint64_t c = thread_item();
  if (c > cells) return;
  if (c == cells) {
    tests[c] = tiles[c] = 0;
    return;
  }
  const std::uint64_t begin = first[c], end = first[c + 1], n = end - begin;
  const std::uint64_t i0 = first_with_root(registered, begin, end, lo) - begin;
  const std::uint64_t i1 = first_with_root(registered, begin, end, hi) - begin;
  row_begin[c] = i0;
  row_end[c] = i1;
  tests[c] = pair_count(n - i0) - pair_count(n - i1);  // the pairs (i, j), i < j, with i0 <= i < i1
  tiles[c] = pair_tile_count(n, i0, i1);
}

/// Tests of each adaptive test cell: the rows of its stuck members, [0,
/// stuck), whatever the root range (the test kernel skips the tests of other
/// ranges); as chunk_tests_kernel otherwise.
__global__ void adaptive_tests_kernel(const TestCell* cells, std::size_t count, std::uint64_t* tests,
                                      std::uint64_t* tiles, std::uint64_t* row_begin, std::uint64_t* row_end) {
  const std::uint64_t c = thread_item();
  if (c > count) return;
  if (c == count) {
    tests[c] = tiles[c] = 0;
    return;
  }
  const std::uint64_t n = cells[c].count, stuck = cells[c].stuck;
  row_begin[c] = 0;
  row_end[c] = stuck;
  tests[c] = pair_count(n) - pair_count(n - stuck);
  tiles[c] = pair_tile_count(n, 0, stuck);
}

/// Buckets of the histogram of kept tests over a pass's root range.
constexpr unsigned kHistogramBuckets = 1024;

/// Consecutive tiles a block of the test kernel takes at a time: the cell of
/// each after the first is found from the last one's in a read or two,
/// instead of a galloping search over the cells of all the blocks' tiles in
/// between (a few hundred cells apart, some 20 dependent reads, while the
/// block waits); the runs still interleave, so that blocks get tiles of
/// every part of the grid. (test_kernel on cloth_ball: 2% shorter, H200.)
constexpr std::uint64_t kTileRun = 4;

/// The test kernel's threads a block, half the other kernels' kBlockSize:
/// a block waits at a barrier for each of its tiles (one thread finds the
/// tile's cell, then the block loads its members), and smaller blocks keep
/// more of them resident to run between those waits. (test_kernel on
/// cloth_ball, both detections: 1.09 -> 0.97 ms a step; 64 threads took
/// 1.18, H200.)
constexpr unsigned kTestBlock = 128;

/// Tiles of at least this many slots (rows × columns) run their tests a row
/// a thread; smaller ones (few rows: a cell's last row tile, small cells) in
/// rounds of a test a thread, which leave no thread idle. (512, 1024 and
/// 2048 measured the same on cloth_ball and its refinements, H200: the
/// large tiles hold nearly all the tests.)
constexpr unsigned kRowLoopTests = 2048;

/// The test kernel's resident blocks a multiprocessor: its launch bound, 56
/// registers a thread, none spilled. (×4, H200: 2.43 ms at the 64 it takes
/// unbounded, 47% of the warps active, 2.36 ms at 56, 52%.)
constexpr int kTestBlocksPerSm = 9;

/// A large tile's meetings dealt out at a time (2 kB of shared memory; in a
/// model of the cells, cloth_ball's tiles hold about 270 meetings, ×4's 190).
constexpr unsigned kBlockMeetings = 1024;

/// from[0, count) into `to`, word by word, each thread of the block a word
/// (a warp reads 128 contiguous bytes at a time, whatever the record's size).
template <class T>
__device__ void block_copy_words(const T* from, unsigned count, T* to) {
  static_assert(sizeof(T) % sizeof(std::uint32_t) == 0 && alignof(T) % 4 == 0, "records are copied word by word");
  constexpr unsigned kWords = sizeof(T) / sizeof(std::uint32_t);
  const auto* in = reinterpret_cast<const std::uint32_t*>(from);
  auto* out = reinterpret_cast<std::uint32_t*>(to);
  for (unsigned w = threadIdx.x; w < count * kWords; w += blockDim.x) out[w] = in[w];
}

SNAG_HD_INLINE bool slots_nested(const UniformTileMember& a, const UniformTileMember& b) {
  return ::snag::slots_nested(a.slot_depth, a.slot_index, b.slot_depth, b.slot_index);
}

/// The uniform grid's cells as the tile kernel reads them: members are the
/// registered leaves, the VSS control bits decide which cell tests a pair
/// (by the leaves' masks around the cell, or by their LeafCells where a
/// block is wide), and the roots' DOPs alone decide what is kept.
struct UniformTileCells {
  using Member = RegisteredLeaf;
  using TileMember = UniformTileMember;
  struct Cell {
    CellCoord coord;
  };
  const std::uint64_t* first;
  const std::uint64_t* cell_ids;
  const RegisteredLeaf* members;
  const UniformTileMember* tile_members;  ///< members[r] in its cell
  const FloatBox* tile_boxes;             ///< members[r]'s root's float box
  GridSpec grid;

  __device__ std::uint64_t begin(std::uint64_t c) const { return first[c]; }
  __device__ std::uint64_t size(std::uint64_t c) const { return first[c + 1] - first[c]; }
  __device__ Cell cell(std::uint64_t c) const { return {grid_cell_coord(grid, cell_ids[c])}; }
  /// tile_members[begin, begin + count) into `to`.
  __device__ void load_members(std::uint64_t begin, unsigned count, const Cell&, TileMember* to) const {
    block_copy_words(tile_members + begin, count, to);
  }
  /// The roots' float boxes of members[begin, begin + count) into `to`.
  __device__ void load_boxes(std::uint64_t begin, unsigned count, const FloatBox*, FloatBox* to) const {
    block_copy_words(tile_boxes + begin, count, to);
  }
  /// a and b are members[index_a] and members[index_b].
  __device__ CellPairVerdict verdict(const TileMember& a, const TileMember& b, std::uint64_t index_a,
                                     std::uint64_t index_b, const Cell& cell) const {
    if (a.cells.wide() || b.cells.wide())
      return cell_pair_verdict(members[index_a].cells, members[index_b].cells, cell.coord);
    return cell_pair_verdict(a.cells, b.cells);
  }
  __device__ bool leaves_overlap(const TileMember&, const TileMember&) const { return true; }
  /// The leaf is its root whole: two such are tested once, in one cell.
  __device__ bool whole_root(const TileMember& m) const { return m.whole_root != 0; }
  /// A pass's rows hold only its tests (chunk_tests_kernel): a cell's
  /// members ascend by root, so a row's root is the smaller of each of its
  /// tests' and lies in the pass's range.
  static constexpr bool kRowsInRange = true;
  __device__ bool tile_may_hold(std::uint64_t, const PairTile&, std::uint32_t, std::uint32_t) const { return true; }
};

/// The adaptive grid's test cells (grid/adaptive_cells.hpp): a pair is tested
/// in the one cell that owns it, and kept when the leaves' DOPs overlap as
/// well as the roots' (the leaves' float boxes first, in shared memory).
struct AdaptiveTileCells {
  using Member = AdaptiveMember;
  using TileMember = AdaptiveMember;
  struct Cell {
    CellCoord coord;
    std::int32_t level;
  };
  const TestCell* cells;
  const AdaptiveMember* members;
  const Dop18* leaf_dops;
  int depth;

  __device__ std::uint64_t begin(std::uint64_t c) const { return cells[c].first; }
  __device__ std::uint64_t size(std::uint64_t c) const { return cells[c].count; }
  __device__ Cell cell(std::uint64_t c) const { return {cells[c].coord, cells[c].level}; }
  /// members[begin, begin + count) into `to`.
  __device__ void load_members(std::uint64_t begin, unsigned count, const Cell&, TileMember* to) const {
    block_copy_words(members + begin, count, to);
  }
  /// The roots' float boxes of members[begin, begin + count) into `to`.
  __device__ void load_boxes(std::uint64_t begin, unsigned count, const FloatBox* triangle_boxes, FloatBox* to) const {
    for (unsigned k = threadIdx.x; k < count; k += blockDim.x) to[k] = triangle_boxes[members[begin + k].root];
  }
  __device__ CellPairVerdict verdict(const Member& a, const Member& b, std::uint64_t, std::uint64_t,
                                     const Cell& cell) const {
    return adaptive_cell_owns_pair(a.block, b.block, depth, cell.level, cell.coord) ? CellPairVerdict::kTest
                                                                                    : CellPairVerdict::kSkipControlBits;
  }
  __device__ bool leaves_overlap(const Member& a, const Member& b) const {
    return leaf_boxes_may_overlap(a, b) && dop_overlap(leaf_dops[a.leaf], leaf_dops[b.leaf]);
  }
  /// Not known here: every kept key is sorted.
  __device__ bool whole_root(const Member&) const { return false; }
  /// Stuck members' rows meet pushed members of any root.
  static constexpr bool kRowsInRange = false;
  /// False when no test of the tile of cell c has its smaller root in [lo,
  /// hi). A cell's stuck and pushed members each ascend by root, so the rows
  /// (stuck) and the columns (one run or two) span known roots, and the
  /// smaller root of any of the tile's pairs lies between the smaller of the
  /// two lowest and the smaller of the two highest.
  __device__ bool tile_may_hold(std::uint64_t c, const PairTile& tile, std::uint32_t lo, std::uint32_t hi) const {
    const TestCell& cell = cells[c];
    const AdaptiveMember* m = members + cell.first;
    const Index row_low = m[tile.row_begin].root, row_high = m[tile.row_end - 1].root;
    Index column_low = m[tile.column_begin].root, column_high = m[tile.column_end - 1].root;
    if (tile.column_begin < cell.stuck && tile.column_end > cell.stuck) {  // both runs
      column_low = ::min(column_low, m[cell.stuck].root);
      column_high = ::max(column_high, m[cell.stuck - 1].root);
    }
    return ::min(row_low, column_low) < hi && ::min(row_high, column_high) >= lo;
  }
};

/// A tile's run of members (rows or columns) in shared memory, as the cells'
/// TileMember, with the float boxes of their roots.
template <class Cells>
struct TileSide {
  typename Cells::TileMember members[kPairTileSide];
  FloatBox boxes[kPairTileSide];
};

/// Loads the cell's members [begin, begin + count) and their roots' boxes
/// into `side` (every thread of the block takes part; the caller
/// synchronizes after).
template <class Cells>
__device__ void load_tile_side(const Cells& source, std::uint64_t begin, unsigned count,
                               const typename Cells::Cell& cell, const FloatBox* triangle_boxes,
                               TileSide<Cells>& side) {
  source.load_members(begin, count, cell, side.members);
  source.load_boxes(begin, count, triangle_boxes, side.boxes);
}

/// The tests of a chunk, tile by tile (first_tile[cells] of them, read on the
/// device): each block strides over runs of kTileRun tiles
/// (grid/pair_index.hpp), finds a tile's cell by a galloping search from its
/// last one (the block's tiles ascend), reads the tile's rows (unless its
/// last tile had the same) and columns and their roots' float boxes into
/// shared memory (the uniform grid's as order_registrations_on_device laid
/// them out, in cell order: test_kernel on cloth_ball ×4 2.27 -> 2.05 ms,
/// ×16 22.7 -> 20.9 ms a step, H200), and its threads run the
/// tile's tests (a large tile a row a thread, a small one in rounds of a test
/// a thread), with the CPU's filters in the CPU's order
/// (broad_phase/virtual_subdivision_grid.cpp): the roots' float boxes first,
/// then same root, time slots and the cell's rule (Cells: UniformTileCells,
/// AdaptiveTileCells), then the roots' DOPs (the boxes' and the DOPs' test
/// give the DOPs' answer together, see float_box.hpp). Only the tests whose
/// smaller root lies in [range_first, range_end) run (the uniform cells' rows
/// hold no other), and a tile that Cells::tile_may_hold rules out is skipped
/// whole. A round's tests whose boxes meet (8 to 17% on cloth_ball and its
/// refinements) wait in their warp's list of the tile's (row, column) until
/// it holds 32, whose rules the warp then runs with all its lanes (the last
/// ones at the tile's end): run in the round, they took the warp's time in nearly every
/// round (test_kernel on cloth_ball ×4: 4.09 -> 2.93 ms, 2.91e9 -> 1.97e9
/// instructions, H200). The tests they pass wait in a second list until it
/// holds 32, whose roots' DOPs the warp then tests with all its lanes
/// (across tiles; the last ones at the end). Each kept
/// test adds one to its smaller root's bucket of the histogram over the range
/// (in shared memory, added to `histogram` once per block). Counters are summed
/// in registers and added with one atomic per warp at the end; kept root pairs
/// are written 32 at a time with an atomic for each end of `kept` (with
/// `once`, the keys of two whole roots' pairs from the front, the others from
/// the back; without, all from the back), culled ones (count_culled) with one
/// atomic per warp and round. Every thread of the block runs every
/// round of a tile, so warp-wide operations see full warps.
template <class Cells>
__global__ void __launch_bounds__(kTestBlock, kTestBlocksPerSm)
    test_kernel(const std::uint64_t* first_tile, std::size_t cells, const std::uint64_t* row_begin,
                const std::uint64_t* row_end, Cells source, const Dop18* triangle_dops, const FloatBox* triangle_boxes,
                std::uint32_t range_first, std::uint32_t range_end, std::uint32_t bucket_width, int key_bits,
                unsigned* histogram, std::uint64_t* kept, std::uint64_t kept_capacity, bool once, bool count_culled,
                std::uint64_t* culled, std::uint64_t culled_capacity, unsigned long long* counters) {
  using Member = typename Cells::TileMember;
  using Cell = typename Cells::Cell;
  using Side = TileSide<Cells>;
  const std::uint64_t tiles = first_tile[cells];
  __shared__ unsigned block_histogram[kHistogramBuckets];
  // Raw storage: shared variables take no initializers, and the records have them.
  __shared__ alignas(alignof(Side)) unsigned char side_storage[2 * sizeof(Side)];
  __shared__ alignas(alignof(Cell)) unsigned char cell_storage[sizeof(Cell)];
  __shared__ std::uint64_t tile_cell, tile_rows[2], tile_columns[2];  // [begin, end) of each
  // The members the rows hold, [begin, end) in the source: a run's tiles
  // share their row tile but at its end, and read it once.
  __shared__ std::uint64_t held_rows[2];
  __shared__ bool tile_skipped, rows_held;
  Side& rows = *reinterpret_cast<Side*>(side_storage);
  Side& columns = *reinterpret_cast<Side*>(side_storage + sizeof(Side));
  Cell& tile_cell_info = *reinterpret_cast<Cell*>(cell_storage);
  for (unsigned k = threadIdx.x; k < kHistogramBuckets; k += blockDim.x) block_histogram[k] = 0;
  if (threadIdx.x == 0) {
    tile_cell = 0;
    held_rows[0] = held_rows[1] = ~std::uint64_t{0};
  }
  unsigned boxes_apart = 0, same_root = 0, time_slots = 0, control_bits = 0, extended = 0, fallback = 0, passed = 0,
           culls = 0;
  // Each warp's tests of the tile whose boxes meet, still to be decided (as
  // row << 6 | column), its keys whose roots' DOPs are still to be tested,
  // and its kept keys still to be written, in shared memory: a warp decides
  // 32 tests and tests 32 DOP pairs at once with all its lanes, and reserves
  // room for 32 kept keys with one atomic. The counts are the same on every
  // lane of the warp.
  __shared__ std::uint16_t warp_meeting[kTestBlock / 32][64];
  // A large tile's meetings, gathered from every warp of the block and dealt
  // out to all of them in turn, kBlockMeetings at a time, and each warp's
  // count of them.
  __shared__ std::uint16_t block_meeting[kBlockMeetings];
  __shared__ unsigned warp_meetings[kTestBlock / 32];
  __shared__ std::uint64_t warp_waiting[kTestBlock / 32][64], warp_keeping[kTestBlock / 32][64];
  const unsigned lane = threadIdx.x & 31u;
  std::uint16_t* const meeting = warp_meeting[threadIdx.x / 32];
  std::uint64_t* const waiting = warp_waiting[threadIdx.x / 32];
  std::uint64_t* const keeping = warp_keeping[threadIdx.x / 32];
  unsigned meeting_count = 0, waiting_count = 0, keeping_count = 0;
  auto record_cull = [&](bool cull, std::uint64_t key) {
    if (count_culled) {
      const unsigned long long slot = detail::warp_append(cull, &counters[kCulled]);
      if (cull && slot < culled_capacity) culled[slot] = key & ~kOnceBit;
    } else {
      culls += cull ? 1 : 0;
    }
  };
  // Writes the first n (at most 32) kept keys, those of two whole roots'
  // pairs from the front of `kept` and the others from its back.
  auto write_kept = [&](unsigned n) {
    const std::uint64_t key = lane < n ? keeping[lane] : 0;
    const bool front = lane < n && (key & kOnceBit) != 0, back = lane < n && !front;
    const unsigned long long at_front = detail::warp_append(front, &counters[kKeptOnce]);
    const unsigned long long at_back = detail::warp_append(back, &counters[kKept]);
    if (front && at_front < kept_capacity) kept[at_front] = key & ~kOnceBit;
    if (back && at_back < kept_capacity) kept[kept_capacity - 1 - at_back] = key;
    detail::warp_list_drop(keeping, keeping_count, n);
  };
  // Tests the roots' DOPs of the first n (at most 32) waiting keys, a key a lane.
  auto test_waiting = [&](unsigned n) {
    bool keep = false, cull = false;
    std::uint64_t key = 0;
    if (lane < n) {
      key = waiting[lane];
      Index low = 0, high = 0;
      unpack_key(key & ~kOnceBit, key_bits, low, high);
      if (dop_overlap(triangle_dops[low], triangle_dops[high])) {
        keep = true;
        atomicAdd(&block_histogram[(low - range_first) / bucket_width], 1u);
      } else {
        cull = true;
      }
    }
    detail::warp_list_drop(waiting, waiting_count, n);
    detail::warp_list_push(keep, key, keeping, keeping_count);
    if (keeping_count >= 32) write_kept(32);
    record_cull(cull, key);
  };
  for (std::uint64_t t = blockIdx.x * kTileRun; t < tiles;
       t = (t + 1) % kTileRun == 0 ? t + 1 + (gridDim.x - 1) * kTileRun : t + 1) {
    // Thread 0 finds the tile between two barriers. Found during the last
    // tile instead, while the members were copied asynchronously (cp.async),
    // with one barrier a tile, test_kernel took 18.1 ms a step on ×16
    // against 19.8 (H100), but racecheck reported hazards on the adaptive
    // cells (cloth_ball, CCD) and none on this form: not kept.
    __syncthreads();  // the last tile's shared data is read by all
    if (threadIdx.x == 0) {
      const std::uint64_t c = cell_of_work_item_from(first_tile, cells, tile_cell, t);
      tile_cell = c;
      tile_cell_info = source.cell(c);
      const PairTile tile = pair_tile(source.size(c), row_begin[c], row_end[c], t - first_tile[c]);
      tile_rows[0] = tile.row_begin;
      tile_rows[1] = tile.row_end;
      tile_columns[0] = tile.column_begin;
      tile_columns[1] = tile.column_end;
      tile_skipped = !source.tile_may_hold(c, tile, range_first, range_end);
      const std::uint64_t rows_first = source.begin(c) + tile.row_begin, rows_end = source.begin(c) + tile.row_end;
      rows_held = held_rows[0] == rows_first && held_rows[1] == rows_end;
      if (!tile_skipped) {
        held_rows[0] = rows_first;
        held_rows[1] = rows_end;
      }
    }
    __syncthreads();
    if (tile_skipped) continue;  // no test of this pass's range (the whole block skips)
    const std::uint64_t cell_first = source.begin(tile_cell);
    const auto row_count = static_cast<unsigned>(tile_rows[1] - tile_rows[0]);
    const auto column_count = static_cast<unsigned>(tile_columns[1] - tile_columns[0]);
    // Test (row, column) of the tile is the pair i < j of the cell where
    // j - i = offset + column - row (the offset is negative in a diagonal
    // tile whose first rows the chunk leaves out).
    const auto offset = static_cast<std::int64_t>(tile_columns[0]) - static_cast<std::int64_t>(tile_rows[0]);
    const Cell cell = tile_cell_info;
    if (!rows_held) load_tile_side(source, cell_first + tile_rows[0], row_count, cell, triangle_boxes, rows);
    load_tile_side(source, cell_first + tile_columns[0], column_count, cell, triangle_boxes, columns);
    __syncthreads();
    // The rules of the tests whose roots' boxes meet, 32 waiting tests at a
    // time, a test a lane (a round's tests leave a few lanes whose boxes
    // meet: run there, the rules would take the whole warp's time in almost
    // every round).
    auto decide_meeting = [&](unsigned n) {
      bool wait = false, cull = false;
      std::uint64_t key = 0;
      if (lane < n) {
        const unsigned item = meeting[lane];
        const unsigned row = item >> 6, column = item & 63u;
        const Member& a = rows.members[row];
        const Member& b = columns.members[column];
        const Index ra = a.root, rb = b.root;
        if (ra == rb) {
          ++same_root;
        } else if (!slots_nested(a, b)) {
          ++time_slots;
        } else {
          switch (source.verdict(a, b, cell_first + tile_rows[0] + row, cell_first + tile_columns[0] + column, cell)) {
            case CellPairVerdict::kSkipControlBits:
              ++control_bits;
              break;
            case CellPairVerdict::kSkipExtendedBits:
              ++extended;
              break;
            case CellPairVerdict::kTestFallback:
              ++fallback;
              [[fallthrough]];
            case CellPairVerdict::kTest: {
              ++passed;
              key = ra < rb ? pack_key(ra, rb, key_bits) : pack_key(rb, ra, key_bits);
              if (once && source.whole_root(a) && source.whole_root(b)) key |= kOnceBit;
              if (source.leaves_overlap(a, b)) wait = true; else cull = true;
              break;
            }
          }
        }
      }
      detail::warp_list_drop(meeting, meeting_count, n);
      detail::warp_list_push(wait, key, waiting, waiting_count);
      if (waiting_count >= 32) test_waiting(32);
      record_cull(cull, key);
    };
    // Whether the test of a row (root ra) against `column` is this pass's:
    // its smaller root in the range.
    auto tests_in_range = [&](Index ra, unsigned column) {
      const Index rb = columns.members[column].root;
      const Index low = ra < rb ? ra : rb;
      return low >= range_first && low < range_end;
    };
    // The first filter of the test of a row (root ra, float box `box`)
    // against `column`: whether it is this pass's test (its smaller root in
    // the range, as in every test of the uniform cells' rows) and the roots'
    // float boxes meet. The tests whose boxes are apart are counted.
    auto boxes_meet = [&](Index ra, const FloatBox& box, unsigned column) {
      if (!Cells::kRowsInRange && !tests_in_range(ra, column)) return false;  // another chunk's test
      const bool meet = float_boxes_may_overlap(box, columns.boxes[column]);
      boxes_apart += meet ? 0 : 1;
      return meet;
    };
    // One test of the tile; every thread of the block calls it once per
    // round, with `valid` set where it has a test.
    auto run_test = [&](bool valid, unsigned row, unsigned column) {
      const bool meet = valid && boxes_meet(rows.members[row].root, rows.boxes[row], column);
      static_assert(kPairTileSide <= 64, "a tile's (row, column) is packed in 12 bits");
      detail::warp_list_push(meet, static_cast<std::uint16_t>((row << 6) | column), meeting, meeting_count);
      if (meeting_count >= 32) decide_meeting(32);
    };
    if (row_count * column_count >= kRowLoopTests) {
      // Large tiles a row a thread: thread t takes row t % 64 against the
      // columns [32 h, 32 h + 32) of its half h = t / 64, its row's root and
      // box held in registers, each column's read by the whole warp at once
      // (one shared-memory broadcast), its tests' meetings gathered in a
      // mask and appended to the warp's list after the loop. A test costs a
      // few instructions here, against the rounds' stepping, ballot and list
      // append per test below. (test_kernel, H200: cloth_ball ×4 2.98 ->
      // 2.26 ms, 2.03e9 -> 1.24e9 instructions; cloth_ball 551 -> 480 µs.)
      static_assert(kTestBlock == 2 * kPairTileSide && kPairTileSide == 64,
                    "a tile's rows by two halves of 32 columns");
      const unsigned row = threadIdx.x % kPairTileSide, half = threadIdx.x / kPairTileSide;
      const unsigned warp_row = row & ~31u;  // the warp's first row
      // Row r's tests are the columns q > r + d in a diagonal tile (offset =
      // -d <= 0), every column otherwise.
      const bool diagonal = offset < static_cast<std::int64_t>(row_count);
      const unsigned after = diagonal ? static_cast<unsigned>(1 - offset) : 0;  // the columns from row + after on
      const unsigned lane_first = diagonal ? after + row : 0;
      const unsigned column_begin = 32 * half, column_end = ::min(column_count, column_begin + 32);
      std::uint32_t meets = 0;
      if (warp_row < row_count) {  // the same on every lane of the warp
        const bool has_row = row < row_count;
        const Index ra = rows.members[has_row ? row : 0].root;
        const FloatBox box = rows.boxes[has_row ? row : 0];
        // Below the warp's first row's first column no lane has a test.
        // Every lane runs the warp's columns, without a branch of its own;
        // the bits of the tests it does not have are cleared after, and the
        // tests whose boxes are apart counted from the bits. (The loop took
        // 19 instructions a column when each lane branched to its own tests
        // and counted each, ncu on ×4; test_kernel a step, H100: ×16 21.3
        // -> 19.8 ms, ×4 2.53 -> 2.37, cloth_ball 0.61 -> 0.59.) The loop
        // is a small part of the kernel: a box around each group of 8, 16
        // or 32 of the warp's columns, the groups no row's box meets passed
        // over, was no faster (test_kernel a step, H100, 12 frames, two
        // runs each: ×16 18.2 and 19.5 ms, with groups of 8 20.7 and 20.6,
        // of 16 18.7 and 19.7, of 32 19.4 and 19.0; cloth_ball 0.56 and
        // 0.55, with groups 0.60 to 0.63).
        const unsigned first = ::max(column_begin, diagonal ? after + warp_row : 0u);
        std::uint32_t in_range = 0, bit = first < column_end ? 1u << (first - column_begin) : 0u;
#pragma unroll 2  // unrolled by 4 or more, the kernel spills at its 56 registers
        for (unsigned column = first; column < column_end; ++column, bit <<= 1) {
          if (float_boxes_may_overlap(box, columns.boxes[column])) meets |= bit;
          if (!Cells::kRowsInRange && tests_in_range(ra, column)) in_range |= bit;
        }
        // This lane's tests: the columns [max(first, lane_first), column_end), in the pass's range.
        const unsigned lane_begin = ::max(first, lane_first);
        std::uint32_t tests = 0;
        if (has_row && lane_begin < column_end) {
          const unsigned upto = column_end - column_begin, from = lane_begin - column_begin;
          tests = (upto == 32 ? ~0u : (1u << upto) - 1u) & ~((1u << from) - 1u);
        }
        if (!Cells::kRowsInRange) tests &= in_range;
        meets &= tests;
        boxes_apart += static_cast<unsigned>(__popc(tests) - __popc(meets));
      }
      // The meetings are numbered across the block (a scan of each lane's
      // count) and dealt out a test a thread, so that every warp decides a
      // quarter of the tile's: a warp's own would leave the block waiting
      // at the next barrier for the warp with the most (in a model of the
      // cells, 1.6 times the mean on cloth_ball and 1.9 on ×4). (test_kernel
      // a step, H100: cloth_ball 0.65 -> 0.59 ms, ×4 2.64 -> 2.60, ×16
      // 21.4 -> 20.5.)
      const unsigned mine = static_cast<unsigned>(__popc(meets));
      unsigned through = mine;  // the meetings of the warp's lanes up to this one
      for (unsigned step = 1; step < 32; step *= 2) {
        const unsigned below = __shfl_up_sync(0xffffffffu, through, step);
        if (lane >= step) through += below;
      }
      if (lane == 31u) warp_meetings[threadIdx.x / 32] = through;
      __syncthreads();
      unsigned total = 0, at = through - mine;  // at: this lane's first meeting's number
      for (unsigned w = 0; w < kTestBlock / 32; ++w) {
        total += warp_meetings[w];
        at += w < threadIdx.x / 32 ? warp_meetings[w] : 0;
      }
      for (unsigned pass = 0; pass < total; pass += kBlockMeetings) {
        for (; meets != 0 && at < pass + kBlockMeetings; ++at) {
          const unsigned column = column_begin + static_cast<unsigned>(__ffs(meets)) - 1;
          meets &= meets - 1;
          block_meeting[at - pass] = static_cast<std::uint16_t>((row << 6) | column);
        }
        __syncthreads();
        const unsigned count = ::min(kBlockMeetings, total - pass);
        for (unsigned base = 0; base < count; base += blockDim.x) {  // the same rounds on every thread
          const bool take = base + threadIdx.x < count;
          detail::warp_list_push(take, take ? block_meeting[base + threadIdx.x] : std::uint16_t{0}, meeting,
                                 meeting_count);
          if (meeting_count >= 32) decide_meeting(32);
        }
        __syncthreads();  // block_meeting is read before the next pass writes it
      }
    } else if (offset >= static_cast<std::int64_t>(row_count)) {
      // Every column after every row: slot s = row * column_count + column,
      // each a test; each round moves it on by the block's size, stepped
      // without dividing.
      const unsigned slots = row_count * column_count;
      const unsigned row_step = blockDim.x / column_count, column_step = blockDim.x % column_count;
      unsigned row = threadIdx.x / column_count, column = threadIdx.x % column_count;
      for (unsigned base = 0; base < slots; base += blockDim.x) {
        run_test(base + threadIdx.x < slots, row, column);
        row += row_step;
        column += column_step;
        if (column >= column_count) {
          column -= column_count;
          ++row;
        }
      }
    } else {
      // A diagonal tile (offset = -d <= 0): row r is item q = r + d of the
      // columns, and its tests are the columns j > q. They are the pairs of
      // the columns numbered row by row (pair_from_index) from row d on: no
      // round is spent on the slots on and below the diagonal.
      const std::uint64_t d = static_cast<std::uint64_t>(-offset), m = column_count;
      auto rows_before = [m](std::uint64_t q) { return q * (2 * m - q - 1) / 2; };
      const std::uint64_t first = rows_before(d);
      const std::uint64_t tests = rows_before(d + row_count < m ? d + row_count : m) - first;
      for (std::uint64_t base = 0; base < tests; base += blockDim.x) {
        const std::uint64_t k = base + threadIdx.x;
        std::uint64_t q = d, j = 0;
        if (k < tests) pair_from_index(m, first + k, q, j);
        run_test(k < tests, static_cast<unsigned>(q - d), static_cast<unsigned>(j));
      }
    }
    if (meeting_count > 0) decide_meeting(meeting_count);
  }
  if (waiting_count > 0) test_waiting(waiting_count);
  if (keeping_count > 0) write_kept(keeping_count);
  detail::warp_count(boxes_apart, &counters[kBoxesApart]);
  detail::warp_count(same_root, &counters[kSameRoot]);
  detail::warp_count(time_slots, &counters[kTimeSlots]);
  detail::warp_count(control_bits, &counters[kControlBits]);
  detail::warp_count(extended, &counters[kExtended]);
  detail::warp_count(fallback, &counters[kFallback]);
  detail::warp_count(passed, &counters[kPassed]);
  detail::warp_count(culls, &counters[kCulled]);
  __syncthreads();
  for (unsigned k = threadIdx.x; k < kHistogramBuckets; k += blockDim.x)
    if (block_histogram[k] != 0) atomicAdd(&histogram[k], block_histogram[k]);
}

__global__ void unpack_pairs_kernel(const std::uint64_t* keys, std::size_t n, int key_bits, TrianglePair* pairs) {
  const std::uint64_t k = thread_item();
  if (k < n) unpack_key(keys[k], key_bits, pairs[k].a, pairs[k].b);
}

/// Sorts the n keys of `keys` (using `spare`, as large, as the sort's other
/// half) and removes duplicates; returns the unique count and sets `unique`
/// to the buffer (keys or spare) that holds them. Leaving the count on the
/// device for the kernels after it to read (one wait a chunk instead of
/// three) gained nothing through snag-scan -m all (H100, median of 3 against
/// the same build: ×16 0.990, ×4 0.998, cloth_ball 1.018 of the time).
std::size_t sort_unique(std::uint64_t* keys, std::uint64_t* spare, std::size_t n, int end_bit, DevicePairs& p,
                        std::uint64_t*& unique, cudaStream_t stream) {
  unique = keys;
  if (n == 0) return 0;
  cub::DoubleBuffer<std::uint64_t> halves(keys, spare);
  radix_sort_keys(halves, n, end_bit, p.temp, stream);
  std::size_t bytes = 0;
  SNAG_CUDA_CHECK(cub::DeviceSelect::Unique(nullptr, bytes, halves.Current(), halves.Alternate(),
                                            p.counters.data() + kCounters, n, stream));
  ensure_scratch(p.temp, bytes);
  bytes = p.temp.size();
  SNAG_CUDA_CHECK(cub::DeviceSelect::Unique(p.temp.data(), bytes, halves.Current(), halves.Alternate(),
                                            p.counters.data() + kCounters, n, stream));
  unsigned long long count = 0;
  SNAG_CUDA_CHECK(cudaMemcpyAsync(&count, p.counters.data() + kCounters, sizeof(count), cudaMemcpyDeviceToHost,
                                  stream));
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
  unique = halves.Alternate();
  return count;
}

/// Splits `range` into consecutive ranges of at most key_room kept tests
/// each, from the histogram of a pass over it (buckets of bucket_width
/// triangles). A bucket over key_room becomes a range of its own, to be
/// split again with narrower buckets; one of one triangle cannot be split.
std::vector<RootRange> split_range(RootRange range, const std::vector<unsigned>& histogram, std::uint32_t bucket_width,
                                   std::size_t key_room) {
  std::vector<RootRange> parts;
  std::uint32_t start = range.first;
  std::uint64_t sum = 0;
  for (std::uint32_t k = 0; k < kHistogramBuckets; ++k) {
    const std::uint64_t lo64 = std::uint64_t{range.first} + std::uint64_t{k} * bucket_width;
    if (lo64 >= range.end) break;
    const auto lo = static_cast<std::uint32_t>(lo64);
    const auto hi = static_cast<std::uint32_t>(std::min<std::uint64_t>(range.end, lo64 + bucket_width));
    const std::uint64_t count = histogram[k];
    if (count > key_room) {
      if (bucket_width == 1)
        throw UsageError("the device memory limit is too small for this scene: triangle " + std::to_string(lo) +
                         " alone has " + std::to_string(count) + " pair tests to keep, a chunk of the limit holds " +
                         std::to_string(key_room) + "; raise the limit (snag-scan --device-memory)");
      if (start < lo) parts.push_back({start, lo});
      parts.push_back({lo, hi});
      start = hi;
      sum = 0;
      continue;
    }
    if (sum + count > key_room) {
      parts.push_back({start, lo});
      start = lo;
      sum = 0;
    }
    sum += count;
  }
  if (start < range.end) parts.push_back({start, range.end});
  return parts;
}

}  // namespace

void order_registrations_on_device(const Leaf* leaves, std::size_t triangle_count, const FloatBox* triangle_boxes,
                                   const DeviceCellLists& lists, const GridSpec& grid, DevicePairs& p,
                                   cudaStream_t stream, const GrowthCheck& check) {
  const std::size_t cells = lists.cells;
  const std::size_t registrations = lists.leaves.size();
  check_growth(check, p.registered.growth_bytes(registrations) + p.tile_members.growth_bytes(registrations) +
                          p.tile_boxes.growth_bytes(registrations) + p.order_keys.growth_bytes(registrations) +
                          p.order_keys_spare.growth_bytes(registrations) + p.order_ids.growth_bytes(registrations) +
                          p.order_ids_spare.growth_bytes(registrations));
  p.registered.resize(registrations);
  p.tile_members.resize(registrations);
  p.tile_boxes.resize(registrations);
  if (registrations == 0) return;
  p.order_keys.resize(registrations);
  p.order_keys_spare.resize(registrations);
  p.order_ids.resize(registrations);
  p.order_ids_spare.resize(registrations);
  const int root_bits = radix_bits(triangle_count > 0 ? triangle_count - 1 : 0);
  registration_keys_kernel<<<blocks_for(registrations), detail::kBlockSize, 0, stream>>>(
      leaves, lists.first.data(), cells, lists.leaves.data(), registrations, root_bits, p.order_keys.data(),
      p.order_ids.data());
  SNAG_CUDA_CHECK_LAUNCH();
  cub::DoubleBuffer<std::uint64_t> keys(p.order_keys.data(), p.order_keys_spare.data());
  cub::DoubleBuffer<std::uint32_t> ids(p.order_ids.data(), p.order_ids_spare.data());
  radix_sort_pairs(keys, ids, registrations, root_bits + radix_bits(cells > 0 ? cells - 1 : 0), p.temp, stream, check);
  gather_registered_kernel<<<blocks_for(registrations), detail::kBlockSize, 0, stream>>>(
      leaves, ids.Current(), keys.Current(), root_bits, lists.cell_ids.data(), grid, triangle_boxes, registrations,
      p.registered.data(), p.tile_members.data(), p.tile_boxes.data());
  SNAG_CUDA_CHECK_LAUNCH();
}

namespace {

/// The pair tests of `cells` cells of `source` (UniformTileCells,
/// AdaptiveTileCells), pass by pass over root ranges (PairChunkPlan);
/// number_rows(range) fills the cells' tests, tiles and rows for a range.
/// As enumerate_pairs_on_device otherwise.
template <class Cells, class NumberRows>
void run_pair_tests(const Cells& source, std::size_t cells, const NumberRows& number_rows, const Dop18* triangle_dops,
                    const FloatBox* triangle_boxes, std::size_t triangle_count, bool count_culled,
                    const ChunkPairs& out, PairChunkPlan& plan, DevicePairs& p, cudaStream_t stream,
                    BroadPhaseStats& stats, const PairChunkVisitor& visit) {
  if (triangle_count > 0xffffffffull || cells > 0xffffffffull)
    throw UsageError("broad phase: more than 2^32 - 1 triangles or cells");
  const auto triangle_end = static_cast<std::uint32_t>(triangle_count);
  p.counters.resize(kCounters + 2);  // and the unique keys' count, the pairs written
  p.histogram.resize(kHistogramBuckets);
  p.cell_tests.resize(cells + 1);
  p.test_total.resize(1);
  p.cell_tiles.resize(cells + 1);
  p.first_tile.resize(cells + 1);
  p.row_begin.resize(cells + 1);
  p.row_end.resize(cells + 1);

  // The tests and tiles of the cells whose smaller root lies in `range`:
  // the tiles numbered cell by cell (first_tile), the tests summed; returns
  // their counts.
  struct Numbered {
    std::uint64_t tests = 0, tiles = 0;
    bool known = false;  ///< read back (else only on the device, in test_total and first_tile[cells])
  };
  // `read`: wait for the counts; else they are read with the first pass's counters.
  auto number_tests = [&](RootRange range, bool read) {
    number_rows(range);
    std::size_t bytes = 0;
    SNAG_CUDA_CHECK(
        cub::DeviceReduce::Sum(nullptr, bytes, p.cell_tests.data(), p.test_total.data(), cells + 1, stream));
    ensure_scratch(p.temp, bytes);
    bytes = p.temp.size();
    SNAG_CUDA_CHECK(
        cub::DeviceReduce::Sum(p.temp.data(), bytes, p.cell_tests.data(), p.test_total.data(), cells + 1, stream));
    exclusive_sum(p.cell_tiles.data(), p.first_tile.data(), cells + 1, p.temp, stream);
    Numbered counts;
    if (!read) return counts;
    ReadBack(stream).add(&counts.tests, p.test_total.data()).add(&counts.tiles, p.first_tile.data() + cells).wait();
    counts.known = true;
    return counts;
  };

  // The key room of this call; buffers a larger room left are given back.
  // With room for the keys kept from an earlier call, the whole set's counts
  // are read back with its first pass's counters instead of before it: the
  // first pass runs in that room, and again in a larger one (below) when
  // more are kept. (For the benchmark's culled keys, the counts size their room.)
  const std::size_t key_room = std::max<std::size_t>(plan.key_room, 1);
  if (p.kept.capacity() > key_room) p.kept.release();
  std::deque<RootRange> todo(plan.ranges.begin(), plan.ranges.end());
  if (todo.empty() || todo.front().first != 0 || todo.back().end != triangle_end) todo.assign(1, {0, triangle_end});
  plan.ranges.clear();
  Numbered whole_set = number_tests({0, triangle_end}, p.kept.capacity() == 0 || count_culled || todo.size() > 1);
  if (p.sorted.capacity() > key_room) p.sorted.release();
  if (p.pairs.capacity() > key_room) p.pairs.release();

  // As many blocks as the device holds at once (the kernel strides).
  int device = 0, sms = 0, per_sm = 0;
  SNAG_CUDA_CHECK(cudaGetDevice(&device));
  SNAG_CUDA_CHECK(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device));
  SNAG_CUDA_CHECK(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, test_kernel<Cells>, kTestBlock, 0));
  const auto resident_blocks = static_cast<std::uint64_t>(std::max(1, sms * std::max(1, per_sm)));
  // A warp's per-thread counts are summed in 32 bits: at most 2^27 rounds, a
  // tile's rounds at most kPairTileSide² / kTestBlock.
  const std::uint64_t rounds_per_tile = (kPairTileSide * kPairTileSide + kTestBlock - 1) / kTestBlock;
  // (Checked after the pass when the counts come with it: its results are then not used.)
  auto check_rounds = [&](const Numbered& whole) {
    if ((whole.tiles / resident_blocks + kTileRun) * rounds_per_tile >= (std::uint64_t{1} << 27))
      throw CudaError("broad phase: too many pair tests for one launch", 0);
  };
  if (whole_set.known) check_rounds(whole_set);

  unsigned long long totals[kCounters] = {};
  std::size_t kept_total = 0, unique_total = 0, culled_total = 0, culled_unique_total = 0, separated_total = 0;
  // Root pairs' keys: the smaller root above the larger (pack_key), in 2·key_bits
  // bits (for 92k triangles 34 bits: 5 radix passes of 8 bits).
  const int key_bits = radix_bits(triangle_count > 0 ? triangle_count - 1 : 0), end_bit = 2 * key_bits;
  const bool once = !out.ascending && end_bit < 64;  // kOnceBit is free
  std::vector<unsigned> histogram(kHistogramBuckets);
  double seconds = 0;
  std::size_t culled_room =
      count_culled ? std::max<std::size_t>(p.culled.capacity(), std::min<std::uint64_t>(whole_set.tests, 1 << 18)) : 0;
  RootRange numbered_range{0, triangle_end};  // the range first_tile and test_total hold now
  Numbered range_counts = whole_set;          // and its tests and tiles
  while (!todo.empty()) {
    const RootRange range = todo.front();
    const std::uint32_t bucket_width =
        std::max<std::uint32_t>(1, (range.end - range.first + kHistogramBuckets - 1) / kHistogramBuckets);
    CudaEvent start, done;
    start.record(stream);
    if (range.first != numbered_range.first || range.end != numbered_range.end) {
      range_counts = number_tests(range, true);
      numbered_range = range;
    }
    const std::uint64_t range_tests = range_counts.tests;
    // Room: for the whole set what the last pass needed, at least a share of
    // the tests; for a planned or split range all of key_room (it was sized
    // to hold it); never more than key_room or the range's tests (when known).
    const bool whole = range.first == 0 && range.end == triangle_end;
    const std::size_t kept_room =
        !range_counts.known
            ? p.kept.capacity()
            : std::min<std::uint64_t>(
                  {key_room, std::max<std::uint64_t>(range_tests, 1),
                   whole ? std::max<std::uint64_t>(p.kept.capacity(), std::min<std::uint64_t>(range_tests, 1 << 20))
                         : key_room});
    p.kept.resize(kept_room);
    p.culled.resize(culled_room);
    p.counters.fill_zero();
    p.histogram.fill_zero();
    unsigned long long counts[kCounters] = {};
    if (range_tests > 0 || !range_counts.known) {
      const std::uint64_t blocks =
          range_counts.known ? std::min<std::uint64_t>((range_counts.tiles + kTileRun - 1) / kTileRun, resident_blocks)
                             : resident_blocks;
      test_kernel<Cells><<<static_cast<unsigned>(blocks), kTestBlock, 0, stream>>>(
          p.first_tile.data(), cells, p.row_begin.data(), p.row_end.data(), source, triangle_dops, triangle_boxes,
          range.first, range.end, bucket_width, key_bits, p.histogram.data(), p.kept.data(), kept_room, once,
          count_culled, p.culled.data(), culled_room, p.counters.data());
      SNAG_CUDA_CHECK_LAUNCH();
      ReadBack read(stream);
      read.add(counts, p.counters.data(), kCounters).add(histogram.data(), p.histogram.data(), kHistogramBuckets);
      if (!range_counts.known)
        read.add(&range_counts.tests, p.test_total.data()).add(&range_counts.tiles, p.first_tile.data() + cells);
      read.wait();
      if (!range_counts.known) {
        range_counts.known = true;
        whole_set = range_counts;
        check_rounds(whole_set);
      }
    }
    if (count_culled && counts[kCulled] > culled_room) {  // the benchmark's culled keys: grow, run again
      culled_room = counts[kCulled];
      continue;
    }
    const std::size_t kept_tests = counts[kKeptOnce] + counts[kKept];
    if (kept_tests > kept_room) {
      if (kept_tests <= key_room) {
        p.kept.resize(kept_tests);  // grow within the room and run again
      } else {
        todo.pop_front();
        const std::vector<RootRange> parts = split_range(range, histogram, bucket_width, key_room);
        if (parts.size() == 1)  // the histogram disagrees with the count: never loop on it
          throw CudaError("broad phase: a chunk of " + std::to_string(range.end - range.first) +
                              " triangles could not be split", 0);
        todo.insert(todo.begin(), parts.begin(), parts.end());
      }
      continue;
    }
    todo.pop_front();
    for (int k = 0; k < kCounters; ++k) totals[k] += counts[k];

    // Sort + unique of the chunk's keys but those kept once (two whole
    // roots', at the front); duplicate root-pair tests counted exactly, as
    // on the CPU (among the culled tests only when their keys were kept).
    const std::size_t kept_once = counts[kKeptOnce], kept_rest = counts[kKept];
    const std::size_t culled_tests = count_culled ? counts[kCulled] : 0;
    p.sorted.resize(std::max(kept_rest, culled_tests));
    std::uint64_t* unique = nullptr;
    culled_unique_total += sort_unique(p.culled.data(), p.sorted.data(), culled_tests, end_bit, p, unique, stream);
    const std::size_t rest_unique =
        sort_unique(p.kept.data() + kept_room - kept_rest, p.sorted.data(), kept_rest, end_bit, p, unique, stream);
    const std::size_t kept_unique = kept_once + rest_unique;
    kept_total += kept_tests;
    culled_total += culled_tests;
    unique_total += kept_unique;
    p.pairs.resize(kept_unique);
    std::size_t pair_count = kept_unique;
    if (out.separation != nullptr) {  // both runs of keys appended to the pairs, those apart left out
      unsigned long long* const written = p.counters.data() + kCounters + 1;
      SNAG_CUDA_CHECK(cudaMemsetAsync(written, 0, sizeof(*written), stream));
      append_unseparated_pairs_on_device(*out.separation, out.triangles, p.kept.data(), kept_once, key_bits,
                                         p.pairs.data(), written, stream);
      append_unseparated_pairs_on_device(*out.separation, out.triangles, unique, rest_unique, key_bits,
                                         p.pairs.data(), written, stream);
      unsigned long long left = 0;
      ReadBack(stream).add(&left, written).wait();
      pair_count = static_cast<std::size_t>(left);
      separated_total += kept_unique - pair_count;
    } else {
      if (kept_once > 0) {
        unpack_pairs_kernel<<<blocks_for(kept_once), detail::kBlockSize, 0, stream>>>(p.kept.data(), kept_once,
                                                                                      key_bits, p.pairs.data());
        SNAG_CUDA_CHECK_LAUNCH();
      }
      if (rest_unique > 0) {
        unpack_pairs_kernel<<<blocks_for(rest_unique), detail::kBlockSize, 0, stream>>>(
            unique, rest_unique, key_bits, p.pairs.data() + kept_once);
        SNAG_CUDA_CHECK_LAUNCH();
      }
    }
    done.record(stream);
    SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
    seconds += static_cast<double>(CudaEvent::elapsed_ms(start, done)) / 1000.0;
    plan.ranges.push_back(range);
    visit(p.pairs.data(), pair_count);
  }
  stats.tests = whole_set.tests;
  stats.culled_by_boxes = totals[kBoxesApart];
  stats.same_root_tests = totals[kSameRoot];
  stats.removed_by_time_slots = totals[kTimeSlots];
  stats.removed_by_control_bits = totals[kControlBits];
  stats.removed_by_extended_control_bits = totals[kExtended];
  stats.fallback_tests = totals[kFallback];
  stats.tests_after_control_bits = totals[kPassed];
  stats.culled_by_dop = totals[kCulled];
  stats.duplicate_root_pair_tests = kept_total - unique_total;
  stats.duplicate_culled_tests = culled_total - culled_unique_total;
  stats.triangle_pairs = unique_total;
  stats.separated_triangle_pairs = separated_total;
  stats.seconds_pairs = seconds;
}

}  // namespace

void enumerate_pairs_on_device(const DeviceCellLists& lists, const GridSpec& grid, const Dop18* triangle_dops,
                               const FloatBox* triangle_boxes, std::size_t triangle_count, bool count_culled,
                               const ChunkPairs& out, PairChunkPlan& plan, DevicePairs& p, cudaStream_t stream,
                               BroadPhaseStats& stats, const PairChunkVisitor& visit) {
  const std::size_t cells = lists.cells;
  const UniformTileCells source{lists.first.data(), lists.cell_ids.data(), p.registered.data(),
                                p.tile_members.data(), p.tile_boxes.data(), grid};
  auto number_rows = [&](RootRange range) {
    chunk_tests_kernel<<<blocks_for(cells + 1), detail::kBlockSize, 0, stream>>>(
        lists.first.data(), cells, p.tile_members.data(), range.first, range.end, p.cell_tests.data(),
        p.cell_tiles.data(), p.row_begin.data(), p.row_end.data());
    SNAG_CUDA_CHECK_LAUNCH();
  };
  run_pair_tests(source, cells, number_rows, triangle_dops, triangle_boxes, triangle_count, count_culled, out, plan,
                 p, stream, stats, visit);
}

void enumerate_adaptive_pairs_on_device(const DeviceAdaptiveCells& tree, const Dop18* triangle_dops,
                                        const FloatBox* triangle_boxes, std::size_t triangle_count, bool count_culled,
                                        const ChunkPairs& out, PairChunkPlan& plan, DevicePairs& p,
                                        cudaStream_t stream, BroadPhaseStats& stats, const PairChunkVisitor& visit) {
  const std::size_t cells = tree.cell_count;
  const AdaptiveTileCells source{tree.cells.data(), tree.members.data(), tree.leaf_dops.data(), tree.depth};
  auto number_rows = [&](RootRange) {
    adaptive_tests_kernel<<<blocks_for(cells + 1), detail::kBlockSize, 0, stream>>>(
        tree.cells.data(), cells, p.cell_tests.data(), p.cell_tiles.data(), p.row_begin.data(), p.row_end.data());
    SNAG_CUDA_CHECK_LAUNCH();
  };
  run_pair_tests(source, cells, number_rows, triangle_dops, triangle_boxes, triangle_count, count_culled, out, plan,
                 p, stream, stats, visit);
}

}  // namespace snag
