// One test per thread, then sort + unique of root pairs, on the GPU.
// Pabst, Koch, Straßer, "Fast and scalable CPU/GPU collision detection for
// rigid and deformable surfaces", CGF 2010; Fan, Wang, Dong, Sun, "Efficient
// GPU-based collision detection for deformable models", 2011 (one thread per
// test, prefix sums); Grand, GPU Gems 3 ch. 32 and the virtual subdivision
// chapter, section 5.3.3 (control bits, extended control bits).
// Primitives: CUB DeviceScan, DeviceRadixSort, DeviceSelect::Unique.
#include "libcd/cuda/pair_enumeration.cuh"

#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>
#include <cub/device/device_select.cuh>

#include <algorithm>

#include "libcd/cuda/launch.cuh"
#include "libcd/grid/control_bits.hpp"
#include "libcd/grid/pair_index.hpp"

namespace snag {
namespace {

using detail::blocks_for;
using detail::thread_item;

/// Counter slots of the test kernel.
enum Counter { kSameRoot, kTimeSlots, kControlBits, kExtended, kFallback, kPassed, kKept, kCulled, kCounters };

void ensure(DeviceBuffer<unsigned char>& temp, std::size_t bytes) {
  if (temp.size() < std::max<std::size_t>(bytes, 1)) temp.resize(std::max<std::size_t>(bytes, 1));
}

__global__ void cell_tests_kernel(const std::uint64_t* first, std::size_t cells, std::uint64_t* tests) {
  const std::uint64_t c = thread_item();
  if (c < cells) tests[c] = pair_count(first[c + 1] - first[c]);
  else if (c == cells) tests[c] = 0;
}

__global__ void gather_registered_kernel(const Leaf* leaves, const std::uint32_t* cell_leaves, std::size_t count,
                                         RegisteredLeaf* out) {
  const std::uint64_t r = thread_item();
  if (r >= count) return;
  const Leaf& leaf = leaves[cell_leaves[r]];
  out[r] = RegisteredLeaf{leaf.triangle, leaf.cells};
}

/// The tests, one work item per thread and round: work item w finds its cell
/// by binary search and its pair by the triangular inversion, then runs the
/// CPU's filters in the CPU's order. The grid is sized to fill the device
/// once and strides over the work items, so the counters are summed in
/// registers and added with one atomic per warp at the end; kept (and, with
/// count_culled, culled) root pairs are appended with one atomic per warp and
/// round. Every lane runs every round, so warp-wide operations see full warps.
__global__ void test_kernel(std::uint64_t tests, const std::uint64_t* first_test, std::size_t cells,
                            const std::uint64_t* first, const std::uint64_t* cell_ids,
                            const RegisteredLeaf* registered, GridSpec grid, const Dop18* triangle_dops,
                            std::uint64_t* kept, std::uint64_t kept_capacity, bool count_culled,
                            std::uint64_t* culled, std::uint64_t culled_capacity, unsigned long long* counters) {
  unsigned same_root = 0, time_slots = 0, control_bits = 0, extended = 0, fallback = 0, passed = 0, culls = 0;
  const std::uint64_t stride = static_cast<std::uint64_t>(gridDim.x) * blockDim.x;
  for (std::uint64_t base = static_cast<std::uint64_t>(blockIdx.x) * blockDim.x; base < tests; base += stride) {
    const std::uint64_t w = base + threadIdx.x;
    bool keep = false, cull = false;
    std::uint64_t key = 0;
    if (w < tests) {
      const std::uint64_t c = cell_of_work_item(first_test, cells, w);
      const std::uint64_t n = first[c + 1] - first[c];
      std::uint64_t i = 0, j = 0;
      pair_from_index(n, w - first_test[c], i, j);
      const RegisteredLeaf& a = registered[first[c] + i];
      const RegisteredLeaf& b = registered[first[c] + j];
      if (a.triangle.root == b.triangle.root) {
        ++same_root;
      } else if (!slots_nested(a.triangle, b.triangle)) {
        ++time_slots;
      } else {
        switch (cell_pair_verdict(grid, a.cells, b.cells, cell_ids[c])) {
          case CellPairVerdict::kSkipControlBits: ++control_bits; break;
          case CellPairVerdict::kSkipExtendedBits: ++extended; break;
          case CellPairVerdict::kTestFallback: ++fallback; [[fallthrough]];
          case CellPairVerdict::kTest: {
            ++passed;
            const Index ra = a.triangle.root, rb = b.triangle.root;
            key = pack_pair(ra, rb);
            if (dop_overlap(triangle_dops[ra], triangle_dops[rb])) keep = true;
            else cull = true;
            break;
          }
        }
      }
    }
    const unsigned long long kept_slot = detail::warp_append(keep, &counters[kKept]);
    if (keep && kept_slot < kept_capacity) kept[kept_slot] = key;
    if (count_culled) {
      const unsigned long long culled_slot = detail::warp_append(cull, &counters[kCulled]);
      if (cull && culled_slot < culled_capacity) culled[culled_slot] = key;
    } else {
      culls += cull ? 1 : 0;
    }
  }
  detail::warp_count(same_root, &counters[kSameRoot]);
  detail::warp_count(time_slots, &counters[kTimeSlots]);
  detail::warp_count(control_bits, &counters[kControlBits]);
  detail::warp_count(extended, &counters[kExtended]);
  detail::warp_count(fallback, &counters[kFallback]);
  detail::warp_count(passed, &counters[kPassed]);
  detail::warp_count(culls, &counters[kCulled]);
}

__global__ void unpack_pairs_kernel(const std::uint64_t* keys, std::size_t n, TrianglePair* pairs) {
  const std::uint64_t k = thread_item();
  if (k < n) pairs[k] = unpack_pair(keys[k]);
}

int bits_for(std::uint64_t max_value) {
  int bits = 1;
  while (bits < 64 && (max_value >> bits) != 0) ++bits;
  return bits;
}

/// Sorts n keys of `in` (into p.sorted) and removes duplicates (into out); returns the unique count.
std::size_t sort_unique(std::uint64_t* in, std::size_t n, int end_bit, DevicePairs& p, std::uint64_t* out,
                        cudaStream_t stream) {
  if (n == 0) return 0;
  std::size_t bytes = 0;
  SNAG_CUDA_CHECK(cub::DeviceRadixSort::SortKeys(nullptr, bytes, in, p.sorted.data(), n, 0, end_bit, stream));
  ensure(p.temp, bytes);
  bytes = p.temp.size();
  SNAG_CUDA_CHECK(cub::DeviceRadixSort::SortKeys(p.temp.data(), bytes, in, p.sorted.data(), n, 0, end_bit, stream));
  bytes = 0;
  SNAG_CUDA_CHECK(cub::DeviceSelect::Unique(nullptr, bytes, p.sorted.data(), out, p.counters.data() + kCounters, n,
                                            stream));
  ensure(p.temp, bytes);
  bytes = p.temp.size();
  SNAG_CUDA_CHECK(cub::DeviceSelect::Unique(p.temp.data(), bytes, p.sorted.data(), out, p.counters.data() + kCounters,
                                            n, stream));
  unsigned long long unique = 0;
  SNAG_CUDA_CHECK(cudaMemcpyAsync(&unique, p.counters.data() + kCounters, sizeof(unique), cudaMemcpyDeviceToHost,
                                  stream));
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
  return unique;
}

}  // namespace

void enumerate_pairs_on_device(const Leaf* leaves, const DeviceCellLists& lists, const GridSpec& grid,
                               const Dop18* triangle_dops, std::size_t triangle_count, bool count_culled,
                               DevicePairs& p, cudaStream_t stream, BroadPhaseStats& stats) {
  const std::size_t cells = lists.cells;
  p.counters.resize(kCounters + 1);
  p.pair_count = 0;
  p.pairs.resize(0);
  const std::size_t registrations = lists.leaves.size();
  p.registered.resize(registrations);
  if (registrations > 0) {
    gather_registered_kernel<<<blocks_for(registrations), detail::kBlockSize, 0, stream>>>(
        leaves, lists.leaves.data(), registrations, p.registered.data());
    SNAG_CUDA_CHECK_LAUNCH();
  }
  p.cell_tests.resize(cells + 1);
  p.first_test.resize(cells + 1);
  cell_tests_kernel<<<blocks_for(cells + 1), detail::kBlockSize, 0, stream>>>(lists.first.data(), cells,
                                                                             p.cell_tests.data());
  SNAG_CUDA_CHECK_LAUNCH();
  std::size_t bytes = 0;
  SNAG_CUDA_CHECK(
      cub::DeviceScan::ExclusiveSum(nullptr, bytes, p.cell_tests.data(), p.first_test.data(), cells + 1, stream));
  ensure(p.temp, bytes);
  bytes = p.temp.size();
  SNAG_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(p.temp.data(), bytes, p.cell_tests.data(), p.first_test.data(),
                                                cells + 1, stream));
  std::uint64_t tests = 0;
  SNAG_CUDA_CHECK(
      cudaMemcpyAsync(&tests, p.first_test.data() + cells, sizeof(tests), cudaMemcpyDeviceToHost, stream));
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
  stats.tests = tests;

  // Room for the passing pairs: what the last call needed, at least a share of
  // the tests; grown and run again when a count overflows.
  unsigned long long counts[kCounters] = {};
  if (tests > 0) {
    // As many blocks as the device holds at once (the kernel strides).
    int device = 0, sms = 0, per_sm = 0;
    SNAG_CUDA_CHECK(cudaGetDevice(&device));
    SNAG_CUDA_CHECK(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device));
    SNAG_CUDA_CHECK(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, test_kernel, detail::kBlockSize, 0));
    const std::uint64_t resident_blocks = static_cast<std::uint64_t>(std::max(1, sms * std::max(1, per_sm)));
    // A warp's per-thread counts are summed in 32 bits: at most 2^27 rounds.
    if (tests / (resident_blocks * detail::kBlockSize) >= (std::uint64_t{1} << 27))
      throw CudaError("broad phase: too many pair tests for one launch", 0);
    std::size_t kept_room = std::max<std::size_t>(p.kept.capacity(), std::min<std::uint64_t>(tests, 1 << 20));
    std::size_t culled_room =
        count_culled ? std::max<std::size_t>(p.culled.capacity(), std::min<std::uint64_t>(tests, 1 << 18)) : 0;
    for (;;) {
      p.kept.resize(kept_room);
      p.culled.resize(culled_room);
      p.counters.fill_zero();
      const std::uint64_t blocks = std::min<std::uint64_t>((tests + detail::kBlockSize - 1) / detail::kBlockSize,
                                                           resident_blocks);
      test_kernel<<<static_cast<unsigned>(blocks), detail::kBlockSize, 0, stream>>>(
          tests, p.first_test.data(), cells, lists.first.data(), lists.cell_ids.data(), p.registered.data(), grid,
          triangle_dops, p.kept.data(), kept_room, count_culled, p.culled.data(), culled_room, p.counters.data());
      SNAG_CUDA_CHECK_LAUNCH();
      p.counters.download(counts, kCounters);
      SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
      if (counts[kKept] <= kept_room && (!count_culled || counts[kCulled] <= culled_room)) break;
      kept_room = std::max<std::size_t>(kept_room, counts[kKept]);
      culled_room = std::max<std::size_t>(culled_room, counts[kCulled]);
    }
  }
  stats.same_root_tests = counts[kSameRoot];
  stats.removed_by_time_slots = counts[kTimeSlots];
  stats.removed_by_control_bits = counts[kControlBits];
  stats.removed_by_extended_control_bits = counts[kExtended];
  stats.fallback_tests = counts[kFallback];
  stats.tests_after_control_bits = counts[kPassed];
  stats.culled_by_dop = counts[kCulled];

  // Final sort + unique; duplicate root-pair tests counted exactly, as on the CPU
  // (among the culled tests only when their keys were kept).
  const std::size_t kept_tests = counts[kKept], culled_tests = count_culled ? counts[kCulled] : 0;
  const int end_bit = 32 + bits_for(triangle_count > 0 ? triangle_count - 1 : 0);
  p.sorted.resize(std::max(kept_tests, culled_tests));
  p.unique_keys.resize(std::max(kept_tests, culled_tests));
  const std::size_t culled_unique = sort_unique(p.culled.data(), culled_tests, end_bit, p, p.unique_keys.data(), stream);
  const std::size_t kept_unique = sort_unique(p.kept.data(), kept_tests, end_bit, p, p.unique_keys.data(), stream);
  stats.duplicate_root_pair_tests = kept_tests - kept_unique;
  stats.duplicate_culled_tests = culled_tests - culled_unique;
  stats.triangle_pairs = kept_unique;
  p.pair_count = kept_unique;
  p.pairs.resize(kept_unique);
  if (kept_unique > 0) {
    unpack_pairs_kernel<<<blocks_for(kept_unique), detail::kBlockSize, 0, stream>>>(p.unique_keys.data(), kept_unique,
                                                                                    p.pairs.data());
    SNAG_CUDA_CHECK_LAUNCH();
  }
}

}  // namespace snag
