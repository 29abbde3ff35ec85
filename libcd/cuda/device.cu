#include "libcd/cuda/device.hpp"

#include <cuda_runtime_api.h>

#include <exception>
#include <string>

namespace snag {
namespace {

// An empty kernel: its attributes exist only when the binary holds an image
// (or PTX) that the device can run.
__global__ void probe_kernel() {}

std::string version_text(int v) { return std::to_string(v / 1000) + "." + std::to_string((v % 1000) / 10); }

std::string cuda_words(cudaError_t e) {
  return std::string(cudaGetErrorName(e)) + ": " + cudaGetErrorString(e);
}

CudaDeviceInfo query(CudaDeviceInfo info) {
  cudaDriverGetVersion(&info.driver_version);
  cudaRuntimeGetVersion(&info.runtime_version);

  int count = 0;
  const cudaError_t count_status = cudaGetDeviceCount(&count);
  if (count_status != cudaSuccess || count == 0) {
    (void)cudaGetLastError();
    if (info.driver_version == 0) {
      info.why_not = "no NVIDIA driver found (libcuda could not be loaded); the CUDA back end needs one";
    } else if (count_status == cudaErrorInsufficientDriver || info.driver_version < info.runtime_version) {
      info.why_not = "driver too old: it supports CUDA " + version_text(info.driver_version) + ", this build needs CUDA " +
                     version_text(info.runtime_version) + " (cudaGetDeviceCount: " + cuda_words(count_status) + ")";
    } else if (count_status != cudaSuccess) {
      info.why_not = "no CUDA device found (cudaGetDeviceCount: " + cuda_words(count_status) + ")";
    } else {
      info.why_not = "no CUDA device found (cudaGetDeviceCount: 0 devices)";
    }
    return info;
  }

  int device = 0;
  if (cudaGetDevice(&device) != cudaSuccess) device = 0;
  info.device = device;
  cudaDeviceProp prop{};
  const cudaError_t prop_status = cudaGetDeviceProperties(&prop, device);
  if (prop_status != cudaSuccess) {
    (void)cudaGetLastError();
    info.why_not = "CUDA device " + std::to_string(device) + " cannot be queried (cudaGetDeviceProperties: " +
                   cuda_words(prop_status) + ")";
    return info;
  }
  info.name = prop.name;
  info.sm_major = prop.major;
  info.sm_minor = prop.minor;
  info.total_memory = prop.totalGlobalMem;

  // The first call that creates the context: reports busy or prohibited devices.
  std::size_t free_bytes = 0, total_bytes = 0;
  const cudaError_t mem_status = cudaMemGetInfo(&free_bytes, &total_bytes);
  if (mem_status != cudaSuccess) {
    (void)cudaGetLastError();
    info.why_not = "CUDA device " + std::to_string(device) + " (" + info.name +
                   ") cannot be used (cudaMemGetInfo: " + cuda_words(mem_status) + ")";
    return info;
  }
  info.free_memory = free_bytes;
  info.total_memory = total_bytes;

  cudaFuncAttributes attributes{};
  const cudaError_t image_status = cudaFuncGetAttributes(&attributes, probe_kernel);
  if (image_status != cudaSuccess) {
    (void)cudaGetLastError();
    info.why_not = "CUDA device " + std::to_string(device) + " (" + info.name + ", compute capability " +
                   std::to_string(info.sm_major) + "." + std::to_string(info.sm_minor) +
                   ") cannot run this build's kernels, compiled for CUDA architectures " SNAG_CUDA_ARCHITECTURES
                   " (cudaFuncGetAttributes: " + cuda_words(image_status) +
                   "); rebuild with -DCMAKE_CUDA_ARCHITECTURES=" + std::to_string(info.sm_major) +
                   std::to_string(info.sm_minor);
    return info;
  }
  info.available = true;
  return info;
}

}  // namespace

CudaDeviceInfo query_cuda_device() {
  CudaDeviceInfo info;
  try {
    return query(info);
  } catch (const std::exception& e) {  // std::string may throw bad_alloc; this function promises not to throw
    info.available = false;
    info.why_not = std::string("CUDA device query failed: ") + e.what();
    return info;
  }
}

}  // namespace snag
