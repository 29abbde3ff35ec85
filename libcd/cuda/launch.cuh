// Launch shapes and warp-aggregated counters shared by the broad-phase kernels.
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace snag::detail {

constexpr unsigned kBlockSize = 256;

/// Blocks of kBlockSize threads for one thread per item (n ≥ 1).
inline unsigned blocks_for(std::size_t n) { return static_cast<unsigned>((n + kBlockSize - 1) / kBlockSize); }

/// Index of this thread when one thread handles one item.
__device__ __forceinline__ std::uint64_t thread_item() {
  return static_cast<std::uint64_t>(blockIdx.x) * blockDim.x + threadIdx.x;
}

/// Adds `value` of every lane of the warp to *counter with one atomic per warp.
/// Every lane of the warp must call it (kernels launched with blocks_for).
__device__ __forceinline__ void warp_count(unsigned value, unsigned long long* counter) {
  const unsigned sum = __reduce_add_sync(0xffffffffu, value);
  if ((threadIdx.x & 31u) == 0 && sum != 0) atomicAdd(counter, static_cast<unsigned long long>(sum));
}

/// Reserves one slot per lane with `take` set in the array counted by *counter;
/// returns this lane's slot (meaningful only where take is set). Every lane of
/// the warp must call it. The slot may lie past the array's capacity: the
/// caller writes only below it and the host redoes the stage with more room.
__device__ __forceinline__ unsigned long long warp_append(bool take, unsigned long long* counter) {
  const unsigned mask = __ballot_sync(0xffffffffu, take);
  const unsigned lane = threadIdx.x & 31u;
  unsigned long long base = 0;
  if (lane == 0 && mask != 0) base = atomicAdd(counter, static_cast<unsigned long long>(__popc(mask)));
  base = __shfl_sync(0xffffffffu, base, 0);
  return base + __popc(mask & ((1u << lane) - 1u));
}

/// Copies the warp's `count` records staged in shared memory to out[0,
/// count) in 8-byte words (4-byte words for records aligned to 4), lane l
/// the words l, l + 32, ...: the warp's stores lie in one piece, where the
/// records a thread each would store lie sizeof(T) bytes apart. Syncs the
/// warp before (the lanes' records are staged) and after (the stage may be
/// written again). Every lane of the warp must call it.
template <class T>
__device__ __forceinline__ void warp_copy_run(const T* stage, std::uint64_t count, T* out) {
  using Word = std::conditional_t<alignof(T) >= 8 && sizeof(T) % 8 == 0, std::uint64_t, std::uint32_t>;
  static_assert(sizeof(T) % sizeof(Word) == 0 && alignof(T) >= alignof(Word), "records are copied in whole words");
  constexpr std::uint64_t kWords = sizeof(T) / sizeof(Word);
  __syncwarp();
  const auto* from = reinterpret_cast<const Word*>(stage);
  auto* to = reinterpret_cast<Word*>(out);
  for (std::uint64_t w = threadIdx.x & 31u; w < count * kWords; w += 32) to[w] = from[w];
  __syncwarp();
}

/// Shared memory for a block of `threads` records of T, one a thread (raw:
/// shared variables take no initializers): each warp stages its records
/// there and writes them in one piece (warp_copy_run). Every thread of the
/// block calls write, with record i (valid when i < n) for out[i]; a kernel
/// whose warps write fewer records (compacted) fills warp_records() itself.
template <class T, unsigned threads>
struct WarpRunStage {
  alignas(alignof(T)) unsigned char storage[threads * sizeof(T)];
  /// The calling warp's 32 records.
  __device__ T* warp_records() { return reinterpret_cast<T*>(storage) + (threadIdx.x & ~31u); }
  __device__ void write(const T& record, std::uint64_t i, std::uint64_t n, T* out) {
    const unsigned lane = threadIdx.x & 31u;
    T* const warp_stage = warp_records();
    const std::uint64_t first = i - lane;
    if (i < n) warp_stage[lane] = record;
    warp_copy_run(warp_stage, first < n ? (n - first < 32 ? n - first : 32) : 0, out + first);
  }
};

/// A warp's list in shared memory, of which every lane holds the length
/// `count`: appends the items of the lanes with `take` set, in lane order.
/// Every lane of the warp must call it.
template <class T>
__device__ __forceinline__ void warp_list_push(bool take, const T& item, T* list, unsigned& count) {
  const unsigned mask = __ballot_sync(0xffffffffu, take);
  if (take) list[count + __popc(mask & ((1u << (threadIdx.x & 31u)) - 1u))] = item;
  count += __popc(mask);
  __syncwarp();
}

/// Drops the first n items of a warp's list (warp_list_push), of which at
/// most 32 remain after them. Every lane of the warp must call it.
template <class T>
__device__ __forceinline__ void warp_list_drop(T* list, unsigned& count, unsigned n) {
  const unsigned lane = threadIdx.x & 31u;
  const bool moves = lane + n < count;
  T moved{};
  if (moves) moved = list[lane + n];
  __syncwarp();
  if (moves) list[lane] = moved;
  __syncwarp();
  count -= n;
}

}  // namespace snag::detail
