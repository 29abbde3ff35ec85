// Feature pairs of the unique triangle pairs on the GPU, mirroring
// libcd/culling/representative_triangles.cpp: each triangle pair yields the
// vertex-face and edge-edge pairs of the features its triangles represent,
// culled by the swept 18-DOPs of vertex against face and edge against edge.
// One thread per triangle pair counts, a prefix scan places, a second pass
// writes; a radix sort orders the outputs as the CPU's sort does. For the
// CUDA back end the narrow phase's CCD early exits run between the count and
// the scan (FeatureScreen), so that only what they leave is written.
#pragma once

#include <cuda_runtime_api.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>

#include "libcd/bounding_volume/dop18.hpp"
#include "libcd/broad_phase/candidates.hpp"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/cuda/primitive_bounds.cuh"
#include "libcd/culling/representative_triangles.hpp"
#include "libcd/narrow_phase/ccd_result.hpp"

namespace snag {

/// The scene's topology on the device (uploaded once by build()) and its
/// representatives (by the first continuous detection, which alone uses them).
struct DeviceTopology {
  DeviceBuffer<Triangle> triangles;              ///< #F
  DeviceBuffer<Edge> edges;                      ///< #E
  DeviceBuffer<std::uint8_t> masks;              ///< #F representative masks
  DeviceBuffer<std::array<Index, 3>> edge_ids;   ///< #F edge ids of each triangle

  explicit DeviceTopology(cudaStream_t stream)
      : triangles(0, stream), edges(0, stream), masks(0, stream), edge_ids(0, stream) {}
};

/// What one triangle pair adds: the vertex-face and edge-edge candidates the
/// culling kept, and after an exclusive scan in place those of the pairs
/// before it (its candidates' places).
struct FeatureTally {
  std::uint64_t vf = 0, ee = 0;
};

/// Buffers of the feature stage, reused across calls.
struct DeviceFeatures {
  DeviceBuffer<FeatureTally> tally;  ///< n + 1 per chunk of n pairs, scanned in place: tally[n] is the chunk's sum
  DeviceBuffer<std::uint64_t> vf_keys, ee_keys, vf_sorted, ee_sorted;  ///< keys and sorted: the sort's two halves
  DeviceBuffer<VertexFaceCandidate> vf;  ///< the result of a part, sorted
  DeviceBuffer<EdgeEdgeCandidate> ee;    ///< the result of a part, sorted
  DeviceBuffer<std::uint16_t> kept;      ///< per pair: the feature pairs the culling kept (one bit each)
  DeviceBuffer<unsigned long long> counters;
  DeviceBuffer<std::uint64_t> bounds;  ///< first pair, vf and ee offsets of each part
  DeviceBuffer<unsigned char> temp;
  /// Whether the last call's screen ran: its candidates are then those the
  /// early exits leave undecided or out of range.
  bool screened = false;

  explicit DeviceFeatures(cudaStream_t stream)
      : tally(0, stream),
        vf_keys(0, stream),
        ee_keys(0, stream),
        vf_sorted(0, stream),
        ee_sorted(0, stream),
        vf(0, stream),
        ee(0, stream),
        kept(0, stream),
        counters(0, stream),
        bounds(0, stream),
        temp(0, stream) {}
};

/// Device bytes of the feature stage per triangle pair (the tally and the
/// kept bits, or the separation's flag) and per candidate (key, the sort's second half, the
/// candidate; unsorted, the key and the candidate).
constexpr std::size_t kFeatureBytesPerPair = sizeof(FeatureTally) + sizeof(std::uint16_t);
constexpr std::size_t kFeatureBytesPerCandidate = 3 * sizeof(std::uint64_t);
constexpr std::size_t kUnsortedFeatureBytesPerCandidate = 2 * sizeof(std::uint64_t);
/// The most candidates one triangle pair yields (6 vertex-face, 9 edge-edge).
constexpr std::size_t kMostCandidatesPerPair = 15;

/// The CCD early exits (vertex_face_early_exit, edge_edge_early_exit) run on
/// each feature pair the DOPs keep, for a caller whose narrow phase runs them
/// first anyway: a pair they decide kNo is no candidate. On the refined
/// cloths they decide some 96% of the pairs, which are then never written,
/// read back or handed on, and the narrow phase's rounds hold only the rest.
struct FeatureScreen {
  const Vec3* x_t0 = nullptr;  ///< #V device positions at the start and end of the step
  const Vec3* x_t1 = nullptr;
  CcdSettings settings;  ///< as the narrow phase takes them
  /// When positive, the screen runs only on a call whose candidates of
  /// either kind number more than this (the caller's narrow round) or do not
  /// fit one part: where the narrow phase takes them all in one round anyway,
  /// its own early exits, a thread a candidate, cost less than the screen's
  /// thread a triangle pair (cloth_ball: 3.8 M candidates, 2.9 M pairs).
  /// The counts are taken and read on the device: the host does not wait.
  std::uint64_t only_above = 0;

  /// Whether the screen runs on a call whose DOP-kept candidates number vf
  /// and ee (vertex-face, edge-edge), in parts of part_step: the one rule,
  /// for the kernel that decides on the device and the host that reads the
  /// counts after it.
  __host__ __device__ bool runs(unsigned long long vf, unsigned long long ee, std::uint64_t part_step) const {
    return only_above == 0 || vf > only_above || ee > only_above || vf + ee > part_step;
  }
};

/// Representative feature pairs of pair_count unique device triangle pairs,
/// handed to `visit` in parts of consecutive pairs, each part's vertex-face
/// and edge-edge candidates sorted (device arrays valid until visit
/// returns); with `sorted` false, in the order of their triangle pairs
/// instead (a pair's as count_kernel finds them), which saves the sorts of
/// every candidate for a caller that orders only what it keeps of them. A part holds at most candidate_room candidates
/// (vertex-face and edge-edge together), so that the stage's memory is bounded by the room; one part when they all fit.
/// Adds the counts to `counts` (as the CPU's). With `screen`, only the
/// candidates its early exits leave undecided (or out of range) are handed
/// on, and features.screened says so where the screen ran (screen.only_above);
/// `counts` is as without it. The triangle pairs the CPU's
/// representative_feature_pairs leaves out as separated are left out
/// before, where the pair tests' keys become pairs (triangle_separation.cuh).
/// @param bounds  the step's swept DOPs of triangles, edges and vertices and
///                their float boxes (a feature pair whose boxes are apart is
///                culled without reading its DOPs)
/// Waits for the stream. Throws CudaError, UsageError (a room under kMostCandidatesPerPair + 1).
void representative_feature_pairs_on_device(
    const DeviceTopology& topology, const DevicePrimitiveBounds& bounds, std::size_t vertex_count,
    std::size_t edge_count, const TrianglePair* pairs, std::size_t pair_count, std::size_t candidate_room,
    DeviceFeatures& features, cudaStream_t stream, FeatureCounts& counts,
    const std::function<void(const VertexFaceCandidate*, std::size_t, const EdgeEdgeCandidate*, std::size_t)>& visit,
    bool sorted = true, const FeatureScreen* screen = nullptr);

}  // namespace snag
