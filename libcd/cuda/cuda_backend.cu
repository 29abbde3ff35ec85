// The CUDA back end: mirrors libcd/cpu/cpu_backend.cpp stage for stage.
//  - bind(): topology (triangles, edges) uploaded once; the device must hold
//    it and two frames of positions, else CudaError names the bytes.
//  - frames: two device slots, each with a pinned host mirror of what it
//    holds. A frame already in a slot (compared by content with the mirror:
//    the scan passes step f's x_t1 again as frame f + 1's x and step f + 1's
//    x_t0) is not uploaded again; a new frame is copied to the mirror and
//    uploaded on a copy stream while the broad phase runs, and the compute
//    stream waits for it with an event.
//  - broad phase: the GPU broad phase (libcd/cuda/cuda_broad_phase.hpp) when
//    this tree has it, else the CPU one; its candidates are uploaded.
//  - narrow phase: libcd/cuda/narrow_phase.cuh (same functions as the CPU).
//  - certification: the answers left uncertain go to settings.certifier on
//    the CPU, as in the CPU back end.
//  - events: built on the host from the same doubles with the same formulas
//    (event_position.hpp) and sorted with event_order: bit-identical to the
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
#include "libcd/cuda/cuda_check.cuh"
#include "libcd/cuda/cuda_event.cuh"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/cuda/narrow_phase.cuh"
#include "libcd/pipeline/event_builder.hpp"

#if __has_include("libcd/cuda/cuda_broad_phase.hpp")
#include "libcd/cuda/cuda_broad_phase.hpp"
#define SNAG_CUDA_BACKEND_GPU_BROAD_PHASE 1
#else
#define SNAG_CUDA_BACKEND_GPU_BROAD_PHASE 0
#endif

namespace snag {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::unique_ptr<BroadPhase> make_broad(BroadPhaseMethod method) {
#if SNAG_CUDA_BACKEND_GPU_BROAD_PHASE
  return make_cuda_broad_phase(method);
#else
  return make_broad_phase(method);
#endif
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

/// A CCD answer per candidate, kept by candidate index (as the CPU's CcdOutcome).
struct CcdOutcome {
  std::uint32_t candidate = 0;
  CcdResult result;
  bool certified = false;
};

class CudaBackend final : public Backend {
 public:
  explicit CudaBackend(BroadPhaseMethod method)
      : method_(method),
        triangles_(0, compute_.get()),
        edges_(0, compute_.get()),
        vf_device_(0, compute_.get()),
        ee_device_(0, compute_.get()),
        pairs_device_(0, compute_.get()),
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
    ccd_broad_ = make_broad(method_);
    static_broad_ = make_broad(method_);
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
    const int slot_t0 = upload_frame(x_t0, -1);
    const int slot_t1 = upload_frame(x_t1, slot_t0);
    arena_->execute([&] { ccd_broad_->detect_ccd(x_t0, x_t1, vf_, ee_); });
    stats_.ccd_broad = ccd_broad_->stats();

    const auto start = std::chrono::steady_clock::now();
    const std::size_t first = events.size();
    upload_candidates(vf_, vf_device_, "vertex-face candidates");
    upload_candidates(ee_, ee_device_, "edge-edge candidates");
    wait_for(slot_t0);
    wait_for(slot_t1);
    const Vec3* d_x_t0 = slots_[slot_t0].device.data();
    const Vec3* d_x_t1 = slots_[slot_t1].device.data();
    std::vector<CcdHit> vf_hits, ee_hits;
    narrow_.vertex_face(d_x_t0, d_x_t1, triangles_.data(), vf_device_.data(), vf_.size(), settings_.ccd,
                        CcdPasses::kScreenThenSearch, vf_hits);
    narrow_.edge_edge(d_x_t0, d_x_t1, edges_.data(), ee_device_.data(), ee_.size(), settings_.ccd,
                      CcdPasses::kScreenThenSearch, ee_hits);
    arena_->execute([&] {
      emit_vertex_face(x_t0, x_t1, vf_hits, events);
      emit_edge_edge(x_t0, x_t1, ee_hits, events);
    });
    std::sort(events.begin() + static_cast<std::ptrdiff_t>(first), events.end(), event_order);
    stats_.narrow.seconds_ccd = seconds_since(start) - stats_.narrow.seconds_certify;
  }

  void intersections(const std::vector<Vec3>& x, std::vector<Event>& events) override {
    require_bound(x.size() == scene_->vertex_count());
    stats_ = PipelineStats{};
    stats_.frames = 1;
    const int slot = upload_frame(x, -1);
    arena_->execute([&] { static_broad_->detect_static(x, pairs_); });
    stats_.static_broad = static_broad_->stats();

    const auto start = std::chrono::steady_clock::now();
    upload_candidates(pairs_, pairs_device_, "triangle pairs");
    wait_for(slot);
    std::vector<std::uint32_t> hits;
    TrianglePairCounts counts;
    narrow_.triangle_pairs(slots_[slot].device.data(), triangles_.data(), pairs_device_.data(), pairs_.size(), hits,
                           counts);
    stats_.narrow.predicate_calls = counts.predicate_calls;
    stats_.narrow.predicate_exact = counts.predicate_exact;
    stats_.narrow.triangle_tests = pairs_.size();
    arena_->execute([&] { append_intersection_events(*scene_, x, pairs_, hits, events); });
    stats_.narrow.triangles_intersecting += hits.size();
    stats_.narrow.seconds_static = seconds_since(start);
  }

  const PipelineStats& stats() const override { return stats_; }

 private:
  void require_bound(bool sizes_match) const {
    if (scene_ == nullptr) throw UsageError("the CUDA back end was used before bind()");
    if (!sizes_match) throw UsageError("the CUDA back end got positions whose count differs from the scene's");
  }

  // Returns the slot that holds x, uploading it into a slot other than
  // `keep` when no slot holds it yet.
  int upload_frame(const std::vector<Vec3>& x, int keep) {
    ++use_clock_;
    const std::size_t bytes = x.size() * sizeof(Vec3);
    for (int s = 0; s < 2; ++s) {
      FrameSlot& slot = slots_[s];
      if (slot.valid && slot.mirror.size() == x.size() &&
          (bytes == 0 || std::memcmp(slot.mirror.data(), x.data(), bytes) == 0)) {
        slot.last_use = use_clock_;
        return s;
      }
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

  template <class T>
  void upload_candidates(const std::vector<T>& host, DeviceBuffer<T>& device, const char* what) {
    resize_or_throw(device, host.size(), what);
    if (!host.empty()) {
      SNAG_CUDA_CHECK(cudaMemcpyAsync(device.data(), host.data(), host.size() * sizeof(T), cudaMemcpyHostToDevice,
                                      compute_.get()));
    }
  }

  // Counts the answers, certifies the uncertain ones and appends the events,
  // as the CPU back end's run_ccd does.
  template <class Emit>
  void finish_ccd(std::size_t tests, const std::vector<CcdHit>& hits, bool edge_edge, const Emit& emit,
                  std::vector<Event>& events) {
    std::vector<CcdOutcome> outcomes(hits.size());
    std::size_t yes = 0, uncertain = 0;
    std::vector<std::size_t> to_certify;
    for (std::size_t k = 0; k < hits.size(); ++k) {
      outcomes[k].candidate = hits[k].candidate;
      outcomes[k].result = hits[k].result;
      if (hits[k].result.answer == CcdAnswer::kYes) {
        ++yes;
      } else {
        ++uncertain;
        to_certify.push_back(k);
      }
    }
    (edge_edge ? stats_.narrow.ee_tests : stats_.narrow.vf_tests) += tests;
    (edge_edge ? stats_.narrow.ee_yes : stats_.narrow.vf_yes) += yes;
    (edge_edge ? stats_.narrow.ee_no : stats_.narrow.vf_no) += tests - yes - uncertain;
    (edge_edge ? stats_.narrow.ee_uncertain : stats_.narrow.vf_uncertain) += uncertain;
    const Certifier* certifier = settings_.certifier;
    if (certifier != nullptr && !to_certify.empty()) {
      const auto start = std::chrono::steady_clock::now();
      tbb::parallel_for(std::size_t{0}, to_certify.size(), [&](std::size_t j) {
        CcdOutcome& outcome = outcomes[to_certify[j]];
        const std::array<Vec3, 8> points = emit.points(outcome.candidate);
        const ExactAnswer exact = edge_edge ? certifier->edge_edge(points, settings_.thickness)
                                            : certifier->vertex_face(points, settings_.thickness);
        outcome.certified = true;
        outcome.result.answer = exact.collides ? CcdAnswer::kYes : CcdAnswer::kNo;
        outcome.result.toi_lo = exact.toi_lo;
        outcome.result.toi_hi = exact.toi_hi;
      });
      stats_.narrow.seconds_certify += seconds_since(start);
      stats_.narrow.certified += to_certify.size();
      for (std::size_t k : to_certify) stats_.narrow.certified_true += outcomes[k].result.answer == CcdAnswer::kYes;
    }
    for (const CcdOutcome& outcome : outcomes) {
      if (outcome.result.answer == CcdAnswer::kNo) continue;
      events.push_back(emit.event(outcome.candidate, outcome.result));
    }
  }

  void emit_vertex_face(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, const std::vector<CcdHit>& hits,
                        std::vector<Event>& events) {
    struct Emit {
      const Scene& scene;
      const std::vector<VertexFaceCandidate>& candidates;
      const std::vector<Vec3>& x_t0;
      const std::vector<Vec3>& x_t1;
      std::array<Vec3, 8> points(std::uint32_t i) const { return vertex_face_points(scene, x_t0, x_t1, candidates[i]); }
      Event event(std::uint32_t i, const CcdResult& result) const {
        return vertex_face_event(scene, x_t0, x_t1, candidates[i], result);
      }
    } emit{*scene_, vf_, x_t0, x_t1};
    finish_ccd(vf_.size(), hits, false, emit, events);
  }

  void emit_edge_edge(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, const std::vector<CcdHit>& hits,
                      std::vector<Event>& events) {
    struct Emit {
      const Scene& scene;
      const std::vector<EdgeEdgeCandidate>& candidates;
      const std::vector<Vec3>& x_t0;
      const std::vector<Vec3>& x_t1;
      std::array<Vec3, 8> points(std::uint32_t i) const { return edge_edge_points(scene, x_t0, x_t1, candidates[i]); }
      Event event(std::uint32_t i, const CcdResult& result) const {
        return edge_edge_event(scene, x_t0, x_t1, candidates[i], result);
      }
    } emit{*scene_, ee_, x_t0, x_t1};
    finish_ccd(ee_.size(), hits, true, emit, events);
  }

  BroadPhaseMethod method_;
  // Declared first: the buffers below are freed in their streams' order.
  Stream compute_, copy_;
  const Scene* scene_ = nullptr;
  BackendSettings settings_;
  std::unique_ptr<BroadPhase> ccd_broad_, static_broad_;
  std::unique_ptr<tbb::task_arena> arena_;
  DeviceBuffer<Triangle> triangles_;
  DeviceBuffer<Edge> edges_;
  DeviceBuffer<VertexFaceCandidate> vf_device_;
  DeviceBuffer<EdgeEdgeCandidate> ee_device_;
  DeviceBuffer<TrianglePair> pairs_device_;
  CudaNarrowPhase narrow_;
  FrameSlot slots_[2];
  unsigned long long use_clock_ = 0;
  std::vector<VertexFaceCandidate> vf_;
  std::vector<EdgeEdgeCandidate> ee_;
  std::vector<TrianglePair> pairs_;
  PipelineStats stats_;
};

}  // namespace

std::unique_ptr<Backend> make_cuda_backend(BroadPhaseMethod broad_phase) {
  return std::make_unique<CudaBackend>(broad_phase);
}

}  // namespace snag
