// query_cuda_device() never throws and always explains itself: either a usable
// device with its properties, or a reason. Runs with and without a GPU.
#include <gtest/gtest.h>

#include "gpu_test.hpp"
#include "libcd/cuda/device.hpp"

namespace snag {
namespace {

TEST(CudaDevice, QueryNeverThrowsAndExplainsItself) {
  CudaDeviceInfo info;
  ASSERT_NO_THROW(info = query_cuda_device());
  EXPECT_GT(info.runtime_version, 0);
  if (info.available) {
    EXPECT_TRUE(info.why_not.empty()) << info.why_not;
    EXPECT_GE(info.device, 0);
    EXPECT_FALSE(info.name.empty());
    EXPECT_GT(info.sm_major, 0);
    EXPECT_GT(info.total_memory, 0u);
    EXPECT_LE(info.free_memory, info.total_memory);
    EXPECT_GE(info.driver_version, info.runtime_version);
    std::cout << "device " << info.device << ": " << info.name << ", compute capability " << info.sm_major << "."
              << info.sm_minor << ", " << info.free_memory / (1 << 20) << " of " << info.total_memory / (1 << 20)
              << " MiB free\n";
  } else {
    EXPECT_FALSE(info.why_not.empty());
    EXPECT_EQ(info.why_not.find('\n'), std::string::npos) << "why_not must be one line";
    std::cout << "no GPU: " << info.why_not << "\n";
  }
}

TEST(CudaDevice, RepeatedQueriesAgree) {
  const CudaDeviceInfo a = query_cuda_device();
  const CudaDeviceInfo b = query_cuda_device();
  EXPECT_EQ(a.available, b.available);
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.why_not, b.why_not);
}

}  // namespace
}  // namespace snag
