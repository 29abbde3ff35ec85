// Cell registration, one radix sort, one duplicate-removing scan on the GPU:
// the CUDA twin of libcd/grid/cell_registration.cpp.
// Grand, "Broad-phase collision detection with CUDA", GPU Gems 3 ch. 32, 2007
// (cell-object array, radix sort by cell id); Wong, Leach, Zambetta, virtual
// subdivision chapter, section 5.3.3 (one sort, one scan, home priority).
// Primitives: CUB DeviceScan, DeviceRadixSort (stable), DeviceSelect, DeviceRunLengthEncode.
#include "libcd/cuda/cell_registration.cuh"

#include <cub/device/device_run_length_encode.cuh>
#include <cub/device/device_scan.cuh>
#include <cub/device/device_select.cuh>

#include <algorithm>

#include "libcd/cuda/device_scan.cuh"
#include "libcd/cuda/launch.cuh"

namespace snag {
namespace {

using detail::blocks_for;
using detail::ensure_scratch;
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

/// The scan: the head of each run of one unit in one cell marks its first
/// home registration, else itself (as the CPU's); keep is zeroed before.
__global__ void keep_kernel(const Leaf* leaves, GridSpec grid, const std::uint64_t* keys, const std::uint32_t* values,
                            std::size_t total, std::uint8_t* keep) {
  const std::uint64_t i = thread_item();
  if (i >= total) return;
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
  keep[chosen] = 1;
}

__global__ void first_kernel(std::uint64_t* run_length, std::size_t cells) {
  // run_length[cells] = 0 so that the exclusive sum's last entry is the total.
  if (thread_item() == 0) run_length[cells] = 0;
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
  check_growth(check, g.block_count.growth_bytes(n + 1) + g.offset.growth_bytes(n + 1));
  g.block_count.resize(n + 1);
  g.offset.resize(n + 1);
  block_count_kernel<<<blocks_for(n + 1), detail::kBlockSize, 0, stream>>>(leaves, n, g.block_count.data());
  SNAG_CUDA_CHECK_LAUNCH();
  exclusive_sum(g.block_count.data(), g.offset.data(), n + 1, g.temp, stream, check);
  std::uint64_t total = 0;
  SNAG_CUDA_CHECK(
      cudaMemcpyAsync(&total, g.offset.data() + n, sizeof(std::uint64_t), cudaMemcpyDeviceToHost, stream));
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
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

  // One scan removing duplicate registrations (home priority).
  check_growth(check, g.keep.growth_bytes(total));
  g.keep.resize(total);
  g.keep.fill_zero();
  keep_kernel<<<blocks_for(total), detail::kBlockSize, 0, stream>>>(leaves, grid, g.keys_sorted.data(),
                                                                    g.values_sorted.data(), total, g.keep.data());
  SNAG_CUDA_CHECK_LAUNCH();

  // Compaction of keys and leaf ids.
  check_growth(check, g.kept_keys.growth_bytes(total) + g.leaves.growth_bytes(total) + g.selected.growth_bytes(2));
  g.kept_keys.resize(total);
  g.leaves.resize(total);
  g.selected.resize(2);
  std::size_t bytes = 0;
  SNAG_CUDA_CHECK(cub::DeviceSelect::Flagged(nullptr, bytes, g.keys_sorted.data(), g.keep.data(), g.kept_keys.data(),
                                             g.selected.data(), total, stream));
  ensure_scratch(g.temp, bytes, check);
  bytes = g.temp.size();
  SNAG_CUDA_CHECK(cub::DeviceSelect::Flagged(g.temp.data(), bytes, g.keys_sorted.data(), g.keep.data(),
                                             g.kept_keys.data(), g.selected.data(), total, stream));
  bytes = 0;
  SNAG_CUDA_CHECK(cub::DeviceSelect::Flagged(nullptr, bytes, g.values_sorted.data(), g.keep.data(), g.leaves.data(),
                                             g.selected.data(), total, stream));
  ensure_scratch(g.temp, bytes, check);
  bytes = g.temp.size();
  SNAG_CUDA_CHECK(cub::DeviceSelect::Flagged(g.temp.data(), bytes, g.values_sorted.data(), g.keep.data(),
                                             g.leaves.data(), g.selected.data(), total, stream));
  unsigned long long kept = 0;
  g.selected.download(&kept, 1);
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
  counts.kept = kept;
  counts.duplicates_removed = total - kept;
  g.leaves.resize(kept);

  // The cells: runs of equal cell id, and their offsets.
  check_growth(check, g.cell_ids.growth_bytes(kept) + g.run_length.growth_bytes(kept + 1));
  g.cell_ids.resize(kept);
  g.run_length.resize(kept + 1);
  bytes = 0;
  SNAG_CUDA_CHECK(cub::DeviceRunLengthEncode::Encode(nullptr, bytes, g.kept_keys.data(), g.cell_ids.data(),
                                                     g.run_length.data(), g.selected.data() + 1, kept, stream));
  ensure_scratch(g.temp, bytes, check);
  bytes = g.temp.size();
  SNAG_CUDA_CHECK(cub::DeviceRunLengthEncode::Encode(g.temp.data(), bytes, g.kept_keys.data(), g.cell_ids.data(),
                                                     g.run_length.data(), g.selected.data() + 1, kept, stream));
  unsigned long long cells = 0;
  SNAG_CUDA_CHECK(cudaMemcpyAsync(&cells, g.selected.data() + 1, sizeof(cells), cudaMemcpyDeviceToHost, stream));
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
  g.cells = cells;
  g.cell_ids.resize(cells);
  first_kernel<<<1, 1, 0, stream>>>(g.run_length.data(), cells);
  SNAG_CUDA_CHECK_LAUNCH();
  check_growth(check, g.first.growth_bytes(cells + 1));
  g.first.resize(cells + 1);
  exclusive_sum(g.run_length.data(), g.first.data(), cells + 1, g.temp, stream, check);
}

}  // namespace snag
