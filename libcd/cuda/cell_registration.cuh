// Registration of leaves in their cells on the GPU, mirroring
// libcd/grid/cell_registration.cpp: one (cell id, leaf id) item per cell of
// each leaf's block, ONE stable radix sort by cell id (items are generated in
// leaf order, so the order is (cell, leaf), as the CPU's sort), one scan that
// keeps one registration per (root, slot) unit per cell with home priority
// and counts the cell runs, and one pass writing the lists.
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>

#include "libcd/cuda/device_buffer.cuh"
#include "libcd/grid/cell_registration.hpp"

namespace snag {

/// What registration i adds to the cell lists: itself when kept, a cell
/// when it starts a run of one cell id; after an exclusive scan in place, the
/// kept registrations and the cells before it.
struct RegistrationTally {
  std::uint64_t kept = 0, cells = 0;
};

/// The grid after registration, on the device (as CellLists), and scratch.
struct DeviceCellLists {
  DeviceBuffer<std::uint64_t> cell_ids;  ///< #C used cell ids, ascending
  DeviceBuffer<std::uint64_t> first;     ///< #C+1 offsets into leaves
  DeviceBuffer<std::uint32_t> leaves;    ///< kept leaf ids, cell by cell
  std::size_t cells = 0;
  // scratch
  DeviceBuffer<std::uint64_t> offset, keys, keys_sorted;  ///< offset: each leaf's first registration
  DeviceBuffer<std::uint32_t> values, values_sorted;
  DeviceBuffer<RegistrationTally> tally;  ///< per sorted registration, scanned in place
  DeviceBuffer<unsigned char> temp;

  explicit DeviceCellLists(cudaStream_t stream)
      : cell_ids(0, stream),
        first(0, stream),
        leaves(0, stream),
        offset(0, stream),
        keys(0, stream),
        keys_sorted(0, stream),
        values(0, stream),
        values_sorted(0, stream),
        tally(0, stream),
        temp(0, stream) {}
};

/// Registers leaf_count device leaves as register_leaves does; counts as the CPU's.
/// Waits for the stream (sizes). Throws CudaError.
/// `check` is told what each allocation adds before it is made (it may throw).
void register_leaves_on_device(const Leaf* leaves, std::size_t leaf_count, const GridSpec& grid,
                               DeviceCellLists& lists, cudaStream_t stream, RegistrationCounts& counts,
                               const GrowthCheck& check = {});

}  // namespace snag
