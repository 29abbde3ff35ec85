// SNAG_CUDA_CHECK turns a failed CUDA call into a CudaError that names the
// call, the file and line, and CUDA's error name. Needs no device: the failing
// status is given directly, or comes from a call that fails without a GPU too.
#include <gtest/gtest.h>

#include <string>

#include "libcd/cuda/cuda_check.cuh"

namespace snag {
namespace {

TEST(CudaCheck, PassesOnSuccess) { EXPECT_NO_THROW(SNAG_CUDA_CHECK(cudaSuccess)); }

TEST(CudaCheck, ThrowsCudaErrorNamingCallFileAndLine) {
  const int line = __LINE__ + 2;
  try {
    SNAG_CUDA_CHECK(cudaErrorInvalidValue);
    FAIL() << "SNAG_CUDA_CHECK did not throw";
  } catch (const CudaError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("cuda_check_test.cu:" + std::to_string(line) + ":"), std::string::npos) << what;
    EXPECT_NE(what.find("cudaErrorInvalidValue failed"), std::string::npos) << what;
    EXPECT_NE(what.find("(invalid argument)"), std::string::npos) << what;
    EXPECT_EQ(e.code(), static_cast<int>(cudaErrorInvalidValue));
  }
}

TEST(CudaCheck, ReportsAFailingRuntimeCall) {
  // No machine has 99999 devices: this fails with or without a GPU
  // (invalid device, no device, or no driver).
  try {
    SNAG_CUDA_CHECK(cudaSetDevice(99999));
    FAIL() << "cudaSetDevice(99999) succeeded";
  } catch (const CudaError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("cudaSetDevice(99999) failed: cudaError"), std::string::npos) << what;
    EXPECT_NE(e.code(), static_cast<int>(cudaSuccess));
  }
}

TEST(CudaCheck, CudaErrorIsARuntimeError) {
  EXPECT_THROW(SNAG_CUDA_CHECK(cudaErrorMemoryAllocation), std::runtime_error);
}

}  // namespace
}  // namespace snag
