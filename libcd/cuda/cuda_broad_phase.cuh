// The GPU broad phase class and its device-side entry points, for the GPU
// narrow phase that reads the candidates where they are.
//
// Wong, Leach, Zambetta, virtual subdivision chapter, Algorithm 1, with every
// stage on the device, file for file the twin of the CPU pipeline:
//   bounds            cuda/primitive_bounds.cu          (bounding_volume/primitive_bounds.cpp)
//   cell size, grid   exact fixed-point radius sum       (grid/radius_sum.hpp, grid/cell_size.cpp)
//   subdivision       cuda/virtual_subdivision.cu       (subdivision/virtual_subdivision.cpp)
//   registration      cuda/cell_registration.cu         (grid/cell_registration.cpp)
//     or the adaptive grid's cells  cuda/adaptive_cells.cu (grid/adaptive_cells.cpp)
//   tests, sort+unique cuda/pair_enumeration.cu         (broad_phase/virtual_subdivision_grid.cpp)
//   features          cuda/representative_triangles.cu  (culling/representative_triangles.cpp)
// The per-element math is the same SNAG_HD code, compiled without FMA
// contraction, so every DOP, cell and decision has the CPU's bits, and the
// outputs are the CPU's sorted vectors exactly.
//
// Device memory is sized to the scene and kept between calls (buffers only
// grow); a count that overflows a preallocated buffer makes that stage grow it
// and run again. The stream waits at each stage for the sizes of the next.
// With a memory budget (set_memory_budget), the pair tests and the feature
// stage, whose buffers grow with the candidates, run in chunks of root
// triangles and parts of pairs sized to what the budget leaves after the
// other stages (pair_enumeration.cuh, representative_triangles.cuh), and the
// candidates are handed to the caller chunk by chunk: the same candidates,
// in ascending order within each chunk.
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/cuda/cuda_broad_phase.hpp"
#include "libcd/culling/representative_triangles.hpp"
#include "libcd/narrow_phase/ccd_result.hpp"

namespace snag {

/// Candidates left on the device by the last detection; valid until the next
/// detection or build() of the same broad phase. Sorted as the CPU's vectors.
struct DeviceCandidates {
  const VertexFaceCandidate* vf = nullptr;  ///< CCD only
  std::size_t vf_count = 0;
  const EdgeEdgeCandidate* ee = nullptr;    ///< CCD only
  std::size_t ee_count = 0;
  /// Unique triangle pairs: static, all of them; CCD, those the feature
  /// stage kept (the separation removes those it proves apart).
  const TrianglePair* pairs = nullptr;
  std::size_t pair_count = 0;
  /// CCD with a screen (detect_ccd_on_device): the screen ran on this
  /// chunk, so vf and ee are what the CCD early exits leave undecided or out of range.
  bool screened = false;
};

/// Receives the candidates of one chunk; the device arrays are valid until it returns.
using CandidateVisitor = std::function<void(const DeviceCandidates&)>;

struct CudaBroadPhaseBuffers;  // device buffers, defined in cuda_broad_phase.cu
struct PairChunkPlan;          // pair_enumeration.cuh

class CudaBroadPhase final : public BroadPhase {
 public:
  /// subdivide = true: the VSS grid; false: the cell fits the largest triangle.
  /// adaptive = true: its crowded cells subdivided (the adaptive grid,
  /// cuda/adaptive_cells.cuh), as the CPU's VirtualSubdivisionGrid::Cells::kAdaptive.
  explicit CudaBroadPhase(bool subdivide, bool adaptive = false);
  ~CudaBroadPhase() override;
  /// For kVirtualSubdivisionGrid, kLargestTriangleGrid or kAdaptiveGrid; UsageError for the others.
  static std::unique_ptr<CudaBroadPhase> create(BroadPhaseMethod method);

  /// The stream its detections run on. Given before build(), build() makes
  /// its buffers and uploads the topology on it, once; a detection on another
  /// stream makes them again, on that one (the default stream until then).
  /// The representative triangles, which only continuous detections use,
  /// are assigned and uploaded by the first of them.
  void set_stream(cudaStream_t stream);
  /// As VirtualSubdivisionGrid::build; uploads the topology.
  /// Throws UsageError for bad settings, CudaError when a CUDA call fails.
  void build(const Scene& scene, const BroadPhaseSettings& settings) override;
  /// Assigns the representative triangles and uploads them now, unless they
  /// are on the device already (else the first continuous detection does).
  void upload_representatives();
  /// Upload, detect_ccd_on_device, download. Throws UsageError like the CPU's, CudaError.
  void detect_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, std::vector<VertexFaceCandidate>& vf,
                  std::vector<EdgeEdgeCandidate>& ee) override;
  /// Upload, detect_static_on_device, download.
  void detect_static(const std::vector<Vec3>& x, std::vector<TrianglePair>& pairs) override;
  const BroadPhaseStats& stats() const override { return stats_; }

  /// Continuous candidates for positions already on the device, handed to
  /// `visit` chunk by chunk (DeviceCandidates::vf and ee; one chunk when the
  /// budget allows): every candidate once, each chunk's sorted, or with
  /// `sorted` false in the order of their triangle pairs
  /// (representative_feature_pairs_on_device). With `screen`, only the
  /// candidates the CCD early exits with those settings leave undecided
  /// (FeatureScreen); stats() are as without it. A positive `screen_above`
  /// (FeatureScreen::only_above) leaves the first chunk unscreened when its
  /// candidates of each kind are at most that many (the caller's narrow
  /// round) in one part; every later chunk is screened.
  /// @param d_x_t0, d_x_t1  #V device positions at the start and end of the step
  /// @param stream          stream to run on (visit may queue work on it)
  /// Throws UsageError when build() was not called or the budget is too
  /// small for one chunk, CudaError.
  void detect_ccd_on_device(const Vec3* d_x_t0, const Vec3* d_x_t1, cudaStream_t stream, const CandidateVisitor& visit,
                            bool sorted = true, const CcdSettings* screen = nullptr, std::size_t screen_above = 0);
  /// Static triangle pairs for #V device positions d_x (DeviceCandidates::pairs
  /// only), chunk by chunk in ascending order.
  void detect_static_on_device(const Vec3* d_x, cudaStream_t stream, const CandidateVisitor& visit);

  /// The most device bytes this broad phase's buffers may hold during a
  /// detection (0: no bound); the chunks are sized from what the stages
  /// before the pair tests leave of it, at most chunk_room_cap bytes.
  void set_memory_budget(std::size_t bytes, std::size_t chunk_room_cap = ~std::size_t{0}) {
    budget_ = bytes;
    chunk_room_cap_ = chunk_room_cap;
  }
  /// Fixes the chunks' rooms instead (kept tests per chunk, candidates per
  /// part of the feature stage; 0 = from the budget), to test chunking.
  void set_chunk_rooms(std::size_t key_room, std::size_t candidate_room) {
    fixed_key_room_ = key_room;
    fixed_candidate_room_ = candidate_room;
  }
  /// Device bytes its buffers hold now.
  std::size_t held_bytes() const;
  /// Its buffers by name with the bytes each holds, largest first (for logs).
  std::vector<std::pair<std::string, std::size_t>> memory_census() const;
  /// Gives back every buffer but the topology (in stream order).
  void release_buffers();
  /// Chunks of root triangles the last detection ran in, and parts of pairs of its feature stage.
  std::size_t last_chunks() const { return last_chunks_; }
  std::size_t last_feature_parts() const { return last_parts_; }

 private:
  void use_stream(cudaStream_t stream);
  /// How a chunk's room is shared with the feature stage: its device bytes
  /// per candidate (sorted or not; 0: no feature stage, the static
  /// detection), and the tenths of the room for the tests' keys and the
  /// pairs' tallies, the rest for the candidates.
  struct FeatureRoom {
    std::size_t bytes_per_candidate = 0;
    std::size_t key_tenths = 10;
  };
  /// Bounds, subdivision, registration, then the pair tests chunk by chunk,
  /// each chunk's room shared with the feature stage as `features` says;
  /// each chunk's pairs ascend unless they go to the feature stage; with
  /// `separation`, those it proves apart are left out (ChunkPairs).
  void triangle_pairs_on_device(const Vec3* d_x_t0, const Vec3* d_x_t1, cudaStream_t stream, FeatureRoom features,
                                const TriangleSeparation* separation,
                                const std::function<void(TrianglePair*, std::size_t)>& visit);
  /// Bytes of the buffers whose size the chunks bound.
  std::size_t chunk_bytes() const;
  /// Gives back the buffers whose size the chunks bound.
  void release_chunk_buffers();
  /// With a budget: the check that `stage`'s next allocation keeps
  /// held_bytes() within it, made before the allocation, giving back the
  /// last detection's chunk buffers first where they are in its way (a
  /// UsageError when it still does not fit); without one, no check.
  std::function<void(std::size_t)> budget_check(const char* stage);  // a GrowthCheck
  /// Gives back the leaves and the subdivision's and registration's scratch
  /// (once the pair tests' copy of the leaves is queued).
  void release_stage_buffers();

  bool subdivide_, adaptive_;
  const Scene* scene_ = nullptr;
  BroadPhaseSettings settings_;
  BroadPhaseStats stats_;
  cudaStream_t stream_ = nullptr;
  std::unique_ptr<CudaBroadPhaseBuffers> buffers_;
  std::unique_ptr<PairChunkPlan> plan_;
  std::size_t budget_ = 0, chunk_room_cap_ = ~std::size_t{0};
  std::size_t fixed_key_room_ = 0, fixed_candidate_room_ = 0;
  std::size_t candidate_room_ = ~std::size_t{0};
  std::size_t last_chunks_ = 0, last_parts_ = 0;
};

}  // namespace snag
