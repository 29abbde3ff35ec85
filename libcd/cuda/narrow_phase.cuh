// The GPU narrow phase: one thread per candidate runs the same host/device
// tests as the CPU back end (vertex_face_ccd and edge_edge_ccd of
// libcd/narrow_phase/, triangles_intersect of triangle_triangle.hpp), then the
// hits are compacted with cub::DeviceSelect::Flagged, which keeps the input
// order, so the hits come back in candidate order exactly as on the CPU.
//
// CCD runs as a screen and a search by default (CcdPasses::kScreenThenSearch):
//  1. screen: every candidate runs the early exits of the CCD function
//     (vertex_face_early_exit, edge_edge_early_exit), which rule out most
//     candidates of a real scene; the survivors are compacted and run the
//     rest of its quick part (vertex_face_quick_search,
//     edge_edge_quick_search: at thickness 0 the search over time), side by
//     side in full warps. These
//     kernels hold no box heap: at most 128 registers and a 3 kB stack frame;
//  2. search: the candidates the screen found to be hits and those it left
//     undecided are compacted; the undecided ones run the whole function
//     (to the (t, u, v) search), the others keep the screen's result.
// The whole function is the early exits, then the time search, then the
// (t, u, v) search, so the answers equal the single pass's
// (CcdPasses::kSinglePass: the whole function over every candidate) and the
// CPU back end's.
//
// Resources (ptxas -v, sm_90, CUDA 13.0, --fmad=false): the whole-function
// kernels use 255 registers and a 17 kB stack frame (the 16 kB box heap of
// ccd_inclusion.hpp and about 1 kB of spills); the early exits are held to
// 128 registers (__launch_bounds__, 4 blocks of 128 per multiprocessor) with
// no spills, the rest of the quick part to 168 (3 blocks) with a 4 kB frame
// (the time search's stack, the exact predicates' expansions) and at most
// 0.3 kB of spills (with 4 blocks, 128 registers, its cloth-ball step took
// 1.79 + 3.77 ms, VF + EE, on an H100, against 1.29 + 3.64 ms with 3); the
// static kernel 222 registers and a 2.3 kB frame
// (the exact stages' expansions). The driver reserves local memory for the
// frame on every resident thread of the device, outside
// DeviceMemoryTracker's count.
//
// Device memory: every buffer is a DeviceBuffer (counted by
// DeviceMemoryTracker); a buffer that cannot grow throws CudaError naming the
// bytes it needed and the bytes free.
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "libcd/broad_phase/candidates.hpp"
#include "libcd/core/worker_thread.hpp"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/geometry/vec3.hpp"
#include "libcd/narrow_phase/ccd_result.hpp"
#include "libcd/pipeline/event.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag {

/// How the CCD kernels are scheduled (see the file comment).
enum class CcdPasses {
  kScreenThenSearch,  ///< the quick part over all candidates, the whole test over the undecided rest
  kSinglePass,        ///< the full search over all candidates at once
  /// The quick part only: the candidates it leaves undecided come back as
  /// hits whose answer is kUncertain, and the caller runs the whole test on
  /// them (the CUDA back end does, on the CPU: they are a handful whose
  /// (t, u, v) search takes one GPU thread milliseconds).
  kScreenOnly,
  /// As kScreenOnly, for candidates whose CCD early exits ran already and
  /// left them undecided or out of range (the CUDA feature stage's screen,
  /// FeatureScreen): of the early exits only the range check runs again.
  kQuickAfterEarlyExits,
};

/// A candidate the filter did not rule out: its index in the candidate list
/// and its answer (kYes or kUncertain).
struct CcdHit {
  std::uint32_t candidate = 0;
  CcdResult result;
};

/// Orientation predicates evaluated by the static test, and how many needed
/// the exact stage (PredicateCounters of predicates.hpp, summed per block).
/// predicates.hpp is kept out of this header: its out-of-line exact stages
/// are not `inline` under nvcc, so a second CUDA translation unit including it
/// would define them twice.
struct TrianglePairCounts {
  unsigned long long predicate_calls = 0;
  unsigned long long predicate_exact = 0;
};

/// Milliseconds of the last call, measured with CUDA events on its stream.
struct NarrowPhaseTimings {
  float screen_ms = 0;   ///< CCD screen pass: early exits and time search (or the single pass)
  float search_ms = 0;   ///< CCD full search over the screen's survivors
  float compact_ms = 0;  ///< compactions and downloads
  float static_ms = 0;   ///< triangle-pair tests
  std::size_t searched = 0;  ///< candidates that reached the search pass
  std::size_t rounds = 0;    ///< CCD rounds (set_chunk_size) the calls ran in
  std::size_t time_searches = 0;  ///< launches of the screen's time search (one or more a round)
};

/// Owns the device buffers of the narrow phase; reused from call to call.
/// Not thread-safe; one stream per object at a time.
class CudaNarrowPhase {
 public:
  /// Buffers are allocated and used on `stream`.
  explicit CudaNarrowPhase(cudaStream_t stream);

  /// Vertex-face CCD of `count` candidates (device arrays): positions
  /// x_t0/x_t1 (#V), triangles (#F). Appends the hits (answers other than
  /// kNo) to `hits` in candidate order and, when hit_candidates is given, the
  /// hit candidates themselves to it (gathered on the device, so that a
  /// caller whose candidates live only on the device gets just the hits).
  /// Waits for the stream. Throws CudaError.
  void vertex_face(const Vec3* x_t0, const Vec3* x_t1, const Triangle* triangles,
                   const VertexFaceCandidate* candidates, std::size_t count, const CcdSettings& settings,
                   CcdPasses passes, std::vector<CcdHit>& hits,
                   std::vector<VertexFaceCandidate>* hit_candidates = nullptr);

  /// Edge-edge CCD, as vertex_face with edges (#E) instead of triangles.
  void edge_edge(const Vec3* x_t0, const Vec3* x_t1, const Edge* edges, const EdgeEdgeCandidate* candidates,
                 std::size_t count, const CcdSettings& settings, CcdPasses passes, std::vector<CcdHit>& hits,
                 std::vector<EdgeEdgeCandidate>* hit_candidates = nullptr);

  /// Vertex-face CCD as vertex_face, with the hits built into collision
  /// events on the device (event_fields.hpp, the formulas of the CPU's
  /// event_builder.hpp: frame 0, certainty kUncertain where the screen left
  /// the candidate undecided) and appended to `events` in candidate order:
  /// only the events cross to the host. `passes` is kScreenOnly,
  /// kQuickAfterEarlyExits or kSinglePass (std::invalid_argument otherwise). `while_busy`, when
  /// given, runs once on this thread while the device works on the first
  /// round, before the events this object holds deferred are flushed (a
  /// caller that flushes another object's deferred events there keeps their
  /// order); it is not called when there is no round. Waits for the stream.
  /// Throws CudaError.
  void vertex_face_events(const Vec3* x_t0, const Vec3* x_t1, const Triangle* triangles,
                          const VertexFaceCandidate* candidates, std::size_t count, const CcdSettings& settings,
                          CcdPasses passes, std::vector<Event>& events,
                          const std::function<void()>& while_busy = nullptr);
  /// Edge-edge CCD as edge_edge, the hits built into events as vertex_face_events.
  void edge_edge_events(const Vec3* x_t0, const Vec3* x_t1, const Edge* edges, const EdgeEdgeCandidate* candidates,
                        std::size_t count, const CcdSettings& settings, CcdPasses passes, std::vector<Event>& events,
                        const std::function<void()>& while_busy = nullptr);

  /// Static test of `count` triangle pairs at positions x (#V): appends the
  /// indices of the intersecting pairs, in order, to `hits` (and the pairs
  /// themselves to hit_pairs when given), and adds the predicate counts to
  /// `counts`. Waits for the stream. Throws CudaError.
  void triangle_pairs(const Vec3* x, const Triangle* triangles, const TrianglePair* pairs, std::size_t count,
                      std::vector<std::uint32_t>& hits, TrianglePairCounts& counts,
                      std::vector<TrianglePair>* hit_pairs = nullptr);

  /// Static test as triangle_pairs, with the intersecting pairs built into
  /// intersection events (frame 0) on the device and appended to `events` in
  /// pair order; returns how many intersect. Waits for the stream. Throws
  /// CudaError.
  std::size_t triangle_pair_events(const Vec3* x, const Triangle* triangles, const TrianglePair* pairs,
                                   std::size_t count, std::vector<Event>& events, TrianglePairCounts& counts);

  /// Deferred events (off by default): the *_events calls then leave the
  /// events of their last round in pinned host memory instead of appending
  /// them, and flush_events() appends them to the vector that call was given,
  /// so that a caller can start other device work before the host copies
  /// them (tens of megabytes a step). The next call on this object flushes
  /// them once its first round's kernels are queued, before it stages its
  /// own; drop_events() forgets them.
  void set_defer_events(bool defer) { defer_events_ = defer; }
  void flush_events();
  /// As flush_events(), to `events` instead of the vector the call was given,
  /// always on this thread.
  void flush_events_to(std::vector<Event>& events);
  void drop_events() { pending_to_ = nullptr; }
  /// Deferred events that flush_events() appends go to `thread` (null: none,
  /// the default), which appends them while this thread drives the device: a
  /// large list grows by tens of megabytes a step, and the device would
  /// wait for that. Narrow phases that append to one list share a thread,
  /// which keeps the order they flush in; the list is complete once the
  /// thread has been waited for. Each round stages its events in the other
  /// of two pinned buffers, so the next round need not wait for the thread.
  void set_event_copies(TaskQueueThread* thread) { event_copies_ = thread; }

  /// The order of the events the CCD *_events calls build: with end_bit >
  /// 0, each round's hits are sorted by their candidates (the first id above
  /// the second, which takes low_bits bits; end_bit bits in all) before their
  /// events are built, so that a round's events are in event order whatever
  /// the candidates' order (the broad phase's unsorted candidates). 0 (the
  /// default): in candidate order.
  void set_event_order(int low_bits, int end_bit) {
    order_low_bits_ = low_bits;
    order_end_bit_ = end_bit;
  }

  /// Candidates (or pairs) per kernel round; a call over more runs in rounds
  /// of this many, so that the device memory of a call is bounded by the
  /// round, not by the candidate count. Results do not depend on it.
  void set_chunk_size(std::size_t candidates) { chunk_size_ = candidates > 0 ? candidates : 1; }
  std::size_t chunk_size() const { return chunk_size_; }
  static constexpr std::size_t kDefaultChunkSize = std::size_t{1} << 24;
  /// The most blocks the screen's time search runs (default: as many as are
  /// resident at once). Its lanes take the queries one after another, so
  /// results do not depend on it; a test can make every lane take many.
  void set_quick_block_limit(unsigned int blocks) { quick_block_limit_ = blocks > 0 ? blocks : 1; }
  /// Device bytes a round holds per CCD candidate (screen only: result,
  /// flag, index, compacted result, gathered candidate) and per static pair
  /// (flag, index, gathered pair), scratch included. Events built on the
  /// device take the room of the compacted result and gathered candidate (or
  /// pair) instead: they are built in slices that fit it. The screen's time
  /// search lists the queries it isolates in that room, or in what a round
  /// of fewer than chunk_size() candidates leaves of the round's room.
  static constexpr std::size_t kCcdBytesPerCandidate = 64;
  static constexpr std::size_t kStaticBytesPerPair = 16;

  /// Device bytes its buffers hold now.
  std::size_t held_bytes() const;
  /// Gives back its buffers (in stream order); they grow again on the next call.
  void release_buffers();

  /// Timings of the calls since the last reset.
  const NarrowPhaseTimings& timings() const { return timings_; }
  void reset_timings() { timings_ = NarrowPhaseTimings{}; }

 private:
  /// Where a call's hits go: hits (with hit_candidates or hit_pairs when
  /// not null), or events built on the device when `events` is not null.
  template <class Candidate>
  struct HitSink {
    std::vector<CcdHit>* hits = nullptr;
    std::vector<Candidate>* hit_candidates = nullptr;
    std::vector<Event>* events = nullptr;
    const std::function<void()>* while_busy = nullptr;  ///< see vertex_face_events; first round only
  };
  struct PairSink {
    std::vector<std::uint32_t>* hits = nullptr;
    std::vector<TrianglePair>* hit_pairs = nullptr;
    std::vector<Event>* events = nullptr;
  };
  template <class Query>
  void run_ccd(const Query& query, std::size_t count, const CcdSettings& settings, CcdPasses passes,
               const HitSink<typename Query::Candidate>& sink);
  /// One round: candidates [first, first + count) of the call, `query` starting at `first`.
  template <class Query>
  void run_ccd_chunk(const Query& query, std::size_t count, std::size_t first, const CcdSettings& settings,
                     CcdPasses passes, const HitSink<typename Query::Candidate>& sink);
  std::size_t run_triangle_pairs(const Vec3* x, const Triangle* triangles, const TrianglePair* pairs,
                                 std::size_t count, TrianglePairCounts& counts, const PairSink& sink);
  std::size_t triangle_pairs_chunk(const Vec3* x, const Triangle* triangles, const TrianglePair* pairs,
                                   std::size_t count, std::size_t first, TrianglePairCounts& counts,
                                   const PairSink& sink);
  /// Builds the events of `hits` hits on the device in slices of at most
  /// `slice` (launch(first, n, out) writes those of hits [first, first + n)
  /// to out) in gathered_, and queues their copies to pinned memory; once
  /// the stream is synchronised, append_staged_events gives gathered_ back
  /// and appends them to `events`, or defers that (set_defer_events).
  template <class Launch>
  void stage_events(std::size_t hits, std::size_t slice, Launch launch);
  void append_staged_events(std::size_t count, std::vector<Event>& events);
  /// Sorts the first `hits` indices of selected_ by their candidates'
  /// event order (set_event_order), with gathered_ as scratch (the room the
  /// hits' events take after it).
  template <class Candidate>
  void order_hits(const Candidate* candidates, std::size_t hits);
  /// Compacts the indices k < count of the flagged candidates into
  /// selected_ and their count into selected_count_, on the device.
  void select_flagged_on_device(std::size_t count);
  /// select_flagged_on_device, and the count read back.
  std::size_t select_flagged(std::size_t count);
  /// Gathers items[selected_[k]] for k < count on the device and queues their
  /// copy to pinned host memory; the returned array is valid once the stream
  /// is synchronised, until the next call.
  template <class T>
  const T* stage_selected(const T* items, std::size_t count);
  /// gathered_ as room for `count` items of type T.
  template <class T>
  T* gathered_as(std::size_t count, const char* what);
  /// How many isolated queries the time search of a round of `count`
  /// candidates may list in gathered_ (see run_ccd_chunk); gathered_ is
  /// given back first when it holds more than that room.
  std::size_t isolated_room(std::size_t count);

  cudaStream_t stream_;
  DeviceBuffer<CcdResult> results_, searched_results_;
  DeviceBuffer<unsigned char> flags_, searched_flags_;
  DeviceBuffer<std::uint32_t> selected_;
  DeviceBuffer<CcdResult> selected_results_;
  DeviceBuffer<long long> selected_count_;
  DeviceBuffer<unsigned long long> counters_;
  DeviceBuffer<unsigned long long> quick_counts_;  ///< the quick kernel's queries taken and queries isolated
  DeviceBuffer<unsigned char> temp_;
  DeviceBuffer<unsigned char> gathered_;  ///< stage_selected's device staging, any item type
  // Pinned host copies of a round's results, reused from call to call.
  PinnedBuffer<std::uint32_t> host_indices_;
  PinnedBuffer<CcdResult> host_results_;
  PinnedBuffer<unsigned char> host_gathered_;
  PinnedBuffer<Event> host_events_[2];       ///< a round's events, in the one after the last round's
  int staged_events_ = 0;                    ///< which of host_events_ the last round staged in
  std::uint64_t handed_events_[2] = {0, 0};  ///< event_copies_'s ticket of a copy that may read it, or 0
  TaskQueueThread* event_copies_ = nullptr;
  std::vector<Event>* pending_to_ = nullptr;  ///< deferred events go there (flush_events), when not null
  std::size_t pending_count_ = 0;             ///< how many, in host_events_[staged_events_]
  bool defer_events_ = false;
  NarrowPhaseTimings timings_;
  std::size_t chunk_size_ = kDefaultChunkSize;
  std::size_t last_survivors_ = 0;       ///< the last round's candidates the early exits left to the time search
  unsigned int refine_block_limit_ = 1;  ///< the refine kernel's blocks: kRefineBlocksPerSm per multiprocessor
  unsigned int quick_block_limit_ = 1;   ///< the quick kernel's blocks: kQuickBlocksPerSm per multiprocessor
  int order_low_bits_ = 0, order_end_bit_ = 0;  ///< set_event_order
};

/// Resizes `buffer` to `count`; when the device cannot hold it, throws
/// CudaError naming `what`, the bytes needed and the bytes free.
template <class T>
void resize_or_throw(DeviceBuffer<T>& buffer, std::size_t count, const char* what) {
  try {
    buffer.resize(count);
  } catch (const CudaError& error) {
    std::size_t free_bytes = 0, total_bytes = 0;
    (void)cudaMemGetInfo(&free_bytes, &total_bytes);
    (void)cudaGetLastError();
    throw CudaError("the GPU has too little memory for " + std::string(what) + ": " +
                        std::to_string(count * sizeof(T)) + " bytes needed, " + std::to_string(free_bytes) +
                        " of " + std::to_string(total_bytes) + " bytes free (" + error.what() + ")",
                    error.code());
  }
}

}  // namespace snag
