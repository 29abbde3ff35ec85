// The GPU narrow phase (see narrow_phase.cuh): one thread per candidate,
// compaction with cub::DeviceSelect::Flagged (order-preserving).
#include "libcd/cuda/narrow_phase.cuh"

#include <thrust/iterator/counting_iterator.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <utility>
#include <cub/block/block_reduce.cuh>
#include <cub/device/device_select.cuh>

#include "libcd/cuda/cuda_check.cuh"
#include "libcd/cuda/cuda_event.cuh"
#include "libcd/cuda/device_scan.cuh"
#include "libcd/cuda/launch.cuh"
#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/triangle_triangle.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "libcd/pipeline/event_builder.hpp"
#include "libcd/pipeline/event_fields.hpp"

namespace snag {

namespace {

static_assert(sizeof(Triangle) == 3 * sizeof(Index), "Triangle must be three packed vertex ids");
static_assert(sizeof(Edge) == 2 * sizeof(Index), "Edge must be two packed vertex ids");

constexpr int kBlockSize = 128;

unsigned int blocks_for(std::size_t count) {
  return static_cast<unsigned int>((count + kBlockSize - 1) / kBlockSize);
}

// Device bytes per candidate (pair) of a round that its hits' events may
// take: those of the compacted result and the gathered candidate (pair) that
// kCcdBytesPerCandidate (kStaticBytesPerPair) counts and the events path does
// not use.
constexpr std::size_t kCcdEventBytesPerCandidate = sizeof(CcdResult) + sizeof(VertexFaceCandidate);
constexpr std::size_t kStaticEventBytesPerPair = sizeof(TrianglePair);

// What the screen pass leaves for the search pass; kIsolated only between
// the quick kernel and the refine kernel.
constexpr unsigned char kScreenedNo = 0, kScreenedHit = 1, kUndecided = 2, kIsolated = 3;

// A query whose time search the quick kernel handed over to the refine
// kernel: the candidate and the interval that holds its earliest contact.
struct IsolatedQuery {
  std::uint32_t candidate;
  ccd_detail::IsolatedTimeInterval interval;
};

// The refine kernel's blocks per multiprocessor: it strides over the
// isolated queries, whose count only the device knows.
constexpr int kRefineBlocksPerSm = 8;
// The quick kernel's resident blocks per multiprocessor (its launch bound:
// 255 registers a thread, about 0.2 kB of spills); its lanes take queries
// until none is left. Three blocks (168 registers, 1.2 kB of spills) took
// 15% longer on cloth_ball (H200), four 5% longer still. On the refined
// cloths too (H100, CUPTI, -m all, the edge-edge launches' ms a step): ×16
// 8.36 at two blocks, 12.0 at three (128 registers at four: 16.5), ×4 1.44,
// 2.04 and 2.82.
constexpr int kQuickBlocksPerSm = 2;

constexpr unsigned kFullWarp = 0xffffffffu;
// The quick kernel's lanes whose searches ended take new queries together,
// once this many of a warp's lanes are idle: a query's start (its points,
// the decisions by structure, the cubic) then runs on many lanes at once.
// 8 and 24 took as long as 16 (cloth_ball, H100: 0.49 ms a step each).
constexpr int kRefillLanes = 16;

// The flag of a decided screen result.
__device__ unsigned char screened(const CcdResult& result) {
  return result.answer != CcdAnswer::kNo ? kScreenedHit : kScreenedNo;
}

// A vertex-face query: candidate i's eight points and the two CCD functions.
struct VertexFaceQuery {
  using Candidate = VertexFaceCandidate;
  using Contact = ccd_detail::VertexFaceContact;
  const Vec3* __restrict__ x_t0;
  const Vec3* __restrict__ x_t1;
  const Index* __restrict__ corners;
  const VertexFaceCandidate* __restrict__ candidates;

  __device__ void points(std::uint32_t i, Vec3 x[8]) const {
    const VertexFaceCandidate c = candidates[i];
    const Index ids[4] = {c.vertex, corners[3 * std::size_t{c.face}], corners[3 * std::size_t{c.face} + 1],
                          corners[3 * std::size_t{c.face} + 2]};
    for (int k = 0; k < 4; ++k) {
      x[k] = x_t0[ids[k]];
      x[4 + k] = x_t1[ids[k]];
    }
  }
  __device__ bool early_exit(std::uint32_t i, const CcdSettings& settings, CcdResult* result) const {
    Vec3 x[8];
    points(i, x);
    return vertex_face_early_exit(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings, result);
  }
  // The early exits' range check alone.
  __device__ bool range_exit(std::uint32_t i, const CcdSettings& settings, CcdResult* result) const {
    Vec3 x[8];
    points(i, x);
    return ccd_detail::range_exit(x, settings.thickness, result);
  }
  __device__ Contact contact(std::uint32_t i) const {
    Contact contact;
    points(i, contact.points);
    return contact;
  }
  // For a query whose early exits decided nothing.
  __device__ bool quick_start(const Contact& contact, const CcdSettings& settings, ccd_detail::TimeSearchState* search,
                              ccd_detail::TimeSearchEnd* end, CcdResult* result) const {
    return vertex_face_quick_start(contact, settings, search, end, result);
  }
  // For a query whose quick part isolated its earliest contact's interval.
  __device__ bool refine(std::uint32_t i, const ccd_detail::IsolatedTimeInterval& isolated, const CcdSettings& settings,
                         CcdResult* result) const {
    Vec3 x[8];
    points(i, x);
    return vertex_face_quick_refine(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], isolated, settings, result);
  }
  __device__ CcdResult full(std::uint32_t i, const CcdSettings& settings) const {
    Vec3 x[8];
    points(i, x);
    return vertex_face_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings);
  }
  // The collision event of a hit (event_fields.hpp).
  __device__ Event event(std::uint32_t i, const CcdResult& result) const {
    const VertexFaceCandidate c = candidates[i];
    return vertex_face_fields(c.vertex, c.face, x_t0[c.vertex], x_t1[c.vertex], result);
  }
};

// An edge-edge query.
struct EdgeEdgeQuery {
  using Candidate = EdgeEdgeCandidate;
  using Contact = ccd_detail::EdgeEdgeContact;
  const Vec3* __restrict__ x_t0;
  const Vec3* __restrict__ x_t1;
  const Index* __restrict__ ends;
  const EdgeEdgeCandidate* __restrict__ candidates;

  __device__ void points(std::uint32_t i, Vec3 x[8]) const {
    const EdgeEdgeCandidate c = candidates[i];
    const Index ids[4] = {ends[2 * std::size_t{c.edge_a}], ends[2 * std::size_t{c.edge_a} + 1],
                          ends[2 * std::size_t{c.edge_b}], ends[2 * std::size_t{c.edge_b} + 1]};
    for (int k = 0; k < 4; ++k) {
      x[k] = x_t0[ids[k]];
      x[4 + k] = x_t1[ids[k]];
    }
  }
  __device__ bool early_exit(std::uint32_t i, const CcdSettings& settings, CcdResult* result) const {
    Vec3 x[8];
    points(i, x);
    return edge_edge_early_exit(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings, result);
  }
  __device__ bool range_exit(std::uint32_t i, const CcdSettings& settings, CcdResult* result) const {
    Vec3 x[8];
    points(i, x);
    return ccd_detail::range_exit(x, settings.thickness, result);
  }
  __device__ Contact contact(std::uint32_t i) const {
    Contact contact;
    points(i, contact.points);
    return contact;
  }
  // For a query whose early exits decided nothing.
  __device__ bool quick_start(const Contact& contact, const CcdSettings& settings, ccd_detail::TimeSearchState* search,
                              ccd_detail::TimeSearchEnd* end, CcdResult* result) const {
    return edge_edge_quick_start(contact, settings, search, end, result);
  }
  // For a query whose quick part isolated its earliest contact's interval.
  __device__ bool refine(std::uint32_t i, const ccd_detail::IsolatedTimeInterval& isolated, const CcdSettings& settings,
                         CcdResult* result) const {
    Vec3 x[8];
    points(i, x);
    return edge_edge_quick_refine(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], isolated, settings, result);
  }
  __device__ CcdResult full(std::uint32_t i, const CcdSettings& settings) const {
    Vec3 x[8];
    points(i, x);
    return edge_edge_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings);
  }
  __device__ Event event(std::uint32_t i, const CcdResult& result) const {
    Vec3 x[8];
    points(i, x);
    const EdgeEdgeCandidate c = candidates[i];
    return edge_edge_fields(c.edge_a, c.edge_b, &x[0], &x[4], result);
  }
};

// The screen, step 1: thread i runs the early exits on candidate i and
// writes its result and kScreenedNo, kScreenedHit or kUndecided. With
// range_only, their range check alone, for candidates the other exits left
// undecided already (CcdPasses::kQuickAfterEarlyExits), on which they would
// run to the end for nothing (×4 on an H200: 57 and 106 µs, vertex-face and
// edge-edge, against 32 and 85 for the range check).
template <class Query>
__global__ void __launch_bounds__(kBlockSize, 4)
    ccd_early_exit_kernel(Query query, std::size_t count, CcdSettings settings, bool range_only,
                          CcdResult* __restrict__ results, unsigned char* __restrict__ flags) {
  const std::size_t i = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i >= count) return;
  CcdResult result;
  const auto k = static_cast<std::uint32_t>(i);
  const bool decided = range_only ? query.range_exit(k, settings, &result) : query.early_exit(k, settings, &result);
  results[i] = result;
  flags[i] = !decided ? kUndecided : screened(result);
}

// The screen, step 2: the candidates subset[k] = selected[first + k] for k
// below count = min(room, *selected_count - first) (0 past the end), which
// step 1 left undecided, get the rest of the quick part (the decisions by
// structure and the time search; their early exits decided nothing), which
// updates their result and flag in place. A search that isolates its
// earliest contact (a hit, nearly always) stops there and is appended to
// `isolated` (room for `room`; counts[1] counts them), flagged kIsolated:
// the halvings down to the time tolerance, the longest part of a hit's
// search, run in ccd_refine_kernel with every lane of a warp on a hit.
//
// The searches take from 3 to some 60 intervals, so a lane does not hold
// one query: each lane advances its search, a round at a time, to the next
// interval the cubic's signs do not exclude (which needs the costly inside
// test), and once kRefillLanes lanes of a warp have ended theirs, they take
// the next queries (counts[0] counts the queries taken, one atomic per warp),
// so that a warp is not held by its longest search while its other lanes
// wait. Launched with at most the blocks that are resident at once
// (kQuickBlocksPerSm per multiprocessor).
template <class Query>
__global__ void __launch_bounds__(kBlockSize, kQuickBlocksPerSm)
    ccd_quick_kernel(Query query, const std::uint32_t* __restrict__ selected,
                     const long long* __restrict__ selected_count, std::size_t first, std::size_t room,
                     CcdSettings settings, CcdResult* __restrict__ results, unsigned char* __restrict__ flags,
                     IsolatedQuery* __restrict__ isolated, unsigned long long* __restrict__ counts) {
  unsigned long long *taken = &counts[0], *isolated_count = &counts[1];
  const std::uint32_t* const subset = selected + first;
  const auto selected_total = static_cast<std::size_t>(*selected_count);
  const std::size_t count = selected_total > first ? std::min(room, selected_total - first) : 0;
  const unsigned lane = threadIdx.x & 31u, lanes_below = (1u << lane) - 1u;
  typename Query::Contact contact;
  ccd_detail::TimeSearchState search;
  ccd_detail::PendingTimeInterval stack[ccd_detail::kTimeSearchStack];
  std::uint32_t i = 0;
  bool searching = false, drained = false;
  for (;;) {
    ccd_detail::TimeSearchEnd end = ccd_detail::TimeSearchEnd::kGaveUp;
    CcdResult result;
    ccd_detail::IsolatedTimeInterval interval;
    bool ended = false;
    const unsigned idle = __ballot_sync(kFullWarp, !searching);
    if (!drained && (idle == kFullWarp || __popc(idle) >= kRefillLanes)) {
      const int leader = __ffs(idle) - 1;
      unsigned long long first = 0;
      if (static_cast<int>(lane) == leader) first = atomicAdd(taken, static_cast<unsigned long long>(__popc(idle)));
      first = __shfl_sync(kFullWarp, first, leader);
      drained = first + __popc(idle) >= count;
      const unsigned long long k = first + __popc(idle & lanes_below);
      if (!searching && k < count) {
        i = subset[k];
        if (flags[i] == kUndecided) {
          contact = query.contact(i);
          searching = query.quick_start(contact, settings, &search, &end, &result);
          ended = !searching;
        }
      }
    } else if (idle == kFullWarp) {
      return;  // every query taken and searched
    }
    if (searching) {
      // An interval the cubic's signs exclude takes no inside test: the lane
      // passes over such intervals now, so that in the next round the lanes
      // that go on all examine an interval that needs one, together. (Passing
      // over those that inherit the inside conditions too measured no faster.)
      do {
        ended =
            ccd_detail::advance_time_search(contact, settings.time_tolerance, &interval, &search, stack, &result, &end);
      } while (!ended && ccd_detail::keeps_sign(search.node.b));
      searching = !ended;
    }
    if (!ended) continue;
    if (end == ccd_detail::TimeSearchEnd::kIsolated) {
      // One atomic per group of lanes that isolate together.
      const unsigned active = __activemask();
      const int leader = __ffs(active) - 1;
      unsigned long long base = 0;
      if (static_cast<int>(lane) == leader)
        base = atomicAdd(isolated_count, static_cast<unsigned long long>(__popc(active)));
      base = __shfl_sync(active, base, leader);
      isolated[base + __popc(active & lanes_below)] = IsolatedQuery{i, interval};
      flags[i] = kIsolated;
      continue;
    }
    results[i] = result;
    flags[i] = end == ccd_detail::TimeSearchEnd::kDecided ? screened(result) : kUndecided;
  }
}

// The rest of the time search of the queries the quick kernel isolated,
// striding over them: each gets the result and flag the quick part would
// have given it.
template <class Query>
__global__ void __launch_bounds__(kBlockSize)
    ccd_refine_kernel(Query query, const IsolatedQuery* __restrict__ isolated,
                      const unsigned long long* __restrict__ isolated_count, CcdSettings settings,
                      CcdResult* __restrict__ results, unsigned char* __restrict__ flags) {
  const std::size_t count = *isolated_count;
  for (std::size_t k = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x; k < count;
       k += static_cast<std::size_t>(gridDim.x) * blockDim.x) {
    const IsolatedQuery q = isolated[k];
    CcdResult result;
    const bool decided = query.refine(q.candidate, q.interval, settings, &result);
    results[q.candidate] = result;
    flags[q.candidate] = decided ? screened(result) : kUndecided;
  }
}

// For the caller's search: the candidates subset[k] the screen left
// undecided get the answer kUncertain.
__global__ void mark_undecided_kernel(const std::uint32_t* __restrict__ subset, std::size_t count,
                                      const unsigned char* __restrict__ flags, CcdResult* __restrict__ results) {
  const std::size_t k = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (k < count && flags[subset[k]] == kUndecided) results[subset[k]].answer = CcdAnswer::kUncertain;
}

// The whole test: thread k tests candidate subset[k] (k when subset is null)
// and writes its result at k and whether it is a hit (not kNo). With
// screen_flags, a candidate the screen decided keeps the screen's result.
template <class Query>
__global__ void ccd_full_kernel(Query query, const std::uint32_t* __restrict__ subset, std::size_t count,
                                const unsigned char* __restrict__ screen_flags,
                                const CcdResult* __restrict__ screen_results, CcdSettings settings,
                                CcdResult* __restrict__ results, unsigned char* __restrict__ hit) {
  const std::size_t k = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (k >= count) return;
  const std::uint32_t i = subset != nullptr ? subset[k] : static_cast<std::uint32_t>(k);
  const CcdResult result = screen_flags != nullptr && screen_flags[i] != kUndecided ? screen_results[i]
                                                                                    : query.full(i, settings);
  results[k] = result;
  hit[k] = result.answer != CcdAnswer::kNo ? 1 : 0;
}

// out[k] = items[subset[k]] for k < count.
template <class T>
__global__ void gather_kernel(const T* __restrict__ items, const std::uint32_t* __restrict__ subset, std::size_t count,
                              T* __restrict__ out) {
  const std::size_t k = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (k < count) out[k] = items[subset[k]];
}

// events[k] = the collision event of candidate subset[k], whose answer is
// results[subset[k]] (a hit), for k < count.
template <class Query>
__global__ void collision_event_kernel(Query query, const std::uint32_t* __restrict__ subset, std::size_t count,
                                       const CcdResult* __restrict__ results, Event* __restrict__ events) {
  __shared__ detail::WarpRunStage<Event, kBlockSize> stage;  // 72 bytes a thread, written a warp in one piece
  const std::size_t k = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  Event event;
  if (k < count) {
    const std::uint32_t i = subset[k];
    event = query.event(i, results[i]);
  }
  stage.write(event, k, count, events);
}

// The event order of a candidate's events among those of its kind (event.hpp:
// vertex, then face; edge a, then edge b) as a radix sort key.
__device__ std::uint64_t event_order_key(const VertexFaceCandidate& c, int low_bits) {
  return detail::pack_key(c.vertex, c.face, low_bits);
}
__device__ std::uint64_t event_order_key(const EdgeEdgeCandidate& c, int low_bits) {
  return detail::pack_key(c.edge_a, c.edge_b, low_bits);
}

// keys[k] = event_order_key of candidates[subset[k]], for k < count.
template <class Candidate>
__global__ void event_order_keys_kernel(const Candidate* __restrict__ candidates,
                                        const std::uint32_t* __restrict__ subset, std::size_t count, int low_bits,
                                        std::uint64_t* __restrict__ keys) {
  const std::size_t k = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (k < count) keys[k] = event_order_key(candidates[subset[k]], low_bits);
}

// events[k] = the intersection event of the intersecting pair pairs[subset[k]], for k < count.
__global__ void intersection_event_kernel(const Vec3* __restrict__ x, const Index* __restrict__ corners,
                                          const TrianglePair* __restrict__ pairs,
                                          const std::uint32_t* __restrict__ subset, std::size_t count,
                                          Event* __restrict__ events) {
  __shared__ detail::WarpRunStage<Event, kBlockSize> stage;  // 72 bytes a thread, written a warp in one piece
  const std::size_t k = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  Event event;
  if (k < count) {
    const TrianglePair pair = pairs[subset[k]];
    Vec3 a[3], b[3];
    for (int c = 0; c < 3; ++c) {
      a[c] = x[corners[3 * std::size_t{pair.a} + c]];
      b[c] = x[corners[3 * std::size_t{pair.b} + c]];
    }
    event = intersection_fields(pair.a, pair.b, a, b);
  }
  stage.write(event, k, count, events);
}

// The static test: thread i tests pair i; the predicate counters are summed
// per block and added to counters[0] (calls) and counters[1] (exact).
__global__ void triangle_pairs_kernel(const Vec3* __restrict__ x, const Index* __restrict__ corners,
                                      const TrianglePair* __restrict__ pairs, std::size_t count,
                                      unsigned char* __restrict__ intersecting,
                                      unsigned long long* __restrict__ counters) {
  using Reduce = cub::BlockReduce<unsigned long long, kBlockSize>;
  __shared__ typename Reduce::TempStorage calls_storage, exact_storage;
  const std::size_t i = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  PredicateCounters local;
  if (i < count) {
    const TrianglePair pair = pairs[i];
    Index a_ids[3], b_ids[3];
    Vec3 a[3], b[3];
    for (int k = 0; k < 3; ++k) {
      a_ids[k] = corners[3 * std::size_t{pair.a} + k];
      b_ids[k] = corners[3 * std::size_t{pair.b} + k];
      a[k] = x[a_ids[k]];
      b[k] = x[b_ids[k]];
    }
    intersecting[i] = triangles_intersect(a, a_ids, b, b_ids, &local) ? 1 : 0;
  }
  const unsigned long long calls = Reduce(calls_storage).Sum(local.calls);
  const unsigned long long exact = Reduce(exact_storage).Sum(local.exact);
  if (threadIdx.x == 0) {
    atomicAdd(&counters[0], calls);
    atomicAdd(&counters[1], exact);
  }
}

// cub::DeviceSelect::Flagged with temporary storage from `temp`; the number
// selected is written to *selected_count on the device.
template <class Input, class Output>
void select_flagged_into(Input input, const unsigned char* flags, Output output, long long* selected_count,
                         std::size_t count, DeviceBuffer<unsigned char>& temp, cudaStream_t stream) {
  std::size_t bytes = 0;
  const auto items = static_cast<std::int64_t>(count);
  SNAG_CUDA_CHECK(cub::DeviceSelect::Flagged(nullptr, bytes, input, flags, output, selected_count, items, stream));
  if (bytes > temp.size()) resize_or_throw(temp, bytes, "compaction scratch");
  SNAG_CUDA_CHECK(
      cub::DeviceSelect::Flagged(temp.data(), bytes, input, flags, output, selected_count, items, stream));
}

}  // namespace

CudaNarrowPhase::CudaNarrowPhase(cudaStream_t stream)
    : stream_(stream),
      results_(0, stream),
      searched_results_(0, stream),
      flags_(0, stream),
      searched_flags_(0, stream),
      selected_(0, stream),
      selected_results_(0, stream),
      selected_count_(1, stream),
      counters_(2, stream),
      quick_counts_(2, stream),
      temp_(0, stream),
      gathered_(0, stream) {
  int device = 0, multiprocessors = 0;
  SNAG_CUDA_CHECK(cudaGetDevice(&device));
  SNAG_CUDA_CHECK(cudaDeviceGetAttribute(&multiprocessors, cudaDevAttrMultiProcessorCount, device));
  refine_block_limit_ = static_cast<unsigned int>(std::max(1, multiprocessors * kRefineBlocksPerSm));
  quick_block_limit_ = static_cast<unsigned int>(std::max(1, multiprocessors * kQuickBlocksPerSm));
}

std::size_t CudaNarrowPhase::held_bytes() const {
  return results_.capacity_bytes() + searched_results_.capacity_bytes() + flags_.capacity_bytes() +
         searched_flags_.capacity_bytes() + selected_.capacity_bytes() + selected_results_.capacity_bytes() +
         selected_count_.capacity_bytes() + counters_.capacity_bytes() + quick_counts_.capacity_bytes() +
         temp_.capacity_bytes() + gathered_.capacity_bytes();
}

void CudaNarrowPhase::release_buffers() {
  for (auto* results : {&results_, &searched_results_, &selected_results_}) results->release();
  for (auto* bytes : {&flags_, &searched_flags_, &temp_, &gathered_}) bytes->release();
  selected_.release();
}

void CudaNarrowPhase::select_flagged_on_device(std::size_t count) {
  resize_or_throw(selected_, count, "CCD candidate indices");
  select_flagged_into(thrust::counting_iterator<std::uint32_t>(0), flags_.data(), selected_.data(),
                      selected_count_.data(), count, temp_, stream_);
}

std::size_t CudaNarrowPhase::select_flagged(std::size_t count) {
  select_flagged_on_device(count);
  long long selected = 0;
  ReadBack(stream_).add(&selected, selected_count_.data()).wait();
  return static_cast<std::size_t>(selected);
}

template <class T>
T* CudaNarrowPhase::gathered_as(std::size_t count, const char* what) {
  resize_or_throw(gathered_, count * sizeof(T), what);
  return reinterpret_cast<T*>(gathered_.data());  // cudaMallocAsync memory: aligned for any T
}

template <class T>
const T* CudaNarrowPhase::stage_selected(const T* items, std::size_t count) {
  if (count == 0) return nullptr;
  T* gathered = gathered_as<T>(count, "gathered hits");
  gather_kernel<<<blocks_for(count), kBlockSize, 0, stream_>>>(items, selected_.data(), count, gathered);
  SNAG_CUDA_CHECK_LAUNCH();
  host_gathered_.resize(count * sizeof(T));
  T* staged = reinterpret_cast<T*>(host_gathered_.data());  // cudaMallocHost memory: aligned for any T
  SNAG_CUDA_CHECK(cudaMemcpyAsync(staged, gathered, count * sizeof(T), cudaMemcpyDeviceToHost, stream_));
  return staged;
}

std::size_t CudaNarrowPhase::isolated_room(std::size_t count) {
  const std::size_t round =
      std::min(chunk_size_, std::numeric_limits<std::size_t>::max() / kCcdBytesPerCandidate) * kCcdBytesPerCandidate;
  // What the round's other buffers hold, and what it may still take beside
  // gathered_ (its compacted or searched results and flags).
  const std::size_t taken = held_bytes() - gathered_.capacity_bytes() + count * (sizeof(CcdResult) + 1);
  const std::size_t bytes = std::max(count * kCcdEventBytesPerCandidate, round > taken ? round - taken : 0);
  if (gathered_.capacity_bytes() > bytes) gathered_.release();
  return std::max<std::size_t>(1, std::min(count, bytes / sizeof(IsolatedQuery)));
}

template <class Candidate>
void CudaNarrowPhase::order_hits(const Candidate* candidates, std::size_t hits) {
  // The keys, their second half and the indices' second half: 20 bytes a
  // hit, within the room of its event (kCcdEventBytesPerCandidate).
  static_assert(2 * sizeof(std::uint64_t) + sizeof(std::uint32_t) <= kCcdEventBytesPerCandidate,
                "a round's sort keys fit in the room its events take");
  std::uint64_t* keys = gathered_as<std::uint64_t>(2 * hits + (hits + 1) / 2, "the hits' sort keys");
  std::uint64_t* sorted_keys = keys + hits;
  auto* sorted = reinterpret_cast<std::uint32_t*>(keys + 2 * hits);
  event_order_keys_kernel<<<blocks_for(hits), kBlockSize, 0, stream_>>>(candidates, selected_.data(), hits,
                                                                        order_low_bits_, keys);
  SNAG_CUDA_CHECK_LAUNCH();
  // Double buffers: the sort's scratch holds no copy of the hits.
  cub::DoubleBuffer<std::uint64_t> key_halves(keys, sorted_keys);
  cub::DoubleBuffer<std::uint32_t> hit_halves(selected_.data(), sorted);
  detail::radix_sort_pairs(key_halves, hit_halves, hits, order_end_bit_, temp_, stream_);
  if (hit_halves.Current() != selected_.data()) {
    SNAG_CUDA_CHECK(cudaMemcpyAsync(selected_.data(), hit_halves.Current(), hits * sizeof(std::uint32_t),
                                    cudaMemcpyDeviceToDevice, stream_));
  }
}

template <class Launch>
void CudaNarrowPhase::stage_events(std::size_t hits, std::size_t slice, Launch launch) {
  staged_events_ ^= 1;  // the other buffer may still be read by event_copies_
  if (handed_events_[staged_events_] != 0) event_copies_->wait_for(std::exchange(handed_events_[staged_events_], 0));
  host_events_[staged_events_].resize(hits);
  Event* host = host_events_[staged_events_].data();
  slice = std::max<std::size_t>(1, std::min(slice, hits));
  Event* device = gathered_as<Event>(slice, "events");
  // In stream order, a slice's kernel starts after the previous slice's copy.
  for (std::size_t first = 0; first < hits; first += slice) {
    const std::size_t n = std::min(slice, hits - first);
    launch(first, n, device);
    SNAG_CUDA_CHECK(cudaMemcpyAsync(host + first, device, n * sizeof(Event), cudaMemcpyDeviceToHost, stream_));
  }
}

void CudaNarrowPhase::append_staged_events(std::size_t count, std::vector<Event>& events) {
  // The device copy is given back: a large scene's events (72 bytes each)
  // would otherwise stay counted against the budget the other detection gets.
  gathered_.release();
  pending_to_ = &events;
  pending_count_ = count;
  if (!defer_events_) flush_events_to(events);
}

void CudaNarrowPhase::flush_events() {
  if (pending_to_ == nullptr) return;
  if (event_copies_ == nullptr || pending_count_ == 0) {
    flush_events_to(*pending_to_);
    return;
  }
  std::vector<Event>* to = std::exchange(pending_to_, nullptr);
  const Event* staged = host_events_[staged_events_].data();
  const std::size_t count = pending_count_;
  // A plain copy on that thread: a round's events are a few megabytes, and
  // the host's threads sort and certify the last step's meanwhile.
  handed_events_[staged_events_] =
      event_copies_->post([to, staged, count] { to->insert(to->end(), staged, staged + count); });
}

void CudaNarrowPhase::flush_events_to(std::vector<Event>& events) {
  if (std::exchange(pending_to_, nullptr) == nullptr || pending_count_ == 0) return;
  append_events(events, host_events_[staged_events_].data(), pending_count_);
}

template <class Query>
void CudaNarrowPhase::run_ccd(const Query& query, std::size_t count, const CcdSettings& settings, CcdPasses passes,
                              const HitSink<typename Query::Candidate>& sink) {
  if (count > 0xffffffffu) throw CudaError("the GPU narrow phase takes at most 2^32 - 1 candidates per call", 0);
  if (sink.events != nullptr && passes == CcdPasses::kScreenThenSearch)
    throw std::invalid_argument("CCD events are built on the device only after kScreenOnly or kSinglePass");
  HitSink<typename Query::Candidate> round_sink = sink;
  for (std::size_t first = 0; first < count; first += chunk_size_) {
    Query chunk = query;
    chunk.candidates += first;
    run_ccd_chunk(chunk, std::min(chunk_size_, count - first), first, settings, passes, round_sink);
    round_sink.while_busy = nullptr;
  }
}

template <class Query>
void CudaNarrowPhase::run_ccd_chunk(const Query& query, std::size_t count, std::size_t first,
                                    const CcdSettings& settings, CcdPasses passes,
                                    const HitSink<typename Query::Candidate>& sink) {
  const bool screen = passes != CcdPasses::kSinglePass;
  const bool search = passes == CcdPasses::kScreenThenSearch;
  DeviceMemoryTracker::set_stage("narrow phase");
  CudaEvent start, screened, compacted, searched;
  ++timings_.rounds;
  resize_or_throw(results_, count, "CCD results");
  resize_or_throw(flags_, count, "CCD flags");
  start.record(stream_);
  if (screen) {
    ccd_early_exit_kernel<<<blocks_for(count), kBlockSize, 0, stream_>>>(
        query, count, settings, passes == CcdPasses::kQuickAfterEarlyExits, results_.data(), flags_.data());
    SNAG_CUDA_CHECK_LAUNCH();
    // The time search runs on the compacted survivors of the early exits, in
    // full warps, in slices, each a launch that ends in a tail on every
    // multiprocessor: a slice's isolated queries take the room the hits'
    // events take later (kCcdEventBytesPerCandidate per candidate), or what
    // the round's room (chunk_size_ candidates of kCcdBytesPerCandidate)
    // leaves beside the other buffers where that is more: a round of fewer
    // candidates than it holds, as those the feature stage's screen leaves,
    // is searched in one slice. (In slices of a third of the candidates, the
    // searches took three launches a round on cloth_ball ×4: 0.36 ms more a
    // step, 3 ms on ×16, H200.) The first slice, as large as the last round's
    // survivors with room to spare, is enqueued before the survivors are
    // counted on the host: its kernels read their count on the device; more
    // slices follow when they were more.
    select_flagged_on_device(count);
    long long counted = 0;
    ReadBack survivors_read(stream_);
    survivors_read.add(&counted, selected_count_.data()).start();
    const std::size_t slice = isolated_room(count);
    auto search_slice = [&](std::size_t at, std::size_t room) {
      ++timings_.time_searches;
      IsolatedQuery* isolated = gathered_as<IsolatedQuery>(room, "isolated CCD queries");
      quick_counts_.fill_zero();
      const unsigned int quick_blocks = std::min(blocks_for(room), quick_block_limit_);
      ccd_quick_kernel<<<quick_blocks, kBlockSize, 0, stream_>>>(query, selected_.data(), selected_count_.data(), at,
                                                                 room, settings, results_.data(), flags_.data(),
                                                                 isolated, quick_counts_.data());
      SNAG_CUDA_CHECK_LAUNCH();
      const unsigned int refine_blocks = std::min(blocks_for(room), refine_block_limit_);
      ccd_refine_kernel<<<refine_blocks, kBlockSize, 0, stream_>>>(query, isolated, quick_counts_.data() + 1, settings,
                                                                   results_.data(), flags_.data());
      SNAG_CUDA_CHECK_LAUNCH();
    };
    const std::size_t first_room = std::min(slice, last_survivors_ + last_survivors_ / 4 + 1024);
    search_slice(0, first_room);
    survivors_read.wait();
    const auto survivors = static_cast<std::size_t>(counted);
    last_survivors_ = survivors;
    for (std::size_t at = first_room; at < survivors; at += slice) search_slice(at, std::min(slice, survivors - at));
    if (!search && survivors > 0) {
      mark_undecided_kernel<<<blocks_for(survivors), kBlockSize, 0, stream_>>>(selected_.data(), survivors,
                                                                               flags_.data(), results_.data());
    }
  } else {
    ccd_full_kernel<<<blocks_for(count), kBlockSize, 0, stream_>>>(query, nullptr, count, nullptr, nullptr, settings,
                                                                   results_.data(), flags_.data());
  }
  SNAG_CUDA_CHECK_LAUNCH();
  // While the device works: the caller's work, then the deferred events of
  // the last call or round (their buffer is staged in again a round later).
  if (sink.while_busy != nullptr && *sink.while_busy) (*sink.while_busy)();
  flush_events();
  screened.record(stream_);
  // The screen's hits and the candidates it left undecided, or the single
  // pass's hits.
  const std::size_t survivors = select_flagged(count);
  compacted.record(stream_);

  host_indices_.resize(survivors);
  host_results_.resize(survivors);
  const std::uint32_t* indices = host_indices_.data();
  const CcdResult* results = host_results_.data();
  const typename Query::Candidate* candidates = nullptr;
  if (survivors > 0 && sink.events != nullptr) {
    // Without the search, every survivor is a hit whose answer is in results_.
    if (order_end_bit_ > 0 && survivors > 1) order_hits(query.candidates, survivors);
    stage_events(survivors, count * kCcdEventBytesPerCandidate / sizeof(Event),
                 [&](std::size_t hit, std::size_t n, Event* events) {
                   collision_event_kernel<<<blocks_for(n), kBlockSize, 0, stream_>>>(
                       query, selected_.data() + hit, n, results_.data(), events);
                   SNAG_CUDA_CHECK_LAUNCH();
                 });
    searched.record(stream_);
  } else if (survivors > 0) {
    if (search) {
      resize_or_throw(searched_results_, survivors, "CCD search results");
      resize_or_throw(searched_flags_, survivors, "CCD search flags");
      ccd_full_kernel<<<blocks_for(survivors), kBlockSize, 0, stream_>>>(
          query, selected_.data(), survivors, flags_.data(), results_.data(), settings, searched_results_.data(),
          searched_flags_.data());
      SNAG_CUDA_CHECK_LAUNCH();
      searched.record(stream_);
      searched_results_.download(host_results_.data(), survivors);
    } else {
      resize_or_throw(selected_results_, survivors, "CCD hits");
      select_flagged_into(results_.data(), flags_.data(), selected_results_.data(), selected_count_.data(), count,
                          temp_, stream_);
      searched.record(stream_);
      selected_results_.download(host_results_.data(), survivors);
    }
    selected_.download(host_indices_.data(), survivors);
    if (sink.hit_candidates != nullptr) candidates = stage_selected(query.candidates, survivors);
  } else {
    searched.record(stream_);
  }
  CudaEvent done;
  done.record(stream_);
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream_));
  timings_.screen_ms += CudaEvent::elapsed_ms(start, screened);
  if (search) {
    timings_.search_ms += CudaEvent::elapsed_ms(compacted, searched);
    timings_.compact_ms += CudaEvent::elapsed_ms(screened, compacted) + CudaEvent::elapsed_ms(searched, done);
    timings_.searched += survivors;
  } else {
    timings_.compact_ms += CudaEvent::elapsed_ms(screened, done);
  }
  if (sink.events != nullptr) {
    append_staged_events(survivors, *sink.events);
    return;
  }
  for (std::size_t k = 0; k < survivors; ++k) {
    if (results[k].answer == CcdAnswer::kNo) continue;  // the full search ruled it out
    sink.hits->push_back(CcdHit{static_cast<std::uint32_t>(first + indices[k]), results[k]});
    if (sink.hit_candidates != nullptr) sink.hit_candidates->push_back(candidates[k]);
  }
}

void CudaNarrowPhase::vertex_face(const Vec3* x_t0, const Vec3* x_t1, const Triangle* triangles,
                                  const VertexFaceCandidate* candidates, std::size_t count,
                                  const CcdSettings& settings, CcdPasses passes, std::vector<CcdHit>& hits,
                                  std::vector<VertexFaceCandidate>* hit_candidates) {
  run_ccd(VertexFaceQuery{x_t0, x_t1, reinterpret_cast<const Index*>(triangles), candidates}, count, settings, passes,
          HitSink<VertexFaceCandidate>{&hits, hit_candidates, nullptr});
}

void CudaNarrowPhase::edge_edge(const Vec3* x_t0, const Vec3* x_t1, const Edge* edges,
                                const EdgeEdgeCandidate* candidates, std::size_t count, const CcdSettings& settings,
                                CcdPasses passes, std::vector<CcdHit>& hits,
                                std::vector<EdgeEdgeCandidate>* hit_candidates) {
  run_ccd(EdgeEdgeQuery{x_t0, x_t1, reinterpret_cast<const Index*>(edges), candidates}, count, settings, passes,
          HitSink<EdgeEdgeCandidate>{&hits, hit_candidates, nullptr});
}

void CudaNarrowPhase::vertex_face_events(const Vec3* x_t0, const Vec3* x_t1, const Triangle* triangles,
                                         const VertexFaceCandidate* candidates, std::size_t count,
                                         const CcdSettings& settings, CcdPasses passes, std::vector<Event>& events,
                                         const std::function<void()>& while_busy) {
  run_ccd(VertexFaceQuery{x_t0, x_t1, reinterpret_cast<const Index*>(triangles), candidates}, count, settings, passes,
          HitSink<VertexFaceCandidate>{nullptr, nullptr, &events, &while_busy});
}

void CudaNarrowPhase::edge_edge_events(const Vec3* x_t0, const Vec3* x_t1, const Edge* edges,
                                       const EdgeEdgeCandidate* candidates, std::size_t count,
                                       const CcdSettings& settings, CcdPasses passes, std::vector<Event>& events,
                                       const std::function<void()>& while_busy) {
  run_ccd(EdgeEdgeQuery{x_t0, x_t1, reinterpret_cast<const Index*>(edges), candidates}, count, settings, passes,
          HitSink<EdgeEdgeCandidate>{nullptr, nullptr, &events, &while_busy});
}

void CudaNarrowPhase::triangle_pairs(const Vec3* x, const Triangle* triangles, const TrianglePair* pairs,
                                     std::size_t count, std::vector<std::uint32_t>& hits,
                                     TrianglePairCounts& counts, std::vector<TrianglePair>* hit_pairs) {
  run_triangle_pairs(x, triangles, pairs, count, counts, PairSink{&hits, hit_pairs, nullptr});
}

std::size_t CudaNarrowPhase::triangle_pair_events(const Vec3* x, const Triangle* triangles, const TrianglePair* pairs,
                                                  std::size_t count, std::vector<Event>& events,
                                                  TrianglePairCounts& counts) {
  return run_triangle_pairs(x, triangles, pairs, count, counts, PairSink{nullptr, nullptr, &events});
}

std::size_t CudaNarrowPhase::run_triangle_pairs(const Vec3* x, const Triangle* triangles, const TrianglePair* pairs,
                                                std::size_t count, TrianglePairCounts& counts, const PairSink& sink) {
  if (count > 0xffffffffu) throw CudaError("the GPU narrow phase takes at most 2^32 - 1 pairs per call", 0);
  std::size_t intersecting = 0;
  for (std::size_t first = 0; first < count; first += chunk_size_) {
    intersecting +=
        triangle_pairs_chunk(x, triangles, pairs + first, std::min(chunk_size_, count - first), first, counts, sink);
  }
  return intersecting;
}

std::size_t CudaNarrowPhase::triangle_pairs_chunk(const Vec3* x, const Triangle* triangles, const TrianglePair* pairs,
                                                  std::size_t count, std::size_t first, TrianglePairCounts& counts,
                                                  const PairSink& sink) {
  CudaEvent start, tested;
  resize_or_throw(flags_, count, "triangle-pair flags");
  resize_or_throw(selected_, count, "triangle-pair indices");
  counters_.fill_zero();
  start.record(stream_);
  const Index* corners = reinterpret_cast<const Index*>(triangles);
  triangle_pairs_kernel<<<blocks_for(count), kBlockSize, 0, stream_>>>(x, corners, pairs, count, flags_.data(),
                                                                       counters_.data());
  SNAG_CUDA_CHECK_LAUNCH();
  flush_events();  // while the device tests
  tested.record(stream_);
  const std::size_t intersecting = select_flagged(count);
  const TrianglePair* staged_pairs = nullptr;
  if (sink.events != nullptr) {
    if (intersecting > 0) {
      stage_events(intersecting, count * kStaticEventBytesPerPair / sizeof(Event),
                   [&](std::size_t hit, std::size_t n, Event* events) {
                     intersection_event_kernel<<<blocks_for(n), kBlockSize, 0, stream_>>>(
                         x, corners, pairs, selected_.data() + hit, n, events);
                     SNAG_CUDA_CHECK_LAUNCH();
                   });
    }
  } else {
    host_indices_.resize(intersecting);
    selected_.download(host_indices_.data(), intersecting);
    if (sink.hit_pairs != nullptr) staged_pairs = stage_selected(pairs, intersecting);
  }
  unsigned long long sums[2] = {0, 0};
  counters_.download(sums, 2);
  CudaEvent done;
  done.record(stream_);
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream_));
  if (sink.events != nullptr) {
    append_staged_events(intersecting, *sink.events);
  } else {
    for (std::size_t k = 0; k < intersecting; ++k)
      sink.hits->push_back(static_cast<std::uint32_t>(first) + host_indices_[k]);
    if (sink.hit_pairs != nullptr) sink.hit_pairs->insert(sink.hit_pairs->end(), staged_pairs, staged_pairs + intersecting);
  }
  counts.predicate_calls += sums[0];
  counts.predicate_exact += sums[1];
  timings_.static_ms += CudaEvent::elapsed_ms(start, tested);
  timings_.compact_ms += CudaEvent::elapsed_ms(tested, done);
  return intersecting;
}

}  // namespace snag
