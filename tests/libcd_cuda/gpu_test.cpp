#include "gpu_test.hpp"

#include <cstdlib>

namespace snag::test {

const CudaDeviceInfo& cuda_device() {
  static const CudaDeviceInfo info = query_cuda_device();
  return info;
}

std::string shared_data_dir() {
  const char* from_environment = std::getenv("SNAG_SHARED_DATA_DIR");
  if (from_environment != nullptr && *from_environment != '\0') return from_environment;
  return SNAG_SHARED_DATA_DIR;
}

}  // namespace snag::test
