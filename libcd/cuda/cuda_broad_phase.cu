// The GPU broad phase: the stages of cuda_broad_phase.cuh in order, timed with
// CUDA events, counted as the CPU's VirtualSubdivisionGrid counts.
#include "libcd/cuda/cuda_broad_phase.cuh"

#include <algorithm>
#include <chrono>
#include <string>

#include "libcd/core/error.hpp"
#include "libcd/cuda/adaptive_cells.cuh"
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
  DeviceAdaptiveCells adaptive;
  DevicePairs pairs;
  DeviceFeatures features;

  explicit CudaBroadPhaseBuffers(cudaStream_t stream)
      : topology(stream), x_t0(0, stream), x_t1(0, stream), bounds(stream), subdivision(stream), cells(stream),
        adaptive(stream), pairs(stream), features(stream) {}
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

/// Appends `count` device items to `host` (waits for the stream).
template <class T>
void append_download(const T* items, std::size_t count, std::vector<T>& host, cudaStream_t stream) {
  if (count == 0) return;
  const std::size_t at = host.size();
  host.resize(at + count);
  SNAG_CUDA_CHECK(cudaMemcpyAsync(host.data() + at, items, count * sizeof(T), cudaMemcpyDeviceToHost, stream));
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
}

}  // namespace

CudaBroadPhase::CudaBroadPhase(bool subdivide, bool adaptive) : subdivide_(subdivide), adaptive_(adaptive) {}
CudaBroadPhase::~CudaBroadPhase() = default;

void CudaBroadPhase::build(const Scene& scene, const BroadPhaseSettings& settings) {
  if (!(settings.lambda > 1.0)) throw UsageError("broad phase: lambda must be greater than 1");
  if (!(settings.thickness >= 0.0)) throw UsageError("broad phase: thickness must be >= 0");
  if (settings.max_subdivision_levels < 0 || settings.max_subdivision_levels > 30 || settings.max_time_halvings < 0 ||
      settings.max_time_halvings > 30)
    throw UsageError("broad phase: safety limits must lie in [0, 30]");
  if (adaptive_ && (settings.adaptive_cell_limit < 2 || settings.adaptive_max_depth < 0 ||
                    settings.adaptive_max_depth > kMaxAdaptiveDepth))
    throw UsageError("broad phase: the adaptive grid needs a cell limit >= 2 and a depth in [0, 8]");
  if (scene.vertex_count() > 0xffffffffull || scene.triangle_count() > 0xffffffffull)
    throw UsageError("broad phase: the GPU back end takes at most 2^32 - 1 vertices and triangles");
  scene_ = &scene;
  settings_ = settings;
  buffers_.reset();
  plan_ = std::make_unique<PairChunkPlan>();
  use_stream(stream_);
}

void CudaBroadPhase::set_stream(cudaStream_t stream) {
  if (buffers_ == nullptr) {
    stream_ = stream;
  } else {
    use_stream(stream);
  }
}

void CudaBroadPhase::use_stream(cudaStream_t stream) {
  if (buffers_ != nullptr && stream == stream_) return;
  if (buffers_ != nullptr) SNAG_CUDA_CHECK(cudaStreamSynchronize(stream_));
  buffers_.reset();
  stream_ = stream;
  buffers_ = std::make_unique<CudaBroadPhaseBuffers>(stream);
  // Topology (once per scene and stream); the representatives come with
  // upload_representatives (the CUDA back end's bind, or the first
  // continuous detection): the static detection does not use them.
  DeviceTopology& topology = buffers_->topology;
  topology.triangles.upload(scene_->triangles());
  topology.edges.upload(scene_->edges());
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
}

void CudaBroadPhase::upload_representatives() {
  if (scene_ == nullptr) throw UsageError("broad phase: build() must be called before the representatives");
  DeviceTopology& topology = buffers_->topology;
  if (topology.masks.size() == scene_->triangle_count()) return;  // uploaded on this stream already
  const RepresentativeTriangles reps = assign_representative_triangles(*scene_);
  topology.masks.upload(reps.masks);
  topology.edge_ids.upload(reps.edge_ids);
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream_));
}

void CudaBroadPhase::triangle_pairs_on_device(const Vec3* d_x_t0, const Vec3* d_x_t1, cudaStream_t stream,
                                              FeatureRoom features, const TriangleSeparation* separation,
                                              const std::function<void(TrianglePair*, std::size_t)>& visit) {
  const bool with_features = features.bytes_per_candidate > 0;
  const Scene& scene = *scene_;
  CudaBroadPhaseBuffers& b = *buffers_;
  stats_ = BroadPhaseStats{};
  const std::size_t triangle_count = scene.triangle_count(), edge_count = scene.edges().size(),
                    vertex_count = scene.vertex_count();
  CudaEvent start, bounded, subdivided, registered;
  start.record(stream);

  // 1. Bounding volumes; 2. cell size (exact sum) and grid.
  DeviceMemoryTracker::set_stage("broad phase: bounds");
  BoundsSummary bounded_by;
  compute_primitive_bounds_on_device(b.topology.triangles.data(), triangle_count, b.topology.edges.data(), edge_count,
                                     d_x_t0, d_x_t1, vertex_count, settings_.thickness, subdivide_, with_features,
                                     b.bounds, stream, bounded_by, budget_check("bounds"));
  double size = 0;
  if (triangle_count > 0) {
    size = subdivide_ ? 3.0 * settings_.lambda *
                            fixed_point_mean(bounded_by.radius_sum, triangle_count, bounded_by.radius_shift)
                      : 3.0 * bounded_by.max_radius * (1 + 1e-9);  // largest_triangle_cell_size
  }
  bounded.record(stream);
  const GridSpec grid = make_grid(bounded_by.scene_lo, bounded_by.scene_hi, size);
  stats_.cell_size = grid.cell_size;
  for (int a = 0; a < 3; ++a) stats_.grid_dims[a] = grid.dims[a];

  // 3. Virtual subdivision.
  DeviceMemoryTracker::set_stage("broad phase: subdivision");
  std::vector<SubdivisionLevelCounts> levels;
  const std::size_t leaf_count = subdivide_virtually_on_device(
      b.topology.triangles.data(), triangle_count, d_x_t0, d_x_t1, grid, settings_.thickness,
      static_cast<std::uint32_t>(subdivide_ ? settings_.max_subdivision_levels : 0),
      static_cast<std::uint32_t>(subdivide_ ? settings_.max_time_halvings : 0), b.subdivision, stream, levels,
      budget_check("subdivision"));
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

  // 4. Registration: one sort and one scan in the uniform grid, or the
  // hierarchy of crowded cells.
  DeviceMemoryTracker::set_stage("broad phase: registration");
  std::size_t test_cells = 0;
  if (adaptive_) {
    DeviceAdaptiveCells& tree = b.adaptive;
    build_adaptive_cells_on_device(b.subdivision.leaves.data(), leaf_count, grid, settings_.adaptive_max_depth,
                                   settings_.adaptive_cell_limit, tree, stream, budget_check("adaptive grid"));
    stats_.registrations = tree.registrations;
    stats_.cells_used = test_cells = tree.cell_count;
    stats_.cells_subdivided = tree.cells_subdivided;
    stats_.deepest_level = tree.deepest_level;
  } else {
    RegistrationCounts reg;
    register_leaves_on_device(b.subdivision.leaves.data(), leaf_count, grid, b.cells, stream, reg,
                              budget_check("registration"));
    stats_.registrations = reg.registrations;
    stats_.home_registrations = reg.home;
    stats_.phantom_registrations = reg.phantom;
    stats_.duplicate_registrations_removed = reg.duplicates_removed;
    stats_.cells_used = test_cells = b.cells.cells;
  }
  registered.record(stream);
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
  stats_.seconds_bounds = seconds_between(start, bounded);
  stats_.seconds_subdivision = seconds_between(bounded, subdivided);
  stats_.seconds_registration = seconds_between(subdivided, registered);

  // 5a. What the pair tests read of the leaves, in cell order (the adaptive
  // cells' members are that already). Under a tight budget (the stages so far
  // hold over half of it), the leaves and the subdivision's and
  // registration's scratch are given back now.
  DeviceMemoryTracker::set_stage("broad phase: pairs");
  if (!adaptive_)
    order_registrations_on_device(b.subdivision.leaves.data(), triangle_count, b.bounds.triangle_boxes.data(),
                                  b.cells, grid, b.pairs, stream,
                                  budget_check("copy of the leaves for the pair tests"));
  if (budget_ > 0 && held_bytes() - chunk_bytes() > budget_ / 2) release_stage_buffers();

  // The chunks' room: what the budget leaves beside the buffers the chunks do
  // not bound (the tests per cell are sized just below).
  std::size_t key_room = ~std::size_t{0};
  candidate_room_ = ~std::size_t{0};
  if (budget_ > 0) {
    const std::size_t fixed = held_bytes() - chunk_bytes() + (test_cells + 1) * 3 * sizeof(std::uint64_t) +
                              (std::size_t{4} << 20);  // counters, histogram, sort scratch
    if (fixed >= budget_)
      throw UsageError("the device memory limit is too small for this scene: the broad phase holds " +
                       std::to_string(fixed) + " bytes before its pair tests, its share of the limit is " +
                       std::to_string(budget_) + " bytes; raise the limit (snag-scan --device-memory)");
    const std::size_t room = std::min(budget_ - fixed, chunk_room_cap_);
    if (with_features) {
      key_room = room / 10 * features.key_tenths / (kPairChunkBytesPerTest + kFeatureBytesPerPair);
      candidate_room_ =
          room / 10 * (10 - features.key_tenths) / (2 * features.bytes_per_candidate);  // vf and ee grow apart
    } else {
      key_room = room / kPairChunkBytesPerTest;
    }
  }
  if (fixed_key_room_ > 0) key_room = fixed_key_room_;
  if (fixed_candidate_room_ > 0) candidate_room_ = fixed_candidate_room_;
  plan_->key_room = key_room;
  // Buffers a larger room of an earlier call left are given back.
  DeviceFeatures& f = b.features;
  if (f.tally.capacity() > 0 && f.tally.capacity() - 1 > key_room) f.tally.release();  // n + 1 for n pairs
  if (f.kept.capacity() > key_room) f.kept.release();
  for (DeviceBuffer<std::uint64_t>* keys : {&f.vf_keys, &f.ee_keys, &f.vf_sorted, &f.ee_sorted})
    if (keys->capacity() > candidate_room_) keys->release();
  if (f.vf.capacity() > candidate_room_) f.vf.release();
  if (f.ee.capacity() > candidate_room_) f.ee.release();

  // 5. One test per thread; 6. sort + unique of root pairs, chunk by chunk.
  DeviceMemoryTracker::set_stage("broad phase: pairs");
  last_chunks_ = 0;
  auto visit_chunk = [&](TrianglePair* pairs, std::size_t count) {
    ++last_chunks_;
    visit(pairs, count);
    DeviceMemoryTracker::set_stage("broad phase: pairs");
  };
  // The feature stage's candidates are sorted or not on their own: its pairs need no order.
  const ChunkPairs out{!with_features, separation, b.topology.triangles.data()};
  if (adaptive_)
    enumerate_adaptive_pairs_on_device(b.adaptive, b.bounds.triangles.data(), b.bounds.triangle_boxes.data(),
                                       triangle_count, settings_.count_culled_duplicates, out, *plan_, b.pairs,
                                       stream, stats_, visit_chunk);
  else
    enumerate_pairs_on_device(b.cells, grid, b.bounds.triangles.data(), b.bounds.triangle_boxes.data(),
                              triangle_count, settings_.count_culled_duplicates, out, *plan_, b.pairs, stream,
                              stats_, visit_chunk);
}

void CudaBroadPhase::detect_ccd_on_device(const Vec3* d_x_t0, const Vec3* d_x_t1, cudaStream_t stream,
                                          const CandidateVisitor& visit, bool sorted, const CcdSettings* screen,
                                          std::size_t screen_above) {
  if (scene_ == nullptr) throw UsageError("broad phase: build() must be called before detection");
  use_stream(stream);
  upload_representatives();
  DeviceMemoryTracker::instance().reset_peak();
  const auto start = std::chrono::steady_clock::now();
  double visit_seconds = 0;
  CudaBroadPhaseBuffers& b = *buffers_;
  FeatureCounts counts;
  double feature_seconds = 0;
  last_parts_ = 0;
  // A chunk's room: 40% for the tests' keys and the pairs' tallies, 60% for
  // the candidates, which outnumber the kept tests (cloth_ball ×16: 1.6 a
  // test); screened, 80% for the keys (×16: 0.07 candidates a test), so that
  // there are fewer chunks.
  const FeatureRoom room{sorted ? kFeatureBytesPerCandidate : kUnsortedFeatureBytesPerCandidate,
                         screen != nullptr ? std::size_t{8} : std::size_t{4}};
  // Only the first chunk's counts decide whether it is screened; a detection
  // of several chunks is large (cloth_ball ×4, ×16) and screens the rest
  // without counting (counted in every chunk, ×16 was 1-2% slower, H200).
  FeatureScreen feature_screen{d_x_t0, d_x_t1, screen != nullptr ? *screen : CcdSettings{}, screen_above};
  const TriangleSeparation separation{d_x_t0, d_x_t1, settings_.thickness};
  const TriangleSeparation* const separate = settings_.separate_triangles ? &separation : nullptr;
  triangle_pairs_on_device(d_x_t0, d_x_t1, stream, room, separate, [&](TrianglePair* pairs, std::size_t pair_count) {
    if (last_chunks_ > 1) feature_screen.only_above = 0;
    DeviceMemoryTracker::set_stage("broad phase: features");
    CudaEvent features_start, features_done;
    features_start.record(stream);
    representative_feature_pairs_on_device(
        b.topology, b.bounds, scene_->vertex_count(), scene_->edges().size(), pairs, pair_count, candidate_room_,
        b.features, stream, counts,
        [&](const VertexFaceCandidate* vf, std::size_t vf_count, const EdgeEdgeCandidate* ee, std::size_t ee_count) {
          features_done.record(stream);
          SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
          feature_seconds += seconds_between(features_start, features_done);
          ++last_parts_;
          const auto visit_start = std::chrono::steady_clock::now();
          visit(DeviceCandidates{vf, vf_count, ee, ee_count, pairs, pair_count, b.features.screened});
          visit_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - visit_start).count();
          DeviceMemoryTracker::set_stage("broad phase: features");
          features_start.record(stream);
        },
        sorted, screen != nullptr ? &feature_screen : nullptr);
  });
  DeviceMemoryTracker::set_stage("other");
  stats_.vf_before_culling = counts.vf_before;
  stats_.vf_after_culling = counts.vf_after;
  stats_.ee_before_culling = counts.ee_before;
  stats_.ee_after_culling = counts.ee_after;
  stats_.candidates = counts.vf_after + counts.ee_after;
  stats_.seconds_features = feature_seconds;
  stats_.seconds_total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - visit_seconds;
  stats_.memory_bytes = DeviceMemoryTracker::instance().peak_bytes();
}

void CudaBroadPhase::detect_static_on_device(const Vec3* d_x, cudaStream_t stream, const CandidateVisitor& visit) {
  if (scene_ == nullptr) throw UsageError("broad phase: build() must be called before detection");
  use_stream(stream);
  DeviceMemoryTracker::instance().reset_peak();
  const auto start = std::chrono::steady_clock::now();
  double visit_seconds = 0;
  last_parts_ = 0;
  triangle_pairs_on_device(d_x, d_x, stream, FeatureRoom{}, nullptr, [&](TrianglePair* pairs, std::size_t pair_count) {
    const auto visit_start = std::chrono::steady_clock::now();
    DeviceCandidates chunk;
    chunk.pairs = pairs;
    chunk.pair_count = pair_count;
    visit(chunk);
    visit_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - visit_start).count();
  });
  DeviceMemoryTracker::set_stage("other");
  stats_.candidates = stats_.triangle_pairs;
  stats_.seconds_total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - visit_seconds;
  stats_.memory_bytes = DeviceMemoryTracker::instance().peak_bytes();
}

void CudaBroadPhase::detect_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                std::vector<VertexFaceCandidate>& vf, std::vector<EdgeEdgeCandidate>& ee) {
  check_positions(scene_, x_t0.size(), "x_t0");
  check_positions(scene_, x_t1.size(), "x_t1");
  use_stream(stream_);
  buffers_->x_t0.upload(x_t0);
  buffers_->x_t1.upload(x_t1);
  vf.clear();
  ee.clear();
  detect_ccd_on_device(buffers_->x_t0.data(), buffers_->x_t1.data(), stream_, [&](const DeviceCandidates& chunk) {
    append_download(chunk.vf, chunk.vf_count, vf, stream_);
    append_download(chunk.ee, chunk.ee_count, ee, stream_);
  });
  // Chunks are sorted each; more than one part: the whole sorted as the CPU's.
  if (last_parts_ > 1) {
    std::sort(vf.begin(), vf.end());
    std::sort(ee.begin(), ee.end());
  }
}

void CudaBroadPhase::detect_static(const std::vector<Vec3>& x, std::vector<TrianglePair>& pairs) {
  check_positions(scene_, x.size(), "x");
  use_stream(stream_);
  buffers_->x_t0.upload(x);
  pairs.clear();
  detect_static_on_device(buffers_->x_t0.data(), stream_, [&](const DeviceCandidates& chunk) {
    append_download(chunk.pairs, chunk.pair_count, pairs, stream_);  // chunks ascend
  });
}

std::vector<std::pair<std::string, std::size_t>> CudaBroadPhase::memory_census() const {
  std::vector<std::pair<std::string, std::size_t>> census;
  if (buffers_ == nullptr) return census;
  const CudaBroadPhaseBuffers& b = *buffers_;
  auto add = [&](const char* name, std::size_t bytes) { census.emplace_back(name, bytes); };
  add("topology", b.topology.triangles.capacity_bytes() + b.topology.edges.capacity_bytes() +
                      b.topology.masks.capacity_bytes() + b.topology.edge_ids.capacity_bytes());
  add("uploaded positions", b.x_t0.capacity_bytes() + b.x_t1.capacity_bytes());
  add("bounds: triangle DOPs", b.bounds.triangles.capacity_bytes());
  add("bounds: triangle float boxes", b.bounds.triangle_boxes.capacity_bytes());
  add("bounds: edge DOPs", b.bounds.edges.capacity_bytes());
  add("bounds: vertex DOPs", b.bounds.vertices.capacity_bytes());
  add("bounds: edge and vertex float boxes",
      b.bounds.edge_boxes.capacity_bytes() + b.bounds.vertex_boxes.capacity_bytes());
  add("bounds: radii, reductions", b.bounds.triangle_radii.capacity_bytes() + b.bounds.reduced.capacity_bytes());
  const DeviceSubdivision& s = b.subdivision;
  add("subdivision: leaves", s.leaves.capacity_bytes() + s.spare.capacity_bytes());
  add("subdivision: level lists", s.items.capacity_bytes() + s.next.capacity_bytes());
  add("subdivision: decisions, counts, scratch", s.decision.capacity_bytes() + s.home.capacity_bytes() +
                                                     s.tally.capacity_bytes() + s.state.capacity_bytes() +
                                                     s.temp.capacity_bytes());
  const DeviceCellLists& c = b.cells;
  add("registration: cell lists", c.cell_ids.capacity_bytes() + c.first.capacity_bytes() + c.leaves.capacity_bytes());
  add("registration: sort keys and values", c.keys.capacity_bytes() + c.keys_sorted.capacity_bytes() +
                                                c.values.capacity_bytes() + c.values_sorted.capacity_bytes());
  add("registration: offsets, tallies, scratch",
      c.offset.capacity_bytes() + c.tally.capacity_bytes() + c.temp.capacity_bytes());
  const DevicePairs& p = b.pairs;
  const DeviceAdaptiveCells& a = b.adaptive;
  add("adaptive: fine blocks and leaf DOPs", a.blocks.capacity_bytes() + a.leaf_dops.capacity_bytes());
  add("adaptive: test cells and members", a.cells.capacity_bytes() + a.members.capacity_bytes());
  add("adaptive: scratch", a.scratch_bytes());
  add("pairs: registered leaves", p.registered.capacity_bytes() + p.tile_members.capacity_bytes() +
                                      p.tile_boxes.capacity_bytes());
  add("pairs: registered leaves' sort", p.order_keys.capacity_bytes() + p.order_keys_spare.capacity_bytes() +
                                           p.order_ids.capacity_bytes() + p.order_ids_spare.capacity_bytes());
  add("pairs: cell tests and tiles", p.cell_test_bytes());
  add("pairs: kept test keys (chunk)", p.kept.capacity_bytes());
  add("pairs: sorted keys (chunk)", p.sorted.capacity_bytes());
  add("pairs: culled test keys", p.culled.capacity_bytes());
  add("pairs: unique pairs (chunk)", p.pairs.capacity_bytes());
  add("pairs: counters, histogram, scratch",
      p.counters.capacity_bytes() + p.histogram.capacity_bytes() + p.temp.capacity_bytes());
  const DeviceFeatures& f = b.features;
  add("features: tallies and kept bits (chunk)", f.tally.capacity_bytes() + f.kept.capacity_bytes());
  add("features: keys (part)", f.vf_keys.capacity_bytes() + f.ee_keys.capacity_bytes() +
                                   f.vf_sorted.capacity_bytes() + f.ee_sorted.capacity_bytes());
  add("features: candidates (part)", f.vf.capacity_bytes() + f.ee.capacity_bytes());
  add("features: scratch", f.counters.capacity_bytes() + f.bounds.capacity_bytes() + f.temp.capacity_bytes());
  std::sort(census.begin(), census.end(), [](const auto& x, const auto& y) { return x.second > y.second; });
  return census;
}

std::size_t CudaBroadPhase::held_bytes() const {
  std::size_t total = 0;
  for (const auto& entry : memory_census()) total += entry.second;
  return total;
}

GrowthCheck CudaBroadPhase::budget_check(const char* stage) {
  if (budget_ == 0) return {};
  return [this, stage](std::size_t bytes) {
    // The last detection's chunks, sized again once the registration is done,
    // give their room to a stage before the pair tests that needs it: else a
    // step whose stages grow (more leaves) would be refused under a limit at
    // which it fits alone.
    if (held_bytes() + bytes > budget_) release_chunk_buffers();
    const std::size_t held = held_bytes();
    if (held + bytes > budget_)
      throw UsageError("the device memory limit is too small for this scene: the broad phase's " + std::string(stage) +
                       " would hold " + std::to_string(held + bytes) + " bytes, its share of the limit is " +
                       std::to_string(budget_) + " bytes; raise the limit (snag-scan --device-memory)");
  };
}

namespace {

/// Calls `visit` on each buffer whose size the chunks bound.
template <class Visit>
void for_each_chunk_buffer(CudaBroadPhaseBuffers& b, Visit visit) {
  DevicePairs& p = b.pairs;
  DeviceFeatures& f = b.features;
  visit(p.kept);
  visit(p.sorted);
  visit(p.pairs);
  visit(p.cell_tests);
  visit(p.test_total);
  visit(p.cell_tiles);
  visit(p.first_tile);
  visit(p.row_begin);
  visit(p.row_end);
  visit(f.tally);
  visit(f.kept);
  for (DeviceBuffer<std::uint64_t>* keys : {&f.vf_keys, &f.ee_keys, &f.vf_sorted, &f.ee_sorted}) visit(*keys);
  visit(f.vf);
  visit(f.ee);
}

}  // namespace

std::size_t CudaBroadPhase::chunk_bytes() const {
  std::size_t bytes = 0;
  for_each_chunk_buffer(*buffers_, [&](const auto& buffer) { bytes += buffer.capacity_bytes(); });
  return bytes;
}

void CudaBroadPhase::release_chunk_buffers() {
  for_each_chunk_buffer(*buffers_, [](auto& buffer) { buffer.release(); });
}

void CudaBroadPhase::release_stage_buffers() {
  CudaBroadPhaseBuffers& b = *buffers_;
  b.subdivision.release();       // the last call's plan stays
  DeviceCellLists& c = b.cells;  // cell_ids and first stay: the tests read them
  for (DeviceBuffer<std::uint64_t>* scratch : {&c.offset, &c.keys, &c.keys_sorted}) scratch->release();
  for (DeviceBuffer<std::uint32_t>* scratch : {&c.values, &c.values_sorted, &c.leaves}) scratch->release();
  c.tally.release();
  c.temp.release();
  b.adaptive.release_scratch();
  b.pairs.order_keys.release();
  b.pairs.order_keys_spare.release();
  b.pairs.order_ids.release();
  b.pairs.order_ids_spare.release();
}

void CudaBroadPhase::release_buffers() {
  if (buffers_ == nullptr) return;
  CudaBroadPhaseBuffers& b = *buffers_;
  b.x_t0.release();
  b.x_t1.release();
  b.bounds = DevicePrimitiveBounds(stream_);
  b.subdivision = DeviceSubdivision(stream_);
  b.cells = DeviceCellLists(stream_);
  b.adaptive = DeviceAdaptiveCells(stream_);
  b.pairs = DevicePairs(stream_);
  b.features = DeviceFeatures(stream_);
}

std::unique_ptr<BroadPhase> make_cuda_broad_phase(BroadPhaseMethod method) { return CudaBroadPhase::create(method); }

std::unique_ptr<CudaBroadPhase> CudaBroadPhase::create(BroadPhaseMethod method) {
  if (method == BroadPhaseMethod::kVirtualSubdivisionGrid) return std::make_unique<CudaBroadPhase>(true);
  if (method == BroadPhaseMethod::kLargestTriangleGrid) return std::make_unique<CudaBroadPhase>(false);
  if (method == BroadPhaseMethod::kAdaptiveGrid) return std::make_unique<CudaBroadPhase>(true, true);
  // The CPU's others: brute force, the box grid, sweep and prune.
  throw UsageError(std::string("broad phase: the CUDA back end has no ") + broad_phase_method_name(method) +
                   " broad phase (it has vss-grid, largest-grid and adaptive-grid)");
}

}  // namespace snag
