// Shared pieces of the CUDA tests: the device query made once, a fixture that
// skips when no GPU can run the kernels, and where the reference data lies.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "libcd/cuda/device.hpp"

namespace snag::test {

/// query_cuda_device(), made once per process.
const CudaDeviceInfo& cuda_device();

/// Fixture for tests that need a GPU: skips, saying why, when none is usable.
class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!cuda_device().available) GTEST_SKIP() << "no usable CUDA device: " << cuda_device().why_not;
  }
};

/// The reference data directory: $SNAG_SHARED_DATA_DIR when set, else the one compiled in.
std::string shared_data_dir();

}  // namespace snag::test
