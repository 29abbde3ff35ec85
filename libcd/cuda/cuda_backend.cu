// The CUDA back end: mirrors libcd/cpu/cpu_backend.cpp stage for stage.
//  - bind(): topology (triangles, edges) uploaded once; the device must hold
//    it and three frames of positions, else CudaError names the bytes.
//  - frames: three device slots, each with a pinned host mirror of what it
//    holds. A frame already in a slot (compared by content with the mirror:
//    the scan passes step f's x_t1 again as frame f + 1's x and step f + 1's
//    x_t0) is not uploaded again; a new frame is copied to the mirror and
//    uploaded on a copy stream, and the compute stream waits for it with an
//    event. prepare() starts the upload of a frame the scan will ask about
//    into the slot used least recently of those no work ahead reads, so it
//    overlaps the work on the current one.
//  - broad phase: the GPU broad phase (libcd/cuda/cuda_broad_phase.cuh) on the
//    positions in the slots; its candidates stay on the device, unsorted,
//    and where they would take a narrow phase more than one round, its
//    feature stage runs the CCD early exits on them first (FeatureScreen),
//    so that it hands on only the few they leave undecided (the step's query
//    counts come from its stats).
//  - narrow phase: libcd/cuda/narrow_phase.cuh (same functions as the CPU),
//    reading the broad phase's candidates in place, the vertex-face and the
//    edge-edge queries one after the other, each with its own buffers, so
//    that the host copies both's events (set_defer_events) only once the
//    device has its next work (see overlap below), on a thread of their own
//    (event_copies_), so that the thread that drives the device never waits
//    for a large list to grow. The GPU runs the screen
//    (early exits and the search over time) and builds the hits' events
//    (event_fields.hpp, the CPU's formulas); only the events come back to
//    the host. The few candidates the screen
//    leaves undecided (their events say kUncertain) get the whole test on the
//    CPU (settle_collision_events), where one long (t, u, v) search does not
//    hold up a kernel.
//  - certification: the answers left uncertain go to settings.certifier on
//    the CPU, as in the CPU back end.
//  - events: built on the device from the same doubles with the same
//    formulas (compiled with --fmad=false), each narrow round's in event
//    order (the round's few hits sorted on the device, not the candidates),
//    settled on the host, and sorted with event_order when they came in
//    several chunks or rounds: bit-identical to the CPU back end's.
//    Intersection events are built on the device too.
//  - device memory: everything the back end allocates (DeviceBuffer) stays
//    within a budget: BackendSettings::device_memory_bytes, or what the
//    device has free at bind() less a margin. The CCD detection (broad and
//    narrow phase) and the static one never run on the device at the same
//    time, so each gets what the budget leaves beside the other's buffers and
//    the topology and frames; the broad phase turns that into chunks of
//    candidates (cuda_broad_phase.cuh), the narrow phases into rounds (the
//    CCD's two share the narrow phase's room). The
//    hits of several chunks are put back in event order, so the events
//    are those of one chunk. When the other detection holds more than half
//    of what the topology and frames leave, it gives its buffers back first;
//    when it holds less and the limit refuses this one, it gives them back
//    and this one runs again, with the room it would have alone.
//  - overlap: the scan prepares frame f + 2, then asks for the collisions of
//    f -> f + 1, then for frame f's intersections. As soon as its own device
//    work is done, before its events are copied on the host, collisions()
//    starts on a thread kept for it (the worker): the static detection of
//    its x_t0 (its own stream, broad phase and narrow phase) once
//    intersections have been asked for, then the CCD of the step after it,
//    f + 1 -> f + 2, when f + 2 was prepared since x_t1 (its events staged
//    once the host has copied this step's). When the budget has room for
//    both detections at once (run_together), the static one runs on a second
//    worker beside the CCD, each in half of the room, and the device
//    interleaves their kernels on their two streams; a detection that does
//    not fit its half is run again alone by the call that asks for it, and
//    later steps run them one after the other. The device then works on while
//    the host copies, searches, certifies and orders the step's events and
//    the scan hands the frame on: intersections() copies the static events
//    from where the device left them into the caller's list, and the next
//    collisions() finds its step detected (else it drops that work and
//    detects its own). A slot is never overwritten while that work reads it.
//    Frame f's static test run instead inside the CCD of f -> f + 1, on each
//    chunk's triangle pairs that the separation leaves (two triangles that
//    intersect at the step's start are in contact then), with no static
//    broad phase, gave the same events but took longer through snag-scan
//    -m all (H100, medians of 3: ×16 49.75 -> 54.77 ms a step, ×4 10.54 ->
//    11.77, cloth_ball 3.96 -> 4.64): it tests more pairs (×16: 12.9 M a
//    frame against 9.7 M), in the CCD's chain, while the static detection
//    it replaces runs beside the CCD on its own stream.
#include "libcd/cuda/cuda_backend.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <functional>
#include <future>
#include <string>
#include <utility>

#include "libcd/core/error.hpp"
#include "libcd/core/worker_thread.hpp"
#include "libcd/cuda/cuda_broad_phase.cuh"
#include "libcd/cuda/cuda_check.cuh"
#include "libcd/cuda/cuda_event.cuh"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/cuda/device_scan.cuh"
#include "libcd/cuda/narrow_phase.cuh"
#include "libcd/pipeline/event_builder.hpp"

namespace snag {

namespace {

/// What the budget leaves out by default: the CUDA context, the kernels'
/// local memory (their stack frames, reserved for every resident thread) and
/// the memory pool's slack, none of which DeviceBuffer counts.
constexpr std::size_t kDefaultMarginBytes = std::size_t{2} << 30;
/// The most device memory a detection's chunk buffers take by default, when
/// the budget is larger: chunks cost little (each test still runs once), and
/// a large scene then needs a few GB rather than what is free. Each chunk
/// tests its cells' tiles again (cloth_ball ×16, H200, all kernels a step:
/// 86.9 ms in 8 chunks of 1 GB, 84.4 in 4 of 2 GB, 83.4 in 2 of 4 GB, the
/// device's peak 4,879, 5,647 and 7,087 MiB). Later, at 3 GB, ×16 (CCD and
/// static) took two CCD chunks instead of three and 51.6 ms of device time a
/// step against 52.2 to 52.5 (H100, two runs), its peak 7,215 MiB against
/// 6,831; through snag-scan it was faster in 3 of 5 runs with the CCD alone
/// and in 2 of 5 with the static detection.
constexpr std::size_t kChunkRoomCap = std::size_t{2} << 30;
/// The narrow phase's share of a detection's budget, at most this much.
constexpr std::size_t kNarrowRoomCap = std::size_t{512} << 20;
/// Frames on the device: a step's two, and the frame after them, which the
/// next step's detection ahead reads.
constexpr int kFrameSlots = 3;

/// Lets the device's default memory pool, from which every DeviceBuffer is
/// allocated (cudaMallocAsync), keep up to `bytes` it has reserved when
/// buffers are freed, instead of giving them back to the driver at every
/// synchronisation (its default threshold is 0): a step frees and allocates
/// its chunks and staging buffers again, and memory given back must be
/// mapped again, which stalls the stream for each large buffer. Never
/// lowers a threshold that is already higher.
void keep_pool_memory(std::size_t bytes) {
  int device = 0;
  SNAG_CUDA_CHECK(cudaGetDevice(&device));
  cudaMemPool_t pool = nullptr;
  SNAG_CUDA_CHECK(cudaDeviceGetDefaultMemPool(&pool, device));
  std::uint64_t threshold = 0;  // the attribute's cuuint64_t
  SNAG_CUDA_CHECK(cudaMemPoolGetAttribute(pool, cudaMemPoolAttrReleaseThreshold, &threshold));
  if (threshold >= bytes) return;
  threshold = bytes;
  SNAG_CUDA_CHECK(cudaMemPoolSetAttribute(pool, cudaMemPoolAttrReleaseThreshold, &threshold));
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// A stream that is destroyed with its owner, at the default priority. With
/// the CCD's stream at the device's highest and the static detection's at
/// its lowest, snag-scan -m all took 0.984 of the time on ×16 but 1.12 on ×4;
/// the reverse, 0.995 and 1.005 (H100, medians of 3 and 5 runs against the
/// same build).
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

/// One detection's device parts: its broad phase and its narrow phases (the
/// CCD's vertex-face and edge-edge, or the static one alone), which share
/// the narrow phase's room in rounds of narrow_bytes_per_candidate.
struct Detection {
  CudaBroadPhase* broad = nullptr;
  std::array<CudaNarrowPhase*, 2> narrow{};
  std::size_t narrow_bytes_per_candidate = 0;

  std::size_t held_bytes() const {
    std::size_t bytes = broad->held_bytes();
    for (const CudaNarrowPhase* part : narrow)
      if (part != nullptr) bytes += part->held_bytes();
    return bytes;
  }
  void release_buffers() const {
    broad->release_buffers();
    for (CudaNarrowPhase* part : narrow)
      if (part != nullptr) part->release_buffers();
  }
};

/// One step's CCD on the device (CudaBackend::detect_ccd): the slots of its
/// frames, the events of its chunks but the last (whose the narrow phases
/// leave staged), and the counts.
struct CcdFound {
  int slot_t0 = -1, slot_t1 = -1;
  std::vector<Event> events;  ///< detected ahead: the events of the chunks before the last
  std::size_t vf_count = 0, ee_count = 0;  ///< the queries: every candidate, those the feature stage screened out too
  /// Chunks of the broad phase's candidates, and the most rounds one of the
  /// two narrow phases ran in (each round's events are in event order, and
  /// vertex-face events come before edge-edge ones): the step's events are in
  /// event order when both are at most 1.
  std::size_t chunks = 0, rounds = 0;
  BroadPhaseStats broad;
  double narrow_seconds = 0, device_seconds = 0;
};

/// Sets a promise when it goes, whichever way: a thread waiting on it is
/// never left waiting.
class SetOnExit {
 public:
  explicit SetOnExit(std::promise<void>& promise) : promise_(promise) {}
  ~SetOnExit() { promise_.set_value(); }
  SetOnExit(const SetOnExit&) = delete;
  SetOnExit& operator=(const SetOnExit&) = delete;

 private:
  std::promise<void>& promise_;
};

/// Waits for a TaskQueueThread when it goes, whichever way: its tasks are
/// done before what they write is read or freed (an error of theirs while
/// another unwinds is dropped: the one unwinding is reported).
class WaitOnExit {
 public:
  explicit WaitOnExit(TaskQueueThread& thread) : thread_(thread) {}
  ~WaitOnExit() {
    try {
      thread_.wait();
    } catch (...) {
    }
  }
  WaitOnExit(const WaitOnExit&) = delete;
  WaitOnExit& operator=(const WaitOnExit&) = delete;

 private:
  TaskQueueThread& thread_;
};

/// One frame's static detection on the device: its intersection events
/// (built on the device) and the counts.
struct StaticFound {
  std::vector<Event> events;
  TrianglePairCounts counts;
  BroadPhaseStats broad;
  std::size_t tests = 0;
  double narrow_seconds = 0, device_seconds = 0;
};

class CudaBackend final : public Backend {
 public:
  explicit CudaBackend(BroadPhaseMethod method)
      : method_(method),
        triangles_(0, compute_.get()),
        edges_(0, compute_.get()),
        narrow_(compute_.get()),
        edge_narrow_(compute_.get()),
        static_narrow_(static_stream_.get()),
        slots_{FrameSlot(copy_.get()), FrameSlot(copy_.get()), FrameSlot(copy_.get())} {
    narrow_.set_defer_events(true);
    edge_narrow_.set_defer_events(true);
    static_narrow_.set_defer_events(true);
    narrow_.set_event_copies(&event_copies_);
    edge_narrow_.set_event_copies(&event_copies_);
  }

  ~CudaBackend() override {
    // Buffers are freed in stream order; let the work using them finish first.
    join_worker();  // its errors went to futures nobody asks any more
    (void)cudaStreamSynchronize(static_stream_.get());
    (void)cudaStreamSynchronize(compute_.get());
    (void)cudaStreamSynchronize(copy_.get());
  }

  std::string name() const override { return "cuda"; }

  void bind(const Scene& scene, const BackendSettings& settings) override {
    drop_ahead();
    prepared_slot_ = -1;
    static_narrow_.drop_events();
    static_seen_ = false;
    together_allowed_ = true;
    scene_ = &scene;
    settings_ = settings;
    settings_.ccd.thickness = settings.thickness;
    BroadPhaseSettings broad;
    broad.lambda = settings.lambda;
    broad.thickness = settings.thickness;
    broad.threads = settings.threads;
    ccd_broad_ = CudaBroadPhase::create(method_);
    static_broad_ = CudaBroadPhase::create(method_);
    // On the streams their detections run on: the topology is uploaded once,
    // and the representatives, which the static detection does not use, to
    // the continuous one's broad phase alone.
    ccd_broad_->set_stream(compute_.get());
    static_broad_->set_stream(static_stream_.get());
    ccd_broad_->build(scene, broad);
    ccd_broad_->upload_representatives();
    BroadPhaseSettings static_settings = broad;
    static_settings.thickness = 0;
    static_broad_->build(scene, static_settings);
    // The CCD's candidates come unsorted (in the order of their triangle
    // pairs): each narrow round sorts its hits instead, a few in a thousand
    // of them, into the event order of their kind.
    const int face_bits = detail::radix_bits(scene.triangle_count() > 0 ? scene.triangle_count() - 1 : 0);
    const int vertex_bits = detail::radix_bits(scene.vertex_count() > 0 ? scene.vertex_count() - 1 : 0);
    const int edge_bits = detail::radix_bits(scene.edge_count() > 0 ? scene.edge_count() - 1 : 0);
    narrow_.set_event_order(face_bits, vertex_bits + face_bits);
    edge_narrow_.set_event_order(edge_bits, 2 * edge_bits);
    // The scan's thread copies and settles a step's events in this arena. Not
    // at a higher priority than the others: the report's sink, the slowest
    // stage of a scan with intersections, would lose its workers to it.
    arena_ = std::make_unique<tbb::task_arena>(
        settings.threads == 0 ? tbb::task_arena::automatic : static_cast<int>(settings.threads), 1,
        tbb::task_arena::priority::normal);

    const std::size_t needed = scene.triangle_count() * sizeof(Triangle) + scene.edge_count() * sizeof(Edge) +
                               kFrameSlots * scene.vertex_count() * sizeof(Vec3);
    std::size_t free_bytes = 0, total_bytes = 0;
    SNAG_CUDA_CHECK(cudaMemGetInfo(&free_bytes, &total_bytes));
    budget_ = settings.device_memory_bytes > 0 ? settings.device_memory_bytes
              : free_bytes > kDefaultMarginBytes ? free_bytes - kDefaultMarginBytes
                                                 : free_bytes / 2;
    keep_pool_memory(budget_);
    if (needed > free_bytes) {
      throw CudaError("the scene does not fit in GPU memory: its topology and " + std::to_string(kFrameSlots) +
                          " frames need " + std::to_string(needed) + " bytes, " + std::to_string(free_bytes) + " of " +
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
    const std::size_t bound = bound_bytes();
    if (bound >= budget_)
      throw UsageError("the device memory limit of " + std::to_string(budget_) +
                       " bytes is too small for this scene: its topology and " + std::to_string(kFrameSlots) +
                       " frames take " + std::to_string(bound) + " bytes; raise the limit (snag-scan --device-memory)");
  }

  void collisions(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, std::vector<Event>& events) override {
    require_bound(x_t0.size() == x_t1.size() && x_t0.size() == scene_->vertex_count());
    stats_ = PipelineStats{};
    stats_.steps = 1;
    // Each frame is looked up once (a full compare when it is there); a
    // prepared x_t1 is kept while x_t0 is uploaded.
    const int found_t1 = find_frame(x_t1);
    const int found_t0 = find_frame(x_t0);
    // The step detected ahead, when it is this one; else its work is dropped
    // (an error of it too: this step's detection meets its own).
    // Detected beside the static detection, it may have lacked room that it
    // has alone: then this step is detected here, and later ones alone too.
    bool ahead = false;
    if (ccd_ahead_.valid()) {
      ahead = found_t0 >= 0 && found_t0 == ccd_ahead_found_.slot_t0 && found_t1 == ccd_ahead_found_.slot_t1;
      try {
        ccd_ahead_.get();
      } catch (const UsageError&) {
        if (ahead && !ccd_ahead_together_) throw;
        if (ccd_ahead_together_) together_allowed_ = false;
        ahead = false;
      } catch (...) {
        if (ahead) throw;
      }
    }
    join_worker();  // one detection on the device at a time (see the file comment)
    if (!ahead) {
      narrow_.drop_events();
      edge_narrow_.drop_events();
    }
    const int slot_t0 = upload_frame(x_t0, found_t0, found_t1);
    const int slot_t1 = upload_frame(x_t1, found_t1, slot_t0);

    const std::size_t first = events.size();
    if (ahead) {
      std::swap(ccd_found_, ccd_ahead_found_);  // the next step's detection ahead fills the other
    } else {
      ccd_found_.slot_t0 = slot_t0;
      ccd_found_.slot_t1 = slot_t1;
      detect_ccd(slot_t0, slot_t1, events, ccd_found_);
    }
    const CcdFound& found = ccd_found_;
    stats_.ccd_broad = found.broad;
    stats_.narrow.seconds_ccd_device = found.device_seconds;
    double narrow_seconds = found.narrow_seconds;
    // The device is free: x_t0's intersections, which the scan asks for
    // next, and the collisions of the step after this one when its frame
    // was prepared, while the host works.
    // (A prepared frame equal to x_t0 shares its slot, as in a t0 t1 t0 ... sequence.)
    const int next_t1 = prepared_slot_ != slot_t1 ? prepared_slot_ : -1;
    prepared_slot_ = -1;
    std::promise<void> copied;  // the staged events are copied: the next step's detection may stage its own
    start_ahead(static_seen_ ? slot_t0 : -1, next_t1 >= 0 ? slot_t1 : -1, next_t1, copied.get_future().share());
    {
      const SetOnExit copying(copied);
      const auto flush_start = std::chrono::steady_clock::now();
      // Detected ahead: the events of the chunks before the last, then the
      // last's. An empty list (the scan's) trades places with them instead
      // of taking a copy; its room goes to a later step's work ahead.
      arena_->execute([&] {
        if (ahead && events.empty()) {
          std::swap(events, ccd_found_.events);
        } else if (ahead) {
          append_events(events, ccd_found_.events.data(), ccd_found_.events.size());
        }
        narrow_.flush_events_to(events);
        edge_narrow_.flush_events_to(events);
      });
      narrow_seconds += seconds_since(flush_start);
    }
    // What the screen left undecided: the whole test and certification, on
    // the CPU. Each round's events are in event order, vertex-face before
    // edge-edge; those of several chunks or rounds are put in event order
    // (settling drops events, keeping the order).
    const auto events_start = std::chrono::steady_clock::now();
    arena_->execute([&] {
      settle_collision_events(*scene_, x_t0, x_t1, found.vf_count, found.ee_count, settings_.ccd, settings_.certifier,
                              stats_.narrow, events, first, &event_scratch_);
      if (found.chunks > 1 || found.rounds > 1) sort_events_from(events, first, &event_scratch_);
    });
    stats_.narrow.seconds_ccd_events = seconds_since(events_start) - stats_.narrow.seconds_certify;
    // The narrow phase's rounds ran inside the broad phase's chunks.
    stats_.narrow.seconds_ccd = narrow_seconds + seconds_since(events_start) - stats_.narrow.seconds_certify;
  }

  void intersections(const std::vector<Vec3>& x, std::vector<Event>& events) override {
    require_bound(x.size() == scene_->vertex_count());
    stats_ = PipelineStats{};
    stats_.frames = 1;
    static_seen_ = true;
    const int slot = upload_frame(x, find_frame(x), -1);
    bool ahead = static_ahead_.valid() && static_ahead_slot_ == slot;
    if (ahead) {
      static_ahead_slot_ = -1;
      try {
        static_ahead_.get();  // started by collisions(); rethrows what it threw
      } catch (const UsageError&) {
        if (!static_ahead_together_) throw;
        together_allowed_ = false;  // beside the CCD it lacked room: alone here, and from now on
        ahead = false;
      }
    }
    if (!ahead) {
      static_ahead_ = {};
      static_ahead_slot_ = -1;
      join_worker();
      wait_for(static_stream_.get(), slot);
      find_static(slot);
    }
    const StaticFound& found = static_found_;
    stats_.static_broad = found.broad;
    stats_.narrow.seconds_static_device = found.device_seconds;
    stats_.narrow.predicate_calls = found.counts.predicate_calls;
    stats_.narrow.predicate_exact = found.counts.predicate_exact;
    stats_.narrow.triangle_tests = found.tests;
    // The events of a detection in chunks, then those of its last chunk,
    // from where the device left them.
    const auto events_start = std::chrono::steady_clock::now();
    const std::size_t before = events.size();
    arena_->execute([&] {
      append_events(events, found.events.data(), found.events.size());
      static_narrow_.flush_events_to(events);
    });
    const std::size_t intersecting = events.size() - before;
    stats_.narrow.seconds_static_events = seconds_since(events_start);
    stats_.narrow.triangles_intersecting += intersecting;
    stats_.narrow.seconds_static = found.narrow_seconds + stats_.narrow.seconds_static_events;
  }

  void prepare(const std::vector<Vec3>& x) override {
    require_bound(x.size() == scene_->vertex_count());
    prepared_slot_ = upload_frame(x, find_frame(x), -1);
  }

  const PipelineStats& stats() const override { return stats_; }

 private:
  void require_bound(bool sizes_match) const {
    if (scene_ == nullptr) throw UsageError("the CUDA back end was used before bind()");
    if (!sizes_match) throw UsageError("the CUDA back end got positions whose count differs from the scene's");
  }

  // Static detection of the frame in `slot` on the static stream (which
  // waits for the slot's upload first: wait_for), into static_found_: the
  // broad phase and the narrow phase on the device, the intersection events
  // downloaded, those of the last chunk left staged (static_narrow_ defers
  // them) for intersections() to copy into the caller's list. Runs on the
  // calling thread or as static_ahead_.
  void find_static(int slot) {
    StaticFound& found = static_found_;
    const Vec3* d_x = slots_[slot].device.data();
    auto visit_chunk = [&](const DeviceCandidates& chunk) {
      const auto start = std::chrono::steady_clock::now();
      static_narrow_.triangle_pair_events(d_x, triangles_.data(), chunk.pairs, chunk.pair_count, found.events,
                                          found.counts);
      found.tests += chunk.pair_count;
      found.narrow_seconds += seconds_since(start);
    };
    detect_within_budget(static_detection(), ccd_detection(), [&] {
      found.events.clear();
      static_narrow_.drop_events();
      found.counts = TrianglePairCounts{};
      found.tests = 0;
      found.narrow_seconds = 0;
      static_narrow_.reset_timings();
      static_broad_->detect_static_on_device(d_x, static_stream_.get(), visit_chunk);
    });
    found.broad = static_broad_->stats();
    found.device_seconds = 1e-3 * (static_narrow_.timings().static_ms + static_narrow_.timings().compact_ms);
  }

  // Device bytes of the topology and the frames (the back end's own buffers).
  std::size_t bound_bytes() const {
    std::size_t bytes = triangles_.capacity_bytes() + edges_.capacity_bytes();
    for (const FrameSlot& slot : slots_) bytes += slot.device.capacity_bytes();
    return bytes;
  }

  Detection ccd_detection() {
    return Detection{ccd_broad_.get(), {&narrow_, &edge_narrow_}, CudaNarrowPhase::kCcdBytesPerCandidate};
  }
  Detection static_detection() {
    return Detection{static_broad_.get(), {&static_narrow_, nullptr}, CudaNarrowPhase::kStaticBytesPerPair};
  }

  // Gives one detection what the budget leaves beside the other's buffers
  // (idle: detections never overlap), the topology and the frames: its
  // narrow phases a fifth of it (at most kNarrowRoomCap), shared equally, in
  // rounds of narrow_bytes_per_candidate, the broad phase the rest (its
  // chunks at most kChunkRoomCap). The other detection first gives its
  // buffers back when it holds more than half. When both run together
  // (together_), each gets half of it, and the other's buffers are left alone.
  void use_budget(const Detection& detection, const Detection& other) {
    const std::size_t available = budget_ - bound_bytes();  // bind() checked it is positive
    if (!together_ && other.held_bytes() > available / 2) other.release_buffers();
    const std::size_t taken = together_ ? available / 2 : other.held_bytes();
    if (taken >= available)
      throw UsageError("the device memory limit of " + std::to_string(budget_) +
                       " bytes is too small for this scene: " + std::to_string(bound_bytes() + taken) +
                       " bytes are taken before a detection starts; raise the limit (snag-scan --device-memory)");
    const std::size_t share = available - taken;
    const std::size_t narrow_room = std::min(kNarrowRoomCap, share / 5);
    const std::size_t part_room = narrow_room / (detection.narrow[1] != nullptr ? 2 : 1);
    const std::size_t rounds = std::min(CudaNarrowPhase::kDefaultChunkSize,
                                        std::max<std::size_t>(1, part_room / detection.narrow_bytes_per_candidate));
    for (CudaNarrowPhase* part : detection.narrow) {
      if (part == nullptr) continue;
      part->set_chunk_size(rounds);
      if (part->held_bytes() > part_room) part->release_buffers();
    }
    detection.broad->set_memory_budget(share - narrow_room, kChunkRoomCap);
  }

  // Runs `detect` (one detection from its start: it clears what an earlier
  // run of it left) with the room use_budget gives it. The other detection
  // keeps its buffers when they hold at most half of the room, which spares
  // the next step their allocation; when the limit then refuses this one
  // (UsageError), the other's buffers are given back and `detect` runs again
  // with all the room it would have alone. When that is refused too, its own
  // broad phase's buffers, sized by earlier steps, are given back, and it
  // runs once more as it would in a back end of its own: so a limit at which
  // each detection fits alone holds the whole scan. While both run together
  // the other's buffers are in use: the UsageError goes to the caller.
  template <class Detect>
  void detect_within_budget(const Detection& detection, const Detection& other, Detect detect) {
    bool own_released = false;
    for (;;) {
      use_budget(detection, other);
      try {
        detect();
        return;
      } catch (const UsageError&) {
        if (together_) throw;
        // The other's topology stays: it runs again only when giving its
        // buffers back freed some.
        const std::size_t other_held = other.held_bytes();
        other.release_buffers();
        if (other.held_bytes() < other_held) continue;
        if (own_released) throw;
        detection.broad->release_buffers();
        own_released = true;
      }
    }
  }

  // The CCD of the step in slots (slot_t0, slot_t1) on the compute stream,
  // into `found`: the broad phase, and both narrow phases' screens on each
  // chunk of its candidates. The events of each chunk but the last are
  // appended to `events`; the last's stay staged in the narrow phases (they
  // defer them). Runs on the calling thread, or on the worker ahead of the
  // step's collisions() call; then the events the narrow phases hold staged
  // may still be the host's to copy (collisions() copies them while this
  // runs), and `claim_staged` waits till they are copied: the broad phase
  // runs meanwhile, and the narrow phases' staged events are left alone
  // until it returns (the first pass starts with none staged).
  void detect_ccd(int slot_t0, int slot_t1, std::vector<Event>& events, CcdFound& found,
                  const std::function<void()>& claim_staged = [] {}) {
    wait_for(compute_.get(), slot_t0);
    wait_for(compute_.get(), slot_t1);
    const Vec3* d_x_t0 = slots_[slot_t0].device.data();
    const Vec3* d_x_t1 = slots_[slot_t1].device.data();
    const std::size_t first = events.size();
    bool claimed = false;
    auto claim = [&] {
      if (!std::exchange(claimed, true)) claim_staged();
    };
    // Each chunk's events are copied on the host when the next chunk comes
    // (vertex-face, then edge-edge), while the device works on its first
    // round: the staged events are claimed, then those the narrow phases
    // hold deferred appended in order, on event_copies_ (waited for before
    // `events` is read or cut, and before this returns).
    const WaitOnExit copied_on_exit(event_copies_);
    // Room for about as many events as the last step appended, taken at once
    // (untouched, so it costs no copy): else a large list would grow by
    // copying all it holds, tens of megabytes, while the narrow phase waits
    // for its buffer.
    events.reserve(first + ccd_events_last_ + ccd_events_last_ / 4);
    const std::function<void()> flush_deferred = [&] {
      claim();
      narrow_.flush_events();
      edge_narrow_.flush_events();
    };
    auto visit_chunk = [&](const DeviceCandidates& chunk) {
      const auto narrow_start = std::chrono::steady_clock::now();
      // Candidates the screen left need no early exits but the range check.
      const CcdPasses passes = chunk.screened ? CcdPasses::kQuickAfterEarlyExits : CcdPasses::kScreenOnly;
      narrow_.vertex_face_events(d_x_t0, d_x_t1, triangles_.data(), chunk.vf, chunk.vf_count, settings_.ccd, passes,
                                 events, flush_deferred);
      edge_narrow_.edge_edge_events(d_x_t0, d_x_t1, edges_.data(), chunk.ee, chunk.ee_count, settings_.ccd, passes,
                                    events, flush_deferred);
      ++found.chunks;
      found.narrow_seconds += seconds_since(narrow_start);
    };
    bool again = false;
    detect_within_budget(ccd_detection(), static_detection(), [&] {
      event_copies_.wait();
      events.resize(first);
      if (std::exchange(again, true)) {  // the pass before this one may have left events staged
        claim();
        narrow_.drop_events();
        edge_narrow_.drop_events();
      }
      narrow_.reset_timings();
      edge_narrow_.reset_timings();
      found.chunks = 0;
      found.narrow_seconds = 0;
      // The feature stage's screen only where a narrow phase would need
      // more than one round (cloth_ball ×4, ×16): below, their own early
      // exits cost less.
      ccd_broad_->detect_ccd_on_device(d_x_t0, d_x_t1, compute_.get(), visit_chunk, /*sorted=*/false,
                                       /*screen=*/&settings_.ccd,
                                       std::min(narrow_.chunk_size(), edge_narrow_.chunk_size()));
    });
    claim();  // a step without candidates
    event_copies_.wait();
    ccd_events_last_ = events.size() - first;
    found.broad = ccd_broad_->stats();
    // The queries: every candidate of the feature stage, with those its
    // screen decided (the narrow phases saw the rest).
    found.vf_count = found.broad.vf_after_culling;
    found.ee_count = found.broad.ee_after_culling;
    double device_ms = 0;
    for (const CudaNarrowPhase* part : {&narrow_, &edge_narrow_}) {
      const NarrowPhaseTimings& device = part->timings();
      device_ms += device.screen_ms + device.search_ms + device.compact_ms;
    }
    found.device_seconds = 1e-3 * device_ms;
    found.rounds = std::max(narrow_.timings().rounds, edge_narrow_.timings().rounds);
  }

  // Whether both detections fit in half of what the topology and frames
  // leave each, with room to grow: each held (its buffers kept from its last
  // run) at most a third of it. Neither has run yet: no.
  bool run_together() {
    if (!together_allowed_) return false;
    const std::size_t available = budget_ - bound_bytes();
    const std::size_t ccd = ccd_detection().held_bytes(), found_static = static_detection().held_bytes();
    return ccd > 0 && found_static > 0 && 3 * std::max(ccd, found_static) <= available;
  }

  // Starts, on this thread's device: find_static(static_slot) when it is not
  // -1 (static_ahead_), and when ccd_t0 is not -1 detect_ccd of the step
  // (ccd_t0, ccd_t1) into ccd_ahead_found_ (ccd_ahead_), its narrow phases
  // once `copied` says that the host has copied the events they hold
  // staged. Both on the worker, one after the other, or, when run_together()
  // says they fit, the static detection on static_worker_ beside the CCD.
  void start_ahead(int static_slot, int ccd_t0, int ccd_t1, std::shared_future<void> copied) {
    if (static_slot < 0 && ccd_t0 < 0) return;
    together_ = static_slot >= 0 && ccd_t0 >= 0 && run_together();
    int device = 0;
    SNAG_CUDA_CHECK(cudaGetDevice(&device));
    auto static_done = std::make_shared<std::promise<void>>();
    auto ccd_done = std::make_shared<std::promise<void>>();
    if (static_slot >= 0) {
      wait_for(static_stream_.get(), static_slot);
      static_ahead_ = static_done->get_future();
      static_ahead_slot_ = static_slot;
      static_ahead_together_ = together_;
    }
    if (ccd_t0 >= 0) {
      ccd_ahead_ = ccd_done->get_future();
      ccd_ahead_together_ = together_;
      std::vector<Event> room = std::move(ccd_ahead_found_.events);  // kept: a large step's events fill it again
      room.clear();
      ccd_ahead_found_ = CcdFound{};
      ccd_ahead_found_.events = std::move(room);
      ccd_ahead_found_.slot_t0 = ccd_t0;
      ccd_ahead_found_.slot_t1 = ccd_t1;
    }
    auto part = [device](std::promise<void>& done, const std::function<void()>& work) {
      try {
        SNAG_CUDA_CHECK(cudaSetDevice(device));
        work();
        done.set_value();
      } catch (...) {
        done.set_exception(std::current_exception());
      }
    };
    const bool together = together_;
    if (together) static_task_ = static_worker_.run([=] { part(*static_done, [&] { find_static(static_slot); }); });
    worker_task_ = worker_.run([=] {
      if (static_slot >= 0 && !together) part(*static_done, [&] { find_static(static_slot); });
      if (ccd_t0 >= 0) {
        part(*ccd_done, [&] {
          detect_ccd(ccd_t0, ccd_t1, ccd_ahead_found_.events, ccd_ahead_found_, [&] { copied.wait(); });
        });
      }
    });
  }

  // Waits for the workers' tasks, if any. Their errors are in their parts' futures.
  void join_worker() {
    if (worker_task_.valid()) worker_task_.wait();
    if (static_task_.valid()) static_task_.wait();
    together_ = false;
  }

  // Waits for the worker's task and forgets what it found: a slot it read
  // is about to change.
  void drop_ahead() {
    join_worker();
    static_ahead_ = {};
    ccd_ahead_ = {};
    static_ahead_slot_ = -1;
    narrow_.drop_events();
    edge_narrow_.drop_events();
  }

  // Whether the worker's task may still read `slot`.
  bool read_ahead(int slot) const {
    return (static_ahead_.valid() && static_ahead_slot_ == slot) ||
           (ccd_ahead_.valid() && (ccd_ahead_found_.slot_t0 == slot || ccd_ahead_found_.slot_t1 == slot));
  }

  // The slot that holds x, or -1.
  int find_frame(const std::vector<Vec3>& x) const {
    const std::size_t bytes = x.size() * sizeof(Vec3);
    for (int s = 0; s < kFrameSlots; ++s) {
      const FrameSlot& slot = slots_[s];
      if (slot.valid && slot.mirror.size() == x.size() &&
          (bytes == 0 || std::memcmp(slot.mirror.data(), x.data(), bytes) == 0))
        return s;
    }
    return -1;
  }

  // Returns the slot that holds x: `found` (find_frame(x)) when it is not -1,
  // else a slot other than `keep` into which x is uploaded: the least
  // recently used of those the worker's task does not read, if any (else
  // the task is waited for).
  int upload_frame(const std::vector<Vec3>& x, int found, int keep) {
    ++use_clock_;
    const std::size_t bytes = x.size() * sizeof(Vec3);
    if (found >= 0) {
      slots_[found].last_use = use_clock_;
      return found;
    }
    int s = -1;
    for (bool may_be_read : {false, true}) {
      for (int c = 0; c < kFrameSlots; ++c) {
        if (c == keep || (!may_be_read && read_ahead(c))) continue;
        if (s < 0 || slots_[c].last_use < slots_[s].last_use) s = c;
      }
      if (s >= 0) break;
    }
    if (read_ahead(s)) drop_ahead();
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

  void wait_for(cudaStream_t stream, int slot) {
    SNAG_CUDA_CHECK(cudaStreamWaitEvent(stream, slots_[slot].uploaded.get(), 0));
  }

  BroadPhaseMethod method_;
  // Declared first: the buffers below are freed in their streams' order.
  Stream compute_, copy_, static_stream_;
  const Scene* scene_ = nullptr;
  BackendSettings settings_;
  std::unique_ptr<CudaBroadPhase> ccd_broad_, static_broad_;
  std::unique_ptr<tbb::task_arena> arena_;
  DeviceBuffer<Triangle> triangles_;
  DeviceBuffer<Edge> edges_;
  CudaNarrowPhase narrow_;         ///< the CCD's vertex-face queries, on compute_
  CudaNarrowPhase edge_narrow_;    ///< the CCD's edge-edge queries, on compute_
  CudaNarrowPhase static_narrow_;  ///< on static_stream_
  FrameSlot slots_[kFrameSlots];
  unsigned long long use_clock_ = 0;
  StaticFound static_found_;
  CcdFound ccd_found_;          ///< the last step's CCD
  CcdFound ccd_ahead_found_;    ///< the next step's, detected ahead (ccd_ahead_)
  std::size_t ccd_events_last_ = 0;  ///< events the last CCD detection appended (its last chunk's stay staged)
  EventScratch event_scratch_;  ///< the settle's and the sort's room, kept from step to step
  bool static_seen_ = false;          ///< intersections() was called since bind()
  std::future<void> worker_task_;     ///< what start_ahead() gave the worker
  std::future<void> static_task_;     ///< what start_ahead() gave static_worker_
  bool together_ = false;             ///< the detections ahead run at once, each in half of the room (till joined)
  bool together_allowed_ = true;      ///< no detection ahead lacked room beside the other since bind()
  std::future<void> static_ahead_;    ///< find_static() running ahead, when valid
  int static_ahead_slot_ = -1;
  bool static_ahead_together_ = false;  ///< static_ahead_ ran beside the CCD (together_ when it started)
  std::future<void> ccd_ahead_;  ///< detect_ccd() of the next step running ahead, when valid
  bool ccd_ahead_together_ = false;  ///< ccd_ahead_ ran beside the static detection
  int prepared_slot_ = -1;       ///< the slot of the frame prepare() was given last, if no step used it yet
  PipelineStats stats_;
  std::size_t budget_ = 0;  ///< device bytes the back end may hold
  // Threads kept for the back end's life: a thread started for every frame,
  // with its first CUDA call, took nearly a millisecond before its first
  // kernel (cloth_ball on an H100). Last, so that they stop first.
  WorkerThread static_worker_;  ///< runs static_ahead_ beside ccd_ahead_ (together_)
  WorkerThread worker_;         ///< runs ccd_ahead_ and, one after the other, static_ahead_
  TaskQueueThread event_copies_;  ///< appends the CCD's deferred events (narrow_, edge_narrow_) in order
};

}  // namespace

std::unique_ptr<Backend> make_cuda_backend(BroadPhaseMethod broad_phase) {
  return std::make_unique<CudaBackend>(broad_phase);
}

}  // namespace snag
