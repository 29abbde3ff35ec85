// One candidate test per thread on the GPU, mirroring step 5-6 of
// libcd/broad_phase/virtual_subdivision_grid.cpp: per-cell pair counts are
// prefix-summed, each thread finds its cell by binary search (among the few
// cells its block spans, which one thread of the block finds first) and its
// pair by inverting the triangular numbering (grid/pair_index.hpp), reads the
// two leaves from a copy of them in cell order (coalesced), applies the same
// filters (same root, time slots, control bits and extended control bits,
// root 18-DOPs), and appends the root pair; a device sort + unique gives the
// exact set of triangle pairs, ordered as the CPU's.
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>

#include "libcd/bounding_volume/dop18.hpp"
#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/cuda/cell_registration.cuh"

namespace snag {

/// Buffers of the pair stage, reused across calls (they only grow).
struct DevicePairs {
  DeviceBuffer<RegisteredLeaf> registered;
  DeviceBuffer<std::uint64_t> cell_tests, first_test;
  DeviceBuffer<std::uint64_t> kept, culled, sorted, unique_keys;
  DeviceBuffer<TrianglePair> pairs;  ///< the result: unique root pairs, ascending
  DeviceBuffer<unsigned long long> counters;
  DeviceBuffer<unsigned char> temp;
  std::size_t pair_count = 0;

  explicit DevicePairs(cudaStream_t stream)
      : registered(0, stream),
        cell_tests(0, stream), first_test(0, stream), kept(0, stream), culled(0, stream), sorted(0, stream),
        unique_keys(0, stream), pairs(0, stream), counters(0, stream), temp(0, stream) {}
};

/// Runs every test of the registered cells and leaves the unique triangle
/// pairs in pairs.pairs. Fills stats' test counters, culled_by_dop,
/// duplicate_root_pair_tests, duplicate_culled_tests (when count_culled: the
/// culled tests' keys are then kept, see BroadPhaseSettings) and
/// triangle_pairs. When more pairs pass than the preallocated arrays hold,
/// they are grown and the tests run again. Waits for the stream. Throws CudaError.
/// @param triangle_dops  #F device root swept DOPs; triangle_count = #F
void enumerate_pairs_on_device(const Leaf* leaves, const DeviceCellLists& lists, const GridSpec& grid,
                               const Dop18* triangle_dops, std::size_t triangle_count, bool count_culled,
                               DevicePairs& pairs, cudaStream_t stream, BroadPhaseStats& stats);

}  // namespace snag
