// The GPU broad phase: the stages of cuda_broad_phase.cuh in order, timed with
// CUDA events, counted as the CPU's VirtualSubdivisionGrid counts.
#include "libcd/cuda/cuda_broad_phase.cuh"

#include <string>

#include "libcd/core/error.hpp"
#include "libcd/cuda/cuda_check.cuh"
#include "libcd/cuda/cuda_event.cuh"
#include "libcd/cuda/cell_registration.cuh"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/cuda/device_memory_tracker.hpp"
#include "libcd/cuda/pair_enumeration.cuh"
#include "libcd/cuda/primitive_bounds.cuh"
#include "libcd/cuda/representative_triangles.cuh"
#include "libcd/cuda/virtual_subdivision.cuh"
#include "libcd/grid/cell_size.hpp"
#include "libcd/grid/radius_sum.hpp"

namespace snag {

struct CudaBroadPhaseBuffers {
  DeviceTopology topology;
  DeviceBuffer<Vec3> x_t0, x_t1;  ///< uploads of the host-vector entry points
  DevicePrimitiveBounds bounds;
  DeviceSubdivision subdivision;
  DeviceCellLists cells;
  DevicePairs pairs;
  DeviceFeatures features;

  explicit CudaBroadPhaseBuffers(cudaStream_t stream)
      : topology(stream), x_t0(0, stream), x_t1(0, stream), bounds(stream), subdivision(stream), cells(stream),
        pairs(stream), features(stream) {}
};

namespace {

void check_positions(const Scene* scene, std::size_t size, const char* what) {
  if (scene == nullptr) throw UsageError("broad phase: build() must be called before detection");
  if (size != scene->vertex_count())
    throw UsageError(std::string("broad phase: ") + what + " holds " + std::to_string(size) +
                     " positions, the scene has " + std::to_string(scene->vertex_count()) + " vertices");
}

double seconds_between(const CudaEvent& from, const CudaEvent& to) {
  return static_cast<double>(CudaEvent::elapsed_ms(from, to)) / 1000.0;
}

}  // namespace

CudaBroadPhase::CudaBroadPhase(bool subdivide) : subdivide_(subdivide) {}
CudaBroadPhase::~CudaBroadPhase() = default;

void CudaBroadPhase::build(const Scene& scene, const BroadPhaseSettings& settings) {
  if (!(settings.lambda > 1.0)) throw UsageError("broad phase: lambda must be greater than 1");
  if (!(settings.thickness >= 0.0)) throw UsageError("broad phase: thickness must be >= 0");
  if (settings.max_subdivision_levels < 0 || settings.max_subdivision_levels > 30 || settings.max_time_halvings < 0 ||
      settings.max_time_halvings > 30)
    throw UsageError("broad phase: safety limits must lie in [0, 30]");
  if (scene.vertex_count() > 0xffffffffull || scene.triangle_count() > 0xffffffffull)
    throw UsageError("broad phase: the GPU back end takes at most 2^32 - 1 vertices and triangles");
  scene_ = &scene;
  settings_ = settings;
  buffers_.reset();
  use_stream(stream_);
}

void CudaBroadPhase::use_stream(cudaStream_t stream) {
  if (buffers_ != nullptr && stream == stream_) return;
  if (buffers_ != nullptr) SNAG_CUDA_CHECK(cudaStreamSynchronize(stream_));
  buffers_.reset();
  stream_ = stream;
  buffers_ = std::make_unique<CudaBroadPhaseBuffers>(stream);
  // Topology and representatives (once per scene and stream).
  const RepresentativeTriangles reps = assign_representative_triangles(*scene_);
  DeviceTopology& topology = buffers_->topology;
  topology.triangles.upload(scene_->triangles());
  topology.edges.upload(scene_->edges());
  topology.masks.upload(reps.masks);
  topology.edge_ids.upload(reps.edge_ids);
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
}

void CudaBroadPhase::triangle_pairs_on_device(const Vec3* d_x_t0, const Vec3* d_x_t1, cudaStream_t stream) {
  const Scene& scene = *scene_;
  CudaBroadPhaseBuffers& b = *buffers_;
  stats_ = BroadPhaseStats{};
  const std::size_t triangle_count = scene.triangle_count(), edge_count = scene.edges().size(),
                    vertex_count = scene.vertex_count();
  CudaEvent start, bounded, subdivided, registered, paired;
  start.record(stream);

  // 1. Bounding volumes; 2. cell size (exact sum) and grid.
  Vec3 scene_lo, scene_hi;
  double max_radius = 0;
  compute_primitive_bounds_on_device(b.topology.triangles.data(), triangle_count, b.topology.edges.data(),
                                     edge_count, d_x_t0, d_x_t1, vertex_count, settings_.thickness, b.bounds,
                                     stream, scene_lo, scene_hi, max_radius);
  double size = 0;
  if (triangle_count > 0) {
    if (subdivide_) {
      const int shift = radius_sum_shift(max_radius);
      const FixedPointSum sum = radius_sum_on_device(b.bounds, triangle_count, shift, stream);
      size = 3.0 * settings_.lambda * fixed_point_mean(sum, triangle_count, shift);
    } else {
      size = 3.0 * max_radius * (1 + 1e-9);  // largest_triangle_cell_size
    }
  }
  bounded.record(stream);
  const GridSpec grid = make_grid(scene_lo, scene_hi, size);
  stats_.cell_size = grid.cell_size;
  for (int a = 0; a < 3; ++a) stats_.grid_dims[a] = grid.dims[a];

  // 3. Virtual subdivision.
  std::vector<SubdivisionLevelCounts> levels;
  const std::size_t leaf_count = subdivide_virtually_on_device(
      b.topology.triangles.data(), triangle_count, d_x_t0, d_x_t1, grid, settings_.thickness,
      static_cast<std::uint32_t>(subdivide_ ? settings_.max_subdivision_levels : 0),
      static_cast<std::uint32_t>(subdivide_ ? settings_.max_time_halvings : 0), b.subdivision, stream, levels);
  if (leaf_count > 0xffffffffull) throw UsageError("broad phase: more than 2^32 - 1 leaf triangles");
  stats_.root_triangles = triangle_count;
  for (const SubdivisionLevelCounts& level : levels) {
    stats_.triangles_per_level.push_back(level.triangles);
    stats_.subdivided_per_level.push_back(level.subdivided);
    stats_.halved_per_level.push_back(level.halved);
    stats_.triangles_subdivided += level.subdivided;
    stats_.time_halvings += level.halved;
    stats_.oversized_leaves += level.oversized;
  }
  stats_.leaf_triangles = leaf_count;
  subdivided.record(stream);

  // 4. Registration, one sort, one scan.
  RegistrationCounts reg;
  register_leaves_on_device(b.subdivision.leaves.data(), leaf_count, grid, b.cells, stream, reg);
  stats_.registrations = reg.registrations;
  stats_.home_registrations = reg.home;
  stats_.phantom_registrations = reg.phantom;
  stats_.duplicate_registrations_removed = reg.duplicates_removed;
  stats_.cells_used = b.cells.cells;
  registered.record(stream);

  // 5. One test per thread; 6. sort + unique of root pairs.
  enumerate_pairs_on_device(b.subdivision.leaves.data(), b.cells, grid, b.bounds.triangles.data(), triangle_count,
                            settings_.count_culled_duplicates, b.pairs, stream, stats_);
  paired.record(stream);
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
  stats_.seconds_bounds = seconds_between(start, bounded);
  stats_.seconds_subdivision = seconds_between(bounded, subdivided);
  stats_.seconds_registration = seconds_between(subdivided, registered);
  stats_.seconds_pairs = seconds_between(registered, paired);
  stats_.seconds_total = seconds_between(start, paired);
}

DeviceCandidates CudaBroadPhase::detect_ccd_on_device(const Vec3* d_x_t0, const Vec3* d_x_t1, cudaStream_t stream) {
  if (scene_ == nullptr) throw UsageError("broad phase: build() must be called before detection");
  use_stream(stream);
  DeviceMemoryTracker::instance().reset_peak();
  CudaEvent start, done;
  start.record(stream);
  triangle_pairs_on_device(d_x_t0, d_x_t1, stream);
  CudaBroadPhaseBuffers& b = *buffers_;
  CudaEvent features_start;
  features_start.record(stream);
  FeatureCounts counts;
  representative_feature_pairs_on_device(b.topology, b.bounds.triangles.data(), b.bounds.edges.data(),
                                         b.bounds.vertices.data(), scene_->vertex_count(), scene_->edges().size(),
                                         b.pairs.pairs.data(), b.pairs.pair_count, b.features, stream, counts);
  done.record(stream);
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
  stats_.vf_before_culling = counts.vf_before;
  stats_.vf_after_culling = counts.vf_after;
  stats_.ee_before_culling = counts.ee_before;
  stats_.ee_after_culling = counts.ee_after;
  stats_.candidates = b.features.vf_size + b.features.ee_size;
  stats_.seconds_features = seconds_between(features_start, done);
  stats_.seconds_total = seconds_between(start, done);
  stats_.memory_bytes = DeviceMemoryTracker::instance().peak_bytes();
  return {b.features.vf.data(), b.features.vf_size, b.features.ee.data(), b.features.ee_size, b.pairs.pairs.data(),
          b.pairs.pair_count};
}

DeviceCandidates CudaBroadPhase::detect_static_on_device(const Vec3* d_x, cudaStream_t stream) {
  if (scene_ == nullptr) throw UsageError("broad phase: build() must be called before detection");
  use_stream(stream);
  DeviceMemoryTracker::instance().reset_peak();
  triangle_pairs_on_device(d_x, d_x, stream);
  CudaBroadPhaseBuffers& b = *buffers_;
  stats_.candidates = b.pairs.pair_count;
  stats_.memory_bytes = DeviceMemoryTracker::instance().peak_bytes();
  DeviceCandidates out;
  out.pairs = b.pairs.pairs.data();
  out.pair_count = b.pairs.pair_count;
  return out;
}

void CudaBroadPhase::detect_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                std::vector<VertexFaceCandidate>& vf, std::vector<EdgeEdgeCandidate>& ee) {
  check_positions(scene_, x_t0.size(), "x_t0");
  check_positions(scene_, x_t1.size(), "x_t1");
  use_stream(stream_);
  buffers_->x_t0.upload(x_t0);
  buffers_->x_t1.upload(x_t1);
  const DeviceCandidates out = detect_ccd_on_device(buffers_->x_t0.data(), buffers_->x_t1.data(), stream_);
  vf.resize(out.vf_count);
  ee.resize(out.ee_count);
  if (out.vf_count > 0)
    SNAG_CUDA_CHECK(cudaMemcpyAsync(vf.data(), out.vf, out.vf_count * sizeof(VertexFaceCandidate),
                                    cudaMemcpyDeviceToHost, stream_));
  if (out.ee_count > 0)
    SNAG_CUDA_CHECK(cudaMemcpyAsync(ee.data(), out.ee, out.ee_count * sizeof(EdgeEdgeCandidate),
                                    cudaMemcpyDeviceToHost, stream_));
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream_));
}

void CudaBroadPhase::detect_static(const std::vector<Vec3>& x, std::vector<TrianglePair>& pairs) {
  check_positions(scene_, x.size(), "x");
  use_stream(stream_);
  buffers_->x_t0.upload(x);
  const DeviceCandidates out = detect_static_on_device(buffers_->x_t0.data(), stream_);
  pairs.resize(out.pair_count);
  if (out.pair_count > 0)
    SNAG_CUDA_CHECK(cudaMemcpyAsync(pairs.data(), out.pairs, out.pair_count * sizeof(TrianglePair),
                                    cudaMemcpyDeviceToHost, stream_));
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream_));
}

std::unique_ptr<BroadPhase> make_cuda_broad_phase(BroadPhaseMethod method) { return CudaBroadPhase::create(method); }

std::unique_ptr<CudaBroadPhase> CudaBroadPhase::create(BroadPhaseMethod method) {
  switch (method) {
    case BroadPhaseMethod::kVirtualSubdivisionGrid: return std::make_unique<CudaBroadPhase>(true);
    case BroadPhaseMethod::kLargestTriangleGrid: return std::make_unique<CudaBroadPhase>(false);
    case BroadPhaseMethod::kBruteForce: break;
  }
  throw UsageError("broad phase: the CUDA back end has no brute-force broad phase");
}

}  // namespace snag
