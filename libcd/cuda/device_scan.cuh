// Scratch, prefix sums and radix sorts shared by the GPU stages: CUB's
// two-call pattern (ask the scratch size, then run) written once.
#pragma once

#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "libcd/cuda/device_buffer.cuh"

namespace snag::detail {

/// Sizes CUB's scratch `temp` to at least `bytes` (at least 1); `check` is
/// told what it adds first (it may throw).
inline void ensure_scratch(DeviceBuffer<unsigned char>& temp, std::size_t bytes, const GrowthCheck& check = {}) {
  const std::size_t need = std::max<std::size_t>(bytes, 1);
  check_growth(check, temp.growth_bytes(need));
  if (temp.size() < need) temp.resize(need);
}

/// out[k] = in[0] + ... + in[k-1] for k < n, in stream order. Throws CudaError.
template <class T>
void exclusive_sum(const T* in, T* out, std::size_t n, DeviceBuffer<unsigned char>& temp, cudaStream_t stream,
                   const GrowthCheck& check = {}) {
  std::size_t bytes = 0;
  SNAG_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, bytes, in, out, n, stream));
  ensure_scratch(temp, bytes, check);
  bytes = temp.size();
  SNAG_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(temp.data(), bytes, in, out, n, stream));
}

/// out[k] = in[0] op ... op in[k-1] for k < n (out[0] = T{}), in stream
/// order; op is associative and T{} its identity. Throws CudaError.
template <class T, class Op>
void exclusive_scan(const T* in, T* out, std::size_t n, Op op, DeviceBuffer<unsigned char>& temp, cudaStream_t stream,
                    const GrowthCheck& check = {}) {
  std::size_t bytes = 0;
  SNAG_CUDA_CHECK(cub::DeviceScan::ExclusiveScan(nullptr, bytes, in, out, op, T{}, n, stream));
  ensure_scratch(temp, bytes, check);
  bytes = temp.size();
  SNAG_CUDA_CHECK(cub::DeviceScan::ExclusiveScan(temp.data(), bytes, in, out, op, T{}, n, stream));
}

/// Sorts the pairs (keys_in[k], values_in[k]), k < n, by bits [0, end_bit)
/// of the keys into keys_out and values_out, stably, in stream order.
/// Throws CudaError.
template <class Key, class Value>
void radix_sort_pairs(const Key* keys_in, Key* keys_out, const Value* values_in, Value* values_out, std::size_t n,
                      int end_bit, DeviceBuffer<unsigned char>& temp, cudaStream_t stream,
                      const GrowthCheck& check = {}) {
  std::size_t bytes = 0;
  SNAG_CUDA_CHECK(
      cub::DeviceRadixSort::SortPairs(nullptr, bytes, keys_in, keys_out, values_in, values_out, n, 0, end_bit, stream));
  ensure_scratch(temp, bytes, check);
  bytes = temp.size();
  SNAG_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(temp.data(), bytes, keys_in, keys_out, values_in, values_out, n, 0,
                                                  end_bit, stream));
}

/// The same on double buffers: the sorted pairs are in their Current() halves.
template <class Key, class Value>
void radix_sort_pairs(cub::DoubleBuffer<Key>& keys, cub::DoubleBuffer<Value>& values, std::size_t n, int end_bit,
                      DeviceBuffer<unsigned char>& temp, cudaStream_t stream, const GrowthCheck& check = {}) {
  std::size_t bytes = 0;
  SNAG_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(nullptr, bytes, keys, values, n, 0, end_bit, stream));
  ensure_scratch(temp, bytes, check);
  bytes = temp.size();
  SNAG_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(temp.data(), bytes, keys, values, n, 0, end_bit, stream));
}

/// Sorts the n keys of `keys` by bits [0, end_bit); they are then in its
/// Current() half. Throws CudaError.
template <class Key>
void radix_sort_keys(cub::DoubleBuffer<Key>& keys, std::size_t n, int end_bit, DeviceBuffer<unsigned char>& temp,
                     cudaStream_t stream, const GrowthCheck& check = {}) {
  std::size_t bytes = 0;
  SNAG_CUDA_CHECK(cub::DeviceRadixSort::SortKeys(nullptr, bytes, keys, n, 0, end_bit, stream));
  ensure_scratch(temp, bytes, check);
  bytes = temp.size();
  SNAG_CUDA_CHECK(cub::DeviceRadixSort::SortKeys(temp.data(), bytes, keys, n, 0, end_bit, stream));
}

/// The bits a radix sort needs for keys up to max_value (at least 1).
inline int radix_bits(std::uint64_t max_value) {
  int bits = 1;
  while (bits < 64 && (max_value >> bits) != 0) ++bits;
  return bits;
}

/// A sort key of two ids: `high` above `low`, which takes the lowest
/// low_bits bits (low < 2^low_bits, e.g. radix_bits of the largest low id).
/// Keys ascend as (high, low) do, and a radix sort over
/// radix_bits(largest high) + low_bits bits takes fewer passes than one with
/// `low` in 32 bits.
__host__ __device__ inline std::uint64_t pack_key(std::uint64_t high, std::uint32_t low, int low_bits) {
  return (high << low_bits) | low;
}

/// The two ids of a pack_key key.
__host__ __device__ inline void unpack_key(std::uint64_t key, int low_bits, std::uint32_t& high, std::uint32_t& low) {
  high = static_cast<std::uint32_t>(key >> low_bits);
  low = static_cast<std::uint32_t>(key & ((std::uint64_t{1} << low_bits) - 1));
}

}  // namespace snag::detail
