// Cell registration, one radix sort, one duplicate-removing scan on the GPU:
// the CUDA twin of libcd/grid/cell_registration.cpp.
// Grand, "Broad-phase collision detection with CUDA", GPU Gems 3 ch. 32, 2007
// (cell-object array, radix sort by cell id); Wong, Leach, Zambetta, virtual
// subdivision chapter, section 5.3.3 (one sort, one scan, home priority).
// Primitives: CUB DeviceScan, DeviceRadixSort (stable).
#include "libcd/cuda/cell_registration.cuh"

#include <cub/device/device_scan.cuh>

#include <algorithm>

#include "libcd/cuda/device_scan.cuh"
#include "libcd/cuda/launch.cuh"

namespace snag {
namespace {

using detail::blocks_for;
using detail::exclusive_scan;
using detail::exclusive_sum;
using detail::radix_bits;
using detail::radix_sort_pairs;
using detail::thread_item;

__global__ void block_count_kernel(const Leaf* leaves, std::size_t n, std::uint64_t* count) {
  const std::uint64_t i = thread_item();
  if (i < n) count[i] = block_cell_count(leaves[i].cells.block);
  else if (i == n) count[i] = 0;
}

__global__ void fill_kernel(const Leaf* leaves, std::size_t n, GridSpec grid, const std::uint64_t* offset,
                            std::uint64_t* keys, std::uint32_t* values) {
  const std::uint64_t i = thread_item();
  if (i >= n) return;
  const CellBlock b = leaves[i].cells.block;
  const std::uint64_t k_end = block_cell_count(b);
  for (std::uint64_t k = 0; k < k_end; ++k) {
    keys[offset[i] + k] = grid_cell_id(grid, block_cell(b, k));
    values[offset[i] + k] = static_cast<std::uint32_t>(i);
  }
}

struct AddRegistrationTallies {
  __device__ RegistrationTally operator()(const RegistrationTally& a, const RegistrationTally& b) const {
    return {a.kept + b.kept, a.cells + b.cells};
  }
};

/// The scan: the head of each run of one unit in one cell keeps its first
/// home registration, else itself (as the CPU's); and each registration
/// that starts a run of one cell id counts a cell. `tally` is zeroed before;
/// a run's head writes the kept count, each registration its own cell count
/// (other words: no two threads write one).
__global__ void keep_kernel(const Leaf* leaves, GridSpec grid, const std::uint64_t* keys, const std::uint32_t* values,
                            std::size_t total, RegistrationTally* tally) {
  const std::uint64_t i = thread_item();
  if (i >= total) return;
  if (i == 0 || keys[i] != keys[i - 1]) tally[i].cells = 1;
  auto same_run = [&](std::uint64_t p, std::uint64_t q) {
    return keys[p] == keys[q] && same_unit(leaves[values[p]].triangle, leaves[values[q]].triangle);
  };
  if (i > 0 && same_run(i, i - 1)) return;  // not the head of a run
  std::uint64_t chosen = i;
  for (std::uint64_t j = i; j < total && same_run(j, i); ++j) {
    if (grid_cell_id(grid, leaves[values[j]].cells.home) == keys[j]) {
      chosen = j;
      break;
    }
  }
  tally[chosen].kept = 1;
}

/// The cell lists from the scanned tallies of `total` sorted registrations
/// (each cell id has a kept registration: every run of one unit keeps one):
/// the kept leaf ids in order, each cell's id and its first kept leaf, and
/// first[cells] = the kept count.
__global__ void compact_kernel(const std::uint64_t* keys, const std::uint32_t* values, std::size_t total,
                               const RegistrationTally* offset, std::uint32_t* leaves, std::uint64_t* cell_ids,
                               std::uint64_t* first) {
  const std::uint64_t i = thread_item();
  if (i > total) return;
  const RegistrationTally at = offset[i];
  if (i == total) {
    first[at.cells] = at.kept;
    return;
  }
  const RegistrationTally next = offset[i + 1];
  if (next.kept != at.kept) leaves[at.kept] = values[i];
  if (next.cells != at.cells) {
    cell_ids[at.cells] = keys[i];
    first[at.cells] = at.kept;
  }
}

}  // namespace

void register_leaves_on_device(const Leaf* leaves, std::size_t n, const GridSpec& grid, DeviceCellLists& g,
                               cudaStream_t stream, RegistrationCounts& counts, const GrowthCheck& check) {
  counts = RegistrationCounts{};
  g.cells = 0;
  g.first.resize(1);
  g.first.fill_zero();
  g.cell_ids.resize(0);
  g.leaves.resize(0);
  if (n == 0) return;

  // Registration: one item per cell of each leaf's block.
  check_growth(check, g.offset.growth_bytes(n + 1));
  g.offset.resize(n + 1);
  block_count_kernel<<<blocks_for(n + 1), detail::kBlockSize, 0, stream>>>(leaves, n, g.offset.data());
  SNAG_CUDA_CHECK_LAUNCH();
  exclusive_sum(g.offset.data(), g.offset.data(), n + 1, g.temp, stream, check);
  std::uint64_t total = 0;
  ReadBack(stream).add(&total, g.offset.data() + n).wait();
  counts.registrations = total;
  counts.home = n;
  counts.phantom = total - n;

  check_growth(check, g.keys.growth_bytes(total) + g.values.growth_bytes(total) + g.keys_sorted.growth_bytes(total) +
                          g.values_sorted.growth_bytes(total));
  g.keys.resize(total);
  g.values.resize(total);
  g.keys_sorted.resize(total);
  g.values_sorted.resize(total);
  fill_kernel<<<blocks_for(n), detail::kBlockSize, 0, stream>>>(leaves, n, grid, g.offset.data(), g.keys.data(),
                                                               g.values.data());
  SNAG_CUDA_CHECK_LAUNCH();

  // One stable sort by cell id, over the bits a cell id of this grid can use.
  const std::uint64_t max_id = static_cast<std::uint64_t>(grid.dims[0]) * static_cast<std::uint64_t>(grid.dims[1]) *
                                   static_cast<std::uint64_t>(grid.dims[2]) -
                               1;
  radix_sort_pairs(g.keys.data(), g.keys_sorted.data(), g.values.data(), g.values_sorted.data(), total,
                   radix_bits(max_id), g.temp, stream, check);

  // One scan removing duplicate registrations (home priority) and counting
  // cells, one read of the counts, one pass writing the lists.
  check_growth(check, g.tally.growth_bytes(total + 1));
  g.tally.resize(total + 1);
  g.tally.fill_zero();
  keep_kernel<<<blocks_for(total), detail::kBlockSize, 0, stream>>>(leaves, grid, g.keys_sorted.data(),
                                                                    g.values_sorted.data(), total, g.tally.data());
  SNAG_CUDA_CHECK_LAUNCH();
  exclusive_scan(g.tally.data(), g.tally.data(), total + 1, AddRegistrationTallies{}, g.temp, stream, check);
  RegistrationTally kept;
  ReadBack(stream).add(&kept, g.tally.data() + total).wait();
  counts.kept = kept.kept;
  counts.duplicates_removed = total - kept.kept;
  check_growth(check, g.leaves.growth_bytes(kept.kept) + g.cell_ids.growth_bytes(kept.cells) +
                          g.first.growth_bytes(kept.cells + 1));
  g.leaves.resize(kept.kept);
  g.cell_ids.resize(kept.cells);
  g.first.resize(kept.cells + 1);
  g.cells = kept.cells;
  compact_kernel<<<blocks_for(total + 1), detail::kBlockSize, 0, stream>>>(g.keys_sorted.data(), g.values_sorted.data(),
                                                                           total, g.tally.data(), g.leaves.data(),
                                                                           g.cell_ids.data(), g.first.data());
  SNAG_CUDA_CHECK_LAUNCH();
}

}  // namespace snag
