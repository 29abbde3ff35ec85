// The GPU broad phase class and its device-side entry points, for the GPU
// narrow phase that reads the candidates where they are.
//
// Wong, Leach, Zambetta, virtual subdivision chapter, Algorithm 1, with every
// stage on the device, file for file the twin of the CPU pipeline:
//   bounds            cuda/primitive_bounds.cu          (bounding_volume/primitive_bounds.cpp)
//   cell size, grid   exact fixed-point radius sum       (grid/radius_sum.hpp, grid/cell_size.cpp)
//   subdivision       cuda/virtual_subdivision.cu       (subdivision/virtual_subdivision.cpp)
//   registration      cuda/cell_registration.cu         (grid/cell_registration.cpp)
//   tests, sort+unique cuda/pair_enumeration.cu         (broad_phase/virtual_subdivision_grid.cpp)
//   features          cuda/representative_triangles.cu  (culling/representative_triangles.cpp)
// The per-element math is the same SNAG_HD code, compiled without FMA
// contraction, so every DOP, cell and decision has the CPU's bits, and the
// outputs are the CPU's sorted vectors exactly.
//
// Device memory is sized to the scene and kept between calls (buffers only
// grow); a count that overflows a preallocated buffer makes that stage grow it
// and run again. The stream waits at each stage for the sizes of the next.
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <memory>
#include <vector>

#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/cuda/cuda_broad_phase.hpp"

namespace snag {

/// Candidates left on the device by the last detection; valid until the next
/// detection or build() of the same broad phase. Sorted as the CPU's vectors.
struct DeviceCandidates {
  const VertexFaceCandidate* vf = nullptr;  ///< CCD only
  std::size_t vf_count = 0;
  const EdgeEdgeCandidate* ee = nullptr;    ///< CCD only
  std::size_t ee_count = 0;
  const TrianglePair* pairs = nullptr;      ///< unique triangle pairs (CCD and static)
  std::size_t pair_count = 0;
};

struct CudaBroadPhaseBuffers;  // device buffers, defined in cuda_broad_phase.cu

class CudaBroadPhase final : public BroadPhase {
 public:
  /// subdivide = true: the VSS grid; false: the cell fits the largest triangle.
  explicit CudaBroadPhase(bool subdivide);
  ~CudaBroadPhase() override;
  /// For kVirtualSubdivisionGrid or kLargestTriangleGrid; UsageError for kBruteForce.
  static std::unique_ptr<CudaBroadPhase> create(BroadPhaseMethod method);

  /// As VirtualSubdivisionGrid::build; uploads topology and representatives.
  /// Throws UsageError for bad settings, CudaError when a CUDA call fails.
  void build(const Scene& scene, const BroadPhaseSettings& settings) override;
  /// Upload, detect_ccd_on_device, download. Throws UsageError like the CPU's, CudaError.
  void detect_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, std::vector<VertexFaceCandidate>& vf,
                  std::vector<EdgeEdgeCandidate>& ee) override;
  /// Upload, detect_static_on_device, download.
  void detect_static(const std::vector<Vec3>& x, std::vector<TrianglePair>& pairs) override;
  const BroadPhaseStats& stats() const override { return stats_; }

  /// Continuous candidates for positions already on the device.
  /// @param d_x_t0, d_x_t1  #V device positions at the start and end of the step
  /// @param stream          stream to run on; the call returns when the
  ///                        results are complete on the device
  /// Throws UsageError when build() was not called, CudaError.
  DeviceCandidates detect_ccd_on_device(const Vec3* d_x_t0, const Vec3* d_x_t1, cudaStream_t stream);
  /// Static triangle pairs for #V device positions d_x (DeviceCandidates::pairs only).
  DeviceCandidates detect_static_on_device(const Vec3* d_x, cudaStream_t stream);

 private:
  void use_stream(cudaStream_t stream);
  void triangle_pairs_on_device(const Vec3* d_x_t0, const Vec3* d_x_t1, cudaStream_t stream);

  bool subdivide_;
  const Scene* scene_ = nullptr;
  BroadPhaseSettings settings_;
  BroadPhaseStats stats_;
  cudaStream_t stream_ = nullptr;
  std::unique_ptr<CudaBroadPhaseBuffers> buffers_;
};

}  // namespace snag
