// The CCD early exits as the CUDA feature stage's screen runs them: on the
// device, compiled with fused multiply-adds (contracted_early_exits.cu is
// built with --fmad=true, as libcd/cuda/representative_triangles.cu is),
// where the rest of the CUDA back end and the host round every product.
#pragma once

#include <array>
#include <vector>

#include "libcd/geometry/vec3.hpp"
#include "libcd/narrow_phase/ccd_result.hpp"

namespace snag::test {

/// One CCD query: 8 points in the narrow phase's order (vertex_face_ccd's
/// or edge_edge_ccd's arguments), and its kind.
struct EarlyExitQuery {
  std::array<Vec3, 8> points;
  bool edge_edge = false;
};

/// For each query, whether vertex_face_early_exit or edge_edge_early_exit,
/// contracted and run on the device, decides it kNo. Throws CudaError.
std::vector<bool> contracted_early_exits_rule_out(const std::vector<EarlyExitQuery>& queries,
                                                  const CcdSettings& settings);

/// a * b + c as a kernel of the same file computes it: a contracted product
/// and sum is rounded once, so that a * b + c differs from the host's where
/// the product's rounding matters. Throws CudaError.
double contracted_multiply_add(double a, double b, double c);

}  // namespace snag::test
