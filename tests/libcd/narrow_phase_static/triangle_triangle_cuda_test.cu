// triangles_intersect on the GPU against the same function on the CPU, on
// random soups over tiny integer grids (coplanar, touching and shared-vertex
// cases everywhere, so the exact stage runs on the device), and the exact
// stage counts. Exits 0 when every pair agrees.
#include <cuda_runtime.h>

#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include "libcd/narrow_phase/triangle_triangle.hpp"

namespace {

#define CHECK_CUDA(call)                                                                          \
  do {                                                                                            \
    const cudaError_t status = (call);                                                            \
    if (status != cudaSuccess) {                                                                  \
      std::fprintf(stderr, "%s:%d: %s\n", __FILE__, __LINE__, cudaGetErrorString(status));        \
      return 2;                                                                                   \
    }                                                                                             \
  } while (0)

struct Pair {
  snag::Vec3 a[3], b[3];
  std::uint32_t a_ids[3], b_ids[3];
};

__global__ void test_pairs(const Pair* pairs, int count, unsigned char* results,
                           unsigned long long* exact_count) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  snag::PredicateCounters counters;
  const Pair& p = pairs[i];
  results[i] = snag::triangles_intersect(p.a, p.a_ids, p.b, p.b_ids, &counters) ? 1 : 0;
  atomicAdd(exact_count, counters.exact);
}

std::vector<Pair> random_pairs(int count, double scale, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> coord(0, 2);
  std::vector<snag::Vec3> positions;
  for (int v = 0; v < 40; ++v)
    positions.push_back(snag::Vec3{double(coord(rng)), double(coord(rng)), double(coord(rng))} * scale);
  for (int v = 0; v < 12; ++v) positions.push_back(positions[std::size_t(v) * 3]);
  std::uniform_int_distribution<std::uint32_t> pick(0, std::uint32_t(positions.size() - 1));
  auto triangle = [&](snag::Vec3 p[3], std::uint32_t ids[3]) {
    do {
      for (int k = 0; k < 3; ++k) ids[k] = pick(rng);
    } while (ids[0] == ids[1] || ids[1] == ids[2] || ids[0] == ids[2]);
    for (int k = 0; k < 3; ++k) p[k] = positions[ids[k]];
  };
  std::vector<Pair> pairs(count);
  for (Pair& p : pairs) {
    triangle(p.a, p.a_ids);
    triangle(p.b, p.b_ids);
  }
  return pairs;
}

}  // namespace

int main() {
  int mismatches = 0;
  for (int trial = 0; trial < 2; ++trial) {
    const std::vector<Pair> pairs = random_pairs(200000, trial == 0 ? 1.0 : 0.1, 5 + trial);
    const int count = int(pairs.size());
    Pair* device_pairs = nullptr;
    unsigned char* device_results = nullptr;
    unsigned long long* device_exact = nullptr;
    CHECK_CUDA(cudaMalloc(&device_pairs, sizeof(Pair) * pairs.size()));
    CHECK_CUDA(cudaMalloc(&device_results, pairs.size()));
    CHECK_CUDA(cudaMalloc(&device_exact, sizeof(unsigned long long)));
    CHECK_CUDA(cudaMemcpy(device_pairs, pairs.data(), sizeof(Pair) * pairs.size(), cudaMemcpyHostToDevice));
    CHECK_CUDA(cudaMemset(device_exact, 0, sizeof(unsigned long long)));
    test_pairs<<<(count + 127) / 128, 128>>>(device_pairs, count, device_results, device_exact);
    CHECK_CUDA(cudaGetLastError());
    CHECK_CUDA(cudaDeviceSynchronize());
    std::vector<unsigned char> results(pairs.size());
    unsigned long long device_exact_count = 0;
    CHECK_CUDA(cudaMemcpy(results.data(), device_results, pairs.size(), cudaMemcpyDeviceToHost));
    CHECK_CUDA(cudaMemcpy(&device_exact_count, device_exact, sizeof(device_exact_count), cudaMemcpyDeviceToHost));
    CHECK_CUDA(cudaFree(device_pairs));
    CHECK_CUDA(cudaFree(device_results));
    CHECK_CUDA(cudaFree(device_exact));

    snag::PredicateCounters host_counters;
    int intersecting = 0;
    for (int i = 0; i < count; ++i) {
      const Pair& p = pairs[i];
      const bool host = snag::triangles_intersect(p.a, p.a_ids, p.b, p.b_ids, &host_counters);
      intersecting += host;
      if (host != bool(results[i]) && ++mismatches <= 5) std::printf("trial %d pair %d differs\n", trial, i);
    }
    std::printf("trial %d: %d pairs, %d intersecting, exact stage runs host %llu device %llu\n", trial, count,
                intersecting, host_counters.exact, device_exact_count);
    if (host_counters.exact != device_exact_count) ++mismatches;
    if (intersecting == 0 || intersecting == count) ++mismatches;
  }
  std::printf("%s\n", mismatches == 0 ? "PASSED" : "FAILED");
  return mismatches == 0 ? 0 : 1;
}
