// The CUDA back end: mirrors libcd/cpu/cpu_backend.cpp stage for stage.
//  - bind(): topology (triangles, edges) uploaded once; the device must hold
//    it and two frames of positions, else CudaError names the bytes.
//  - frames: two device slots, each with a pinned host mirror of what it
//    holds. A frame already in a slot (compared by content with the mirror:
//    the scan passes step f's x_t1 again as frame f + 1's x and step f + 1's
//    x_t0) is not uploaded again; a new frame is copied to the mirror and
//    uploaded on a copy stream, and the compute stream waits for it with an
//    event. prepare() starts the upload of the scan's next frame into the
//    slot used least recently, so it overlaps the work on the current one.
//  - broad phase: the GPU broad phase (libcd/cuda/cuda_broad_phase.cuh) on the
//    positions in the slots; its candidates stay on the device.
//  - narrow phase: libcd/cuda/narrow_phase.cuh (same functions as the CPU),
//    reading the broad phase's candidates in place; only the hits, and the
//    candidates they belong to, come back to the host. The GPU runs the
//    screen (early exits and the search over time); the few candidates it
//    leaves undecided get the whole test on the CPU (search_uncertain_hits),
//    where one long (t, u, v) search does not hold up a kernel.
//  - certification: the answers left uncertain go to settings.certifier on
//    the CPU, as in the CPU back end.
//  - events: built on the host from the same doubles with the same formulas
//    (event_builder.hpp) and sorted with event_order: bit-identical to the
//    CPU back end's.
#include "libcd/cuda/cuda_backend.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <string>

#include "libcd/core/error.hpp"
#include "libcd/cuda/cuda_broad_phase.cuh"
#include "libcd/cuda/cuda_check.cuh"
#include "libcd/cuda/cuda_event.cuh"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/cuda/narrow_phase.cuh"
#include "libcd/pipeline/event_builder.hpp"

namespace snag {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// A stream that is destroyed with its owner.
class Stream {
 public:
  Stream() { SNAG_CUDA_CHECK(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking)); }
  ~Stream() {
    if (stream_ != nullptr) (void)cudaStreamDestroy(stream_);
  }
  Stream(const Stream&) = delete;
  Stream& operator=(const Stream&) = delete;
  cudaStream_t get() const { return stream_; }

 private:
  cudaStream_t stream_ = nullptr;
};

/// One frame of positions on the device, with a pinned copy of what it holds.
struct FrameSlot {
  explicit FrameSlot(cudaStream_t copy_stream) : device(0, copy_stream) {}
  DeviceBuffer<Vec3> device;
  PinnedBuffer<Vec3> mirror;
  CudaEvent uploaded;
  bool valid = false;
  unsigned long long last_use = 0;
};

class CudaBackend final : public Backend {
 public:
  explicit CudaBackend(BroadPhaseMethod method)
      : method_(method),
        triangles_(0, compute_.get()),
        edges_(0, compute_.get()),
        narrow_(compute_.get()),
        slots_{FrameSlot(copy_.get()), FrameSlot(copy_.get())} {}

  ~CudaBackend() override {
    // Buffers are freed in stream order; let the work using them finish first.
    (void)cudaStreamSynchronize(compute_.get());
    (void)cudaStreamSynchronize(copy_.get());
  }

  std::string name() const override { return "cuda"; }

  void bind(const Scene& scene, const BackendSettings& settings) override {
    scene_ = &scene;
    settings_ = settings;
    settings_.ccd.thickness = settings.thickness;
    BroadPhaseSettings broad;
    broad.lambda = settings.lambda;
    broad.thickness = settings.thickness;
    broad.threads = settings.threads;
    ccd_broad_ = CudaBroadPhase::create(method_);
    static_broad_ = CudaBroadPhase::create(method_);
    ccd_broad_->build(scene, broad);
    BroadPhaseSettings static_settings = broad;
    static_settings.thickness = 0;
    static_broad_->build(scene, static_settings);
    arena_ = std::make_unique<tbb::task_arena>(settings.threads == 0 ? tbb::task_arena::automatic
                                                                     : static_cast<int>(settings.threads));

    const std::size_t needed = scene.triangle_count() * sizeof(Triangle) + scene.edge_count() * sizeof(Edge) +
                               2 * scene.vertex_count() * sizeof(Vec3);
    std::size_t free_bytes = 0, total_bytes = 0;
    SNAG_CUDA_CHECK(cudaMemGetInfo(&free_bytes, &total_bytes));
    if (needed > free_bytes) {
      throw CudaError("the scene does not fit in GPU memory: its topology and two frames need " +
                          std::to_string(needed) + " bytes, " + std::to_string(free_bytes) + " of " +
                          std::to_string(total_bytes) + " bytes are free; use --backend cpu",
                      static_cast<int>(cudaErrorMemoryAllocation));
    }
    resize_or_throw(triangles_, scene.triangle_count(), "the triangles");
    resize_or_throw(edges_, scene.edge_count(), "the edges");
    triangles_.upload(scene.triangles());
    edges_.upload(scene.edges());
    for (FrameSlot& slot : slots_) {
      resize_or_throw(slot.device, scene.vertex_count(), "a frame of positions");
      slot.mirror.resize(scene.vertex_count());
      slot.valid = false;
    }
    SNAG_CUDA_CHECK(cudaStreamSynchronize(compute_.get()));
    SNAG_CUDA_CHECK(cudaStreamSynchronize(copy_.get()));
  }

  void collisions(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, std::vector<Event>& events) override {
    require_bound(x_t0.size() == x_t1.size() && x_t0.size() == scene_->vertex_count());
    stats_ = PipelineStats{};
    stats_.steps = 1;
    // Each frame is looked up once (a full compare when it is there); a
    // prepared x_t1 is kept while x_t0 is uploaded.
    const int found_t1 = find_frame(x_t1);
    const int slot_t0 = upload_frame(x_t0, find_frame(x_t0), found_t1);
    const int slot_t1 = upload_frame(x_t1, found_t1, slot_t0);
    wait_for(slot_t0);
    wait_for(slot_t1);
    const Vec3* d_x_t0 = slots_[slot_t0].device.data();
    const Vec3* d_x_t1 = slots_[slot_t1].device.data();
    const DeviceCandidates candidates = ccd_broad_->detect_ccd_on_device(d_x_t0, d_x_t1, compute_.get());
    stats_.ccd_broad = ccd_broad_->stats();

    const auto start = std::chrono::steady_clock::now();
    const std::size_t first = events.size();
    // Host vectors are members, cleared and refilled: their pages stay mapped.
    vf_answers_.clear();
    ee_answers_.clear();
    vf_hits_.clear();
    ee_hits_.clear();
    narrow_.reset_timings();
    narrow_.vertex_face(d_x_t0, d_x_t1, triangles_.data(), candidates.vf, candidates.vf_count, settings_.ccd,
                        CcdPasses::kScreenOnly, vf_answers_, &vf_hits_.candidates);
    narrow_.edge_edge(d_x_t0, d_x_t1, edges_.data(), candidates.ee, candidates.ee_count, settings_.ccd,
                      CcdPasses::kScreenOnly, ee_answers_, &ee_hits_.candidates);
    const NarrowPhaseTimings& device = narrow_.timings();
    stats_.narrow.seconds_ccd_device = 1e-3 * (device.screen_ms + device.search_ms + device.compact_ms);
    for (const CcdHit& hit : vf_answers_) vf_hits_.results.push_back(hit.result);
    for (const CcdHit& hit : ee_answers_) ee_hits_.results.push_back(hit.result);
    // What the screen left undecided: the whole test, on the CPU.
    arena_->execute([&] {
      search_uncertain_hits(*scene_, x_t0, x_t1, settings_.ccd, vf_hits_);
      search_uncertain_hits(*scene_, x_t0, x_t1, settings_.ccd, ee_hits_);
    });
    const auto events_start = std::chrono::steady_clock::now();
    arena_->execute([&] {
      append_collision_events(*scene_, x_t0, x_t1, candidates.vf_count, vf_hits_, settings_.certifier,
                              settings_.thickness, stats_.narrow, events);
      append_collision_events(*scene_, x_t0, x_t1, candidates.ee_count, ee_hits_, settings_.certifier,
                              settings_.thickness, stats_.narrow, events);
    });
    sort_events_from(events, first);
    stats_.narrow.seconds_ccd_events = seconds_since(events_start) - stats_.narrow.seconds_certify;
    stats_.narrow.seconds_ccd = seconds_since(start) - stats_.narrow.seconds_certify;
  }

  void intersections(const std::vector<Vec3>& x, std::vector<Event>& events) override {
    require_bound(x.size() == scene_->vertex_count());
    stats_ = PipelineStats{};
    stats_.frames = 1;
    const int slot = upload_frame(x, find_frame(x), -1);
    wait_for(slot);
    const Vec3* d_x = slots_[slot].device.data();
    const DeviceCandidates candidates = static_broad_->detect_static_on_device(d_x, compute_.get());
    stats_.static_broad = static_broad_->stats();

    const auto start = std::chrono::steady_clock::now();
    static_hits_.clear();
    static_hit_pairs_.clear();
    TrianglePairCounts counts;
    narrow_.reset_timings();
    narrow_.triangle_pairs(d_x, triangles_.data(), candidates.pairs, candidates.pair_count, static_hits_, counts,
                           &static_hit_pairs_);
    stats_.narrow.seconds_static_device = 1e-3 * (narrow_.timings().static_ms + narrow_.timings().compact_ms);
    stats_.narrow.predicate_calls = counts.predicate_calls;
    stats_.narrow.predicate_exact = counts.predicate_exact;
    stats_.narrow.triangle_tests = candidates.pair_count;
    const auto events_start = std::chrono::steady_clock::now();
    arena_->execute([&] { append_intersection_events(*scene_, x, static_hit_pairs_, events); });
    stats_.narrow.seconds_static_events = seconds_since(events_start);
    stats_.narrow.triangles_intersecting += static_hits_.size();
    stats_.narrow.seconds_static = seconds_since(start);
  }

  void prepare(const std::vector<Vec3>& x) override {
    require_bound(x.size() == scene_->vertex_count());
    (void)upload_frame(x, find_frame(x), -1);
  }

  const PipelineStats& stats() const override { return stats_; }

 private:
  void require_bound(bool sizes_match) const {
    if (scene_ == nullptr) throw UsageError("the CUDA back end was used before bind()");
    if (!sizes_match) throw UsageError("the CUDA back end got positions whose count differs from the scene's");
  }

  // The slot that holds x, or -1.
  int find_frame(const std::vector<Vec3>& x) const {
    const std::size_t bytes = x.size() * sizeof(Vec3);
    for (int s = 0; s < 2; ++s) {
      const FrameSlot& slot = slots_[s];
      if (slot.valid && slot.mirror.size() == x.size() &&
          (bytes == 0 || std::memcmp(slot.mirror.data(), x.data(), bytes) == 0))
        return s;
    }
    return -1;
  }

  // Returns the slot that holds x: `found` (find_frame(x)) when it is not -1,
  // else a slot other than `keep` (the least recently used one when keep is
  // -1) into which x is uploaded.
  int upload_frame(const std::vector<Vec3>& x, int found, int keep) {
    ++use_clock_;
    const std::size_t bytes = x.size() * sizeof(Vec3);
    if (found >= 0) {
      slots_[found].last_use = use_clock_;
      return found;
    }
    int s = keep == 0 ? 1 : (keep == 1 ? 0 : (slots_[0].last_use <= slots_[1].last_use ? 0 : 1));
    FrameSlot& slot = slots_[s];
    slot.valid = false;
    // The previous upload from this mirror, and the work that read the slot
    // (every call waits for its compute stream), are done before it is reused.
    SNAG_CUDA_CHECK(cudaEventSynchronize(slot.uploaded.get()));
    slot.mirror.resize(x.size());
    if (bytes > 0) std::memcpy(slot.mirror.data(), x.data(), bytes);
    resize_or_throw(slot.device, x.size(), "a frame of positions");
    if (bytes > 0) {
      SNAG_CUDA_CHECK(
          cudaMemcpyAsync(slot.device.data(), slot.mirror.data(), bytes, cudaMemcpyHostToDevice, copy_.get()));
    }
    slot.uploaded.record(copy_.get());
    slot.valid = true;
    slot.last_use = use_clock_;
    return s;
  }

  void wait_for(int slot) { SNAG_CUDA_CHECK(cudaStreamWaitEvent(compute_.get(), slots_[slot].uploaded.get(), 0)); }

  BroadPhaseMethod method_;
  // Declared first: the buffers below are freed in their streams' order.
  Stream compute_, copy_;
  const Scene* scene_ = nullptr;
  BackendSettings settings_;
  std::unique_ptr<CudaBroadPhase> ccd_broad_, static_broad_;
  std::unique_ptr<tbb::task_arena> arena_;
  DeviceBuffer<Triangle> triangles_;
  DeviceBuffer<Edge> edges_;
  CudaNarrowPhase narrow_;
  FrameSlot slots_[2];
  unsigned long long use_clock_ = 0;
  std::vector<CcdHit> vf_answers_, ee_answers_;
  CcdHits<VertexFaceCandidate> vf_hits_;
  CcdHits<EdgeEdgeCandidate> ee_hits_;
  std::vector<std::uint32_t> static_hits_;
  std::vector<TrianglePair> static_hit_pairs_;
  PipelineStats stats_;
};

}  // namespace

std::unique_ptr<Backend> make_cuda_backend(BroadPhaseMethod broad_phase) {
  return std::make_unique<CudaBackend>(broad_phase);
}

}  // namespace snag
