// See contracted_early_exits.hpp. Built with --fmad=true (CMakeLists.txt)
// and the separation loops unrolled, as the screen is.
#define SNAG_CCD_UNROLL_SEPARATION 1
#include "contracted_early_exits.hpp"

#include <cstddef>

#include "libcd/cuda/cuda_check.cuh"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/cuda/launch.cuh"
#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"

namespace snag::test {
namespace {

__global__ void early_exits_kernel(const EarlyExitQuery* queries, std::size_t count, CcdSettings settings,
                                   unsigned char* ruled_out) {
  const std::uint64_t i = detail::thread_item();
  if (i >= count) return;
  const Vec3* p = queries[i].points.data();
  CcdResult result;
  const bool decided =
      queries[i].edge_edge
          ? edge_edge_early_exit(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings, &result)
          : vertex_face_early_exit(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings, &result);
  ruled_out[i] = decided && result.answer == CcdAnswer::kNo ? 1 : 0;
}

__global__ void multiply_add_kernel(const double* in, double* out) { out[0] = in[0] * in[1] + in[2]; }

}  // namespace

std::vector<bool> contracted_early_exits_rule_out(const std::vector<EarlyExitQuery>& queries,
                                                  const CcdSettings& settings) {
  const std::size_t n = queries.size();
  if (n == 0) return {};
  DeviceBuffer<EarlyExitQuery> device_queries(n, nullptr);
  DeviceBuffer<unsigned char> ruled_out(n, nullptr);
  device_queries.upload(queries.data(), n);
  early_exits_kernel<<<detail::blocks_for(n), detail::kBlockSize>>>(device_queries.data(), n, settings,
                                                                    ruled_out.data());
  SNAG_CUDA_CHECK_LAUNCH();
  const std::vector<unsigned char> flags = ruled_out.download();
  return std::vector<bool>(flags.begin(), flags.end());
}

double contracted_multiply_add(double a, double b, double c) {
  const double in[3] = {a, b, c};
  DeviceBuffer<double> device_in(3, nullptr), device_out(1, nullptr);
  device_in.upload(in, 3);
  multiply_add_kernel<<<1, 1>>>(device_in.data(), device_out.data());
  SNAG_CUDA_CHECK_LAUNCH();
  return device_out.download()[0];
}

}  // namespace snag::test
