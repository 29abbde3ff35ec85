// The adaptive grid's hierarchy on the GPU: the CUDA twin of
// libcd/grid/adaptive_cells.cpp, level by level with one stable radix sort,
// one run-length encoding and two prefix sums each (adaptive_cells.cuh).
// Primitives: CUB DeviceRadixSort (stable), DeviceRunLengthEncode, DeviceScan.
#include "libcd/cuda/adaptive_cells.cuh"

#include <cub/device/device_run_length_encode.cuh>

#include <algorithm>
#include <string>

#include "libcd/core/error.hpp"
#include "libcd/cuda/device_scan.cuh"
#include "libcd/cuda/launch.cuh"
#include "libcd/grid/pair_index.hpp"

namespace snag {

namespace {

using detail::blocks_for;
using detail::ensure_scratch;
using detail::exclusive_scan;
using detail::exclusive_sum;
using detail::radix_bits;
using detail::radix_sort_pairs;
using detail::thread_item;

struct AddRegistrationCounts {
  __device__ RegistrationFate operator()(const RegistrationFate& a, const RegistrationFate& b) const {
    return {a.stuck + b.stuck, a.children + b.children};
  }
};

struct AddCellFates {
  __device__ CellFate operator()(const CellFate& a, const CellFate& b) const {
    return {a.crowded + b.crowded, a.cells + b.cells, a.members + b.members};
  }
};

/// The leaves' fine blocks and DOPs, and the cells of each one's level-0
/// block (count[n] = 0 for the prefix sum).
__global__ void fine_blocks_kernel(const Leaf* leaves, std::size_t n, GridSpec grid, int depth, FineBlock* blocks,
                                   Dop18* dops, std::uint64_t* count) {
  const std::uint64_t i = thread_item();
  if (i > n) return;
  if (i == n) {
    count[i] = 0;
    return;
  }
  const FineBlock block = fine_block_of(grid, depth, leaves[i].dop);
  blocks[i] = block;
  dops[i] = leaves[i].dop;
  count[i] = block_cell_count(block_at_level(block, depth, 0));
}

/// Level 0: every leaf in every uniform-grid cell of its block, keyed by cell
/// id, leaf by leaf (so that a stable sort by key orders them by (cell, leaf)).
__global__ void grid_registrations_kernel(const FineBlock* blocks, std::size_t n, GridSpec grid, int depth,
                                          const std::uint64_t* offset, std::uint64_t* keys, std::uint32_t* values) {
  const std::uint64_t i = thread_item();
  if (i >= n) return;
  const CellBlock b = block_at_level(blocks[i], depth, 0);
  const std::uint64_t k_end = block_cell_count(b);
  for (std::uint64_t k = 0; k < k_end; ++k) {
    keys[offset[i] + k] = grid_cell_id(grid, block_cell(b, k));
    values[offset[i] + k] = static_cast<std::uint32_t>(i);
  }
}

/// Each cell's coordinates at `level`: from its id at level 0, else from its
/// parent (key / 8, an index into the crowded cells above) and octant (key % 8).
__global__ void cell_coord_kernel(const std::uint64_t* run_keys, std::size_t runs, GridSpec grid, int level,
                                  const CellCoord* parents, CellCoord* coord) {
  const std::uint64_t c = thread_item();
  if (c >= runs) return;
  const std::uint64_t key = run_keys[c];
  coord[c] = level == 0 ? grid_cell_coord(grid, key) : child_cell(parents[key >> 3], static_cast<unsigned>(key & 7));
}

/// The block of a leaf at the children's level, when the leaf goes down into
/// them: a crowded cell (more than cell_limit members, above the deepest
/// level) and a block that spans at most two children per axis.
struct Descent {
  bool down = false;
  CellBlock child_block;
};

__device__ Descent descent(const FineBlock& block, int depth, int level, std::uint64_t members, std::uint64_t cell_limit) {
  Descent d;
  if (members <= cell_limit || level == depth) return d;
  d.child_block = block_at_level(block, depth, level + 1);
  d.down = fits_two_per_axis(d.child_block);
  return d;
}

/// Per registration: does its leaf stay, and how many children does it go into.
__global__ void classify_kernel(const std::uint64_t* run_first, std::size_t runs, const std::uint32_t* values,
                                std::size_t total, const FineBlock* blocks, const CellCoord* coord, int depth,
                                int level, std::uint64_t cell_limit, RegistrationFate* counts) {
  const std::uint64_t r = thread_item();
  if (r > total) return;
  if (r == total) {
    counts[r] = {0, 0};
    return;
  }
  const std::uint64_t c = cell_of_work_item(run_first, runs, r);
  const Descent d = descent(blocks[values[r]], depth, level, run_first[c + 1] - run_first[c], cell_limit);
  std::uint64_t children = 0;
  if (d.down)
    for (unsigned octant = 0; octant < 8; ++octant) children += block_contains(d.child_block, child_cell(coord[c], octant));
  counts[r] = {d.down ? 0u : 1u, children};
}

/// Per cell of the level: crowded or final, test cell or not; the stuck
/// registrations of crowded cells are counted (one atomic per warp).
__global__ void cell_counts_kernel(const std::uint64_t* run_first, std::size_t runs, const RegistrationFate* reg_offset,
                                   int depth, int level, std::uint64_t cell_limit, CellFate* counts,
                                   unsigned long long* stuck_in_crowded) {
  const std::uint64_t c = thread_item();
  unsigned stuck_here = 0;
  if (c < runs) {
    const std::uint64_t begin = run_first[c], end = run_first[c + 1], n = end - begin;
    const std::uint64_t stuck = reg_offset[end].stuck - reg_offset[begin].stuck;
    const bool crowded = n > cell_limit && level < depth;
    const bool tested = stuck >= 1 && n >= 2;
    counts[c] = {crowded ? 1u : 0u, tested ? 1u : 0u, tested ? n : 0};
    if (crowded) stuck_here = static_cast<unsigned>(stuck);
  } else if (c == runs) {
    counts[c] = {0, 0, 0};
  }
  detail::warp_count(stuck_here, stuck_in_crowded);
}

/// Per cell: its test cell (after `cell_base`, members after `member_base`)
/// and its place among the next level's parents.
__global__ void emit_cells_kernel(const std::uint64_t* run_first, std::size_t runs, const RegistrationFate* reg_offset,
                                  const CellFate* counts, const CellFate* offset, const CellCoord* coord,
                                  int level, TestCell* cells, std::uint64_t member_base, CellCoord* next_parents) {
  const std::uint64_t c = thread_item();
  if (c >= runs) return;
  if (counts[c].cells != 0) {
    const std::uint64_t begin = run_first[c], end = run_first[c + 1];
    TestCell cell;
    cell.first = member_base + offset[c].members;
    cell.count = static_cast<std::uint32_t>(end - begin);
    cell.stuck = static_cast<std::uint32_t>(reg_offset[end].stuck - reg_offset[begin].stuck);
    cell.coord = coord[c];
    cell.level = level;
    cells[offset[c].cells] = cell;
  }
  if (counts[c].crowded != 0) next_parents[offset[c].crowded] = coord[c];
}

/// Per registration: its leaf's place among its test cell's members (stuck
/// ones first, each part in leaf order) and its registrations in the children.
__global__ void emit_registrations_kernel(const std::uint64_t* run_first, std::size_t runs, const std::uint32_t* values,
                                          std::size_t total, const FineBlock* blocks,
                                          const RegistrationFate* reg_offset, const CellFate* counts,
                                          const CellFate* offset, const CellCoord* coord, int depth, int level,
                                          std::uint64_t cell_limit, std::uint32_t* members, std::uint64_t* next_keys,
                                          std::uint32_t* next_values) {
  const std::uint64_t r = thread_item();
  if (r >= total) return;
  const std::uint64_t c = cell_of_work_item(run_first, runs, r);
  const std::uint64_t begin = run_first[c], end = run_first[c + 1];
  const std::uint32_t leaf = values[r];
  const FineBlock& block = blocks[leaf];
  const bool stuck = reg_offset[r + 1].stuck != reg_offset[r].stuck;
  if (counts[c].cells != 0) {
    const std::uint64_t stuck_before = reg_offset[r].stuck - reg_offset[begin].stuck;
    const std::uint64_t cell_stuck = reg_offset[end].stuck - reg_offset[begin].stuck;
    const std::uint64_t position = stuck ? stuck_before : cell_stuck + (r - begin) - stuck_before;
    members[offset[c].members + position] = leaf;
  }
  if (stuck) return;
  const Descent d = descent(block, depth, level, end - begin, cell_limit);
  std::uint64_t at = reg_offset[r].children;
  for (unsigned octant = 0; octant < 8; ++octant) {
    if (!block_contains(d.child_block, child_cell(coord[c], octant))) continue;
    next_keys[at] = offset[c].crowded * 8 + octant;
    next_values[at] = leaf;
    ++at;
  }
}

/// Sort keys of the members, cell by cell: (test cell, stuck or pushed, root).
__global__ void member_keys_kernel(const TestCell* cells, std::size_t cell_count, const std::uint32_t* member_leaves,
                                   std::size_t member_count, const Leaf* leaves, std::uint64_t* keys) {
  const std::uint64_t m = thread_item();
  if (m >= member_count) return;
  std::uint64_t lo = 0, hi = cell_count;  // the cell c with cells[c].first <= m < its end
  while (hi - lo > 1) {
    const std::uint64_t mid = lo + (hi - lo) / 2;
    if (cells[mid].first <= m) lo = mid; else hi = mid;
  }
  const std::uint64_t pushed = m - cells[lo].first >= cells[lo].stuck ? 1 : 0;
  keys[m] = (lo << 33) | (pushed << 32) | leaves[member_leaves[m]].triangle.root;
}

/// The members' records, from their leaves.
__global__ void member_records_kernel(const std::uint32_t* member_leaves, std::size_t count, const Leaf* leaves,
                                      const FineBlock* blocks, AdaptiveMember* members) {
  const std::uint64_t m = thread_item();
  if (m >= count) return;
  const std::uint32_t leaf = member_leaves[m];
  const VirtualTriangle& t = leaves[leaf].triangle;
  const FloatBox box = float_box_of(leaves[leaf].dop);
  members[m] = AdaptiveMember{t.root, t.slot_depth, t.slot_index, leaf, blocks[leaf],
                              {box.lo[0], box.lo[1], box.lo[2]}, {box.hi[0], box.hi[1], box.hi[2]}};
}

}  // namespace

std::size_t DeviceAdaptiveCells::scratch_bytes() const {
  return cells_spare.capacity_bytes() + member_leaves.capacity_bytes() + member_leaves_spare.capacity_bytes() +
         keys.capacity_bytes() + keys_sorted.capacity_bytes() + run_keys.capacity_bytes() + run_length.capacity_bytes() +
         run_first.capacity_bytes() + values.capacity_bytes() + values_sorted.capacity_bytes() +
         run_coord.capacity_bytes() + parents.capacity_bytes() + next_parents.capacity_bytes() +
         reg_counts.capacity_bytes() + reg_offset.capacity_bytes() + cell_counts.capacity_bytes() +
         cell_offset.capacity_bytes() + counters.capacity_bytes() + temp.capacity_bytes();
}

void DeviceAdaptiveCells::release_scratch() {
  cells_spare.release();
  member_leaves.release();
  member_leaves_spare.release();
  for (DeviceBuffer<std::uint64_t>* b : {&keys, &keys_sorted, &run_keys, &run_length, &run_first}) b->release();
  values.release();
  values_sorted.release();
  for (DeviceBuffer<CellCoord>* b : {&run_coord, &parents, &next_parents}) b->release();
  reg_counts.release();
  reg_offset.release();
  cell_counts.release();
  cell_offset.release();
  counters.release();
  temp.release();
}

void build_adaptive_cells_on_device(const Leaf* leaves, std::size_t leaf_count, const GridSpec& grid, int max_depth,
                                    std::size_t cell_limit, DeviceAdaptiveCells& out, cudaStream_t stream,
                                    const GrowthCheck& check) {
  if (leaf_count > 0xffffffffull) throw UsageError("broad phase: more than 2^32 - 1 leaf triangles");
  out.depth = std::clamp(max_depth, 0, kMaxAdaptiveDepth);
  const int depth = out.depth;
  cell_limit = std::max<std::size_t>(cell_limit, 1);
  out.cell_count = out.member_count = 0;
  out.registrations = out.cells_subdivided = out.stuck_registrations = 0;
  out.deepest_level = 0;
  auto grow = [&](auto& buffer, std::size_t count) {
    check_growth(check, buffer.growth_bytes(count));
    buffer.resize(count);
  };
  grow(out.blocks, leaf_count);
  grow(out.leaf_dops, leaf_count);
  grow(out.counters, 1);
  if (leaf_count == 0) return;

  // Level 0: the leaves' fine blocks, and their registrations in the grid.
  grow(out.run_length, leaf_count + 1);
  grow(out.run_first, leaf_count + 1);
  fine_blocks_kernel<<<blocks_for(leaf_count + 1), detail::kBlockSize, 0, stream>>>(
      leaves, leaf_count, grid, depth, out.blocks.data(), out.leaf_dops.data(), out.run_length.data());
  SNAG_CUDA_CHECK_LAUNCH();
  exclusive_sum(out.run_length.data(), out.run_first.data(), leaf_count + 1, out.temp, stream, check);
  std::uint64_t total = 0;
  SNAG_CUDA_CHECK(cudaMemcpyAsync(&total, out.run_first.data() + leaf_count, sizeof(total), cudaMemcpyDeviceToHost,
                                  stream));
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
  grow(out.keys, total);
  grow(out.values, total);
  grid_registrations_kernel<<<blocks_for(leaf_count), detail::kBlockSize, 0, stream>>>(
      out.blocks.data(), leaf_count, grid, depth, out.run_first.data(), out.keys.data(), out.values.data());
  SNAG_CUDA_CHECK_LAUNCH();

  const std::uint64_t max_cell_id = static_cast<std::uint64_t>(grid.dims[0]) *
                                        static_cast<std::uint64_t>(grid.dims[1]) *
                                        static_cast<std::uint64_t>(grid.dims[2]) -
                                    1;
  std::uint64_t max_key = max_cell_id;
  for (int level = 0; total > 0; ++level) {
    out.registrations += total;
    out.deepest_level = level;

    // The level's registrations by (key, leaf): one stable sort by key.
    grow(out.keys_sorted, total);
    grow(out.values_sorted, total);
    radix_sort_pairs(out.keys.data(), out.keys_sorted.data(), out.values.data(), out.values_sorted.data(), total,
                     radix_bits(max_key), out.temp, stream, check);

    // Its cells: runs of one key, their first registrations and coordinates.
    grow(out.run_keys, total);
    grow(out.run_length, total + 1);
    std::size_t bytes = 0;
    SNAG_CUDA_CHECK(cub::DeviceRunLengthEncode::Encode(nullptr, bytes, out.keys_sorted.data(), out.run_keys.data(),
                                                       out.run_length.data(), out.counters.data(), total, stream));
    ensure_scratch(out.temp, bytes, check);
    bytes = out.temp.size();
    SNAG_CUDA_CHECK(cub::DeviceRunLengthEncode::Encode(out.temp.data(), bytes, out.keys_sorted.data(),
                                                       out.run_keys.data(), out.run_length.data(), out.counters.data(),
                                                       total, stream));
    unsigned long long runs = 0;
    out.counters.download(&runs, 1);
    SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
    SNAG_CUDA_CHECK(cudaMemsetAsync(out.run_length.data() + runs, 0, sizeof(std::uint64_t), stream));
    grow(out.run_first, runs + 1);
    exclusive_sum(out.run_length.data(), out.run_first.data(), runs + 1, out.temp, stream, check);
    grow(out.run_coord, runs);
    cell_coord_kernel<<<blocks_for(runs), detail::kBlockSize, 0, stream>>>(out.run_keys.data(), runs, grid, level,
                                                                          out.parents.data(), out.run_coord.data());
    SNAG_CUDA_CHECK_LAUNCH();

    // Who stays and who goes down; the cells' kinds; where everything goes.
    grow(out.reg_counts, total + 1);
    grow(out.reg_offset, total + 1);
    classify_kernel<<<blocks_for(total + 1), detail::kBlockSize, 0, stream>>>(
        out.run_first.data(), runs, out.values_sorted.data(), total, out.blocks.data(), out.run_coord.data(), depth,
        level, cell_limit, out.reg_counts.data());
    SNAG_CUDA_CHECK_LAUNCH();
    exclusive_scan(out.reg_counts.data(), out.reg_offset.data(), total + 1, AddRegistrationCounts{}, out.temp, stream,
                   check);
    grow(out.cell_counts, runs + 1);
    grow(out.cell_offset, runs + 1);
    out.counters.fill_zero();
    cell_counts_kernel<<<blocks_for(runs + 1), detail::kBlockSize, 0, stream>>>(
        out.run_first.data(), runs, out.reg_offset.data(), depth, level, cell_limit, out.cell_counts.data(),
        out.counters.data());
    SNAG_CUDA_CHECK_LAUNCH();
    exclusive_scan(out.cell_counts.data(), out.cell_offset.data(), runs + 1, AddCellFates{}, out.temp, stream,
                   check);
    CellFate level_counts{};
    RegistrationFate reg_totals{};
    unsigned long long stuck_in_crowded = 0;
    ReadBack(stream)
        .add(&level_counts, out.cell_offset.data() + runs)
        .add(&reg_totals, out.reg_offset.data() + total)
        .add(&stuck_in_crowded, out.counters.data())
        .wait();
    out.cells_subdivided += level_counts.crowded;
    out.stuck_registrations += stuck_in_crowded;

    // The level's test cells and members after the earlier levels'; the
    // crowded cells; the next level's registrations (in keys and values,
    // which the sort has read).
    grow_keeping(out.cells, out.cells_spare, out.cell_count, out.cell_count + level_counts.cells, check);
    grow_keeping(out.member_leaves, out.member_leaves_spare, out.member_count,
                 out.member_count + level_counts.members, check);
    grow(out.next_parents, level_counts.crowded);
    grow(out.keys, reg_totals.children);
    grow(out.values, reg_totals.children);
    emit_cells_kernel<<<blocks_for(runs), detail::kBlockSize, 0, stream>>>(
        out.run_first.data(), runs, out.reg_offset.data(), out.cell_counts.data(), out.cell_offset.data(),
        out.run_coord.data(), level, out.cells.data() + out.cell_count, out.member_count, out.next_parents.data());
    SNAG_CUDA_CHECK_LAUNCH();
    emit_registrations_kernel<<<blocks_for(total), detail::kBlockSize, 0, stream>>>(
        out.run_first.data(), runs, out.values_sorted.data(), total, out.blocks.data(), out.reg_offset.data(),
        out.cell_counts.data(), out.cell_offset.data(), out.run_coord.data(), depth, level, cell_limit,
        out.member_leaves.data() + out.member_count, out.keys.data(), out.values.data());
    SNAG_CUDA_CHECK_LAUNCH();
    out.cell_count += level_counts.cells;
    out.member_count += level_counts.members;
    std::swap(out.parents, out.next_parents);
    total = reg_totals.children;
    max_key = level_counts.crowded > 0 ? level_counts.crowded * 8 - 1 : 0;
  }

  // Each cell's stuck and pushed members by root (stable: leaf order among
  // leaves of one root), so that a tile's rows and columns cover few roots
  // and a pass over a root range skips the tiles that hold none of its tests;
  // then their records, once, in exactly the room they need.
  const std::size_t n = out.member_count;
  grow(out.members, n);
  if (n == 0) return;
  grow(out.keys, n);
  grow(out.keys_sorted, n);
  grow(out.values_sorted, n);
  member_keys_kernel<<<blocks_for(n), detail::kBlockSize, 0, stream>>>(
      out.cells.data(), out.cell_count, out.member_leaves.data(), n, leaves, out.keys.data());
  SNAG_CUDA_CHECK_LAUNCH();
  radix_sort_pairs(out.keys.data(), out.keys_sorted.data(), out.member_leaves.data(), out.values_sorted.data(), n,
                   33 + radix_bits(out.cell_count - 1), out.temp, stream, check);
  member_records_kernel<<<blocks_for(n), detail::kBlockSize, 0, stream>>>(out.values_sorted.data(), n, leaves,
                                                                         out.blocks.data(), out.members.data());
  SNAG_CUDA_CHECK_LAUNCH();
}

}  // namespace snag
