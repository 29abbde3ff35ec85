// The GPU broad phase: the virtual subdivision scheme (and the largest-triangle
// grid) with every stage on the device, returning exactly the CPU's sets in
// the CPU's order (libcd/broad_phase/virtual_subdivision_grid.hpp). Plain C++;
// the class and its device-side entry points are in cuda_broad_phase.cuh.
#pragma once

#include <memory>

#include "libcd/broad_phase/broad_phase.hpp"

namespace snag {

/// A CUDA broad phase for kVirtualSubdivisionGrid or kLargestTriangleGrid.
/// Throws UsageError for kBruteForce (no GPU version). Creating it touches no
/// device; build() and the detections throw CudaError when CUDA calls fail.
std::unique_ptr<BroadPhase> make_cuda_broad_phase(BroadPhaseMethod method);

}  // namespace snag
