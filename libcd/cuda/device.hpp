// Which CUDA device the GPU back end would use, and if none, why not.
// `snag-scan --backend auto` picks the GPU when `available` is true;
// `--backend cuda` prints `why_not` when it is false.
#pragma once

#include <cstddef>
#include <string>

namespace snag {

struct CudaDeviceInfo {
  bool available = false;   ///< a device is present and can run this build's kernels
  int device = -1;          ///< CUDA device ordinal used (the current device, 0 unless set); -1 when none
  std::string name;         ///< e.g. "NVIDIA H100 80GB HBM3"; empty when none
  int sm_major = 0;         ///< compute capability, e.g. 9.0 for H100/H200
  int sm_minor = 0;
  std::size_t total_memory = 0;  ///< bytes of device memory
  std::size_t free_memory = 0;   ///< bytes free at the time of the query
  int driver_version = 0;   ///< CUDA version the driver supports, as 1000·major + 10·minor; 0 = no driver
  int runtime_version = 0;  ///< CUDA runtime this build links, same encoding
  std::string why_not;      ///< one line saying why the GPU back end cannot run; empty when available
};

/// Looks for a CUDA device that can run this build's kernels: a driver new
/// enough for the runtime linked in, at least one device, and a kernel image
/// (or PTX) for its architecture. Never throws: every failure is described
/// in why_not. Initialises the CUDA context on the device it reports.
CudaDeviceInfo query_cuda_device();

}  // namespace snag
