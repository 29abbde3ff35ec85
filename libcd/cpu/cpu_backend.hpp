// The CPU back end with a chosen broad phase and static test, for
// comparisons count for count with another back end. make_cpu_backend()
// (pipeline/backend.hpp) is this with the defaults: the box grid
// (broad_phase/box_grid.hpp), which suits CPUs, for CCD and static
// detection, and the 2D exact-sign filter in front of the static triangle
// test (triangles_separated_in_projection). The events are the same with any
// options; candidate and predicate counts are not.
#pragma once

#include <memory>

#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/pipeline/backend.hpp"

namespace snag {

struct CpuBackendOptions {
  BroadPhaseMethod broad_phase = BroadPhaseMethod::kBoxGrid;  ///< for CCD and static detection
  /// The static test by frame: the vertex fans shown apart once per frame
  /// (narrow_phase/vertex_fans.hpp), whose pairs the broad phase may leave
  /// out; each triangle's projection axes once per frame, the plane-side
  /// rejection for triangles that share no vertex and the 2D exact-sign
  /// filter for neighbours, before the exact-sign test.
  /// false: the CUDA back end's test, triangles_intersect pair by pair (the
  /// same answers; its predicate counts).
  bool frame_static_test = true;
};

/// The CPU back end with `options`. The CUDA back end's counts are those of
/// {kVirtualSubdivisionGrid, false}.
std::unique_ptr<Backend> make_cpu_backend(const CpuBackendOptions& options);

}  // namespace snag
