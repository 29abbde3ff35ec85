// Marks functions usable from host and device code, so that the math the CPU
// and CUDA back ends share is written once.
#pragma once

#if defined(__CUDACC__)
#define SNAG_HD __host__ __device__
#define SNAG_HD_INLINE __host__ __device__ __forceinline__
#else
#define SNAG_HD
#define SNAG_HD_INLINE inline
#endif
