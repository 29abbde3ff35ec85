// The first stage of the GPU pipeline: per-triangle bounding-sphere radii
// (static at t0 and swept over the step), the scene's bounding box over both
// frames, the mean radii and the grid cell size 3·λ·r_avg of the virtual
// subdivision scheme (Wong, Leach and Zambetta, eq. 5.1). The radii come from
// one thread per triangle, the box and the means from device reductions (CUB).
// Sphere definitions: libcd/cuda/triangle_sphere.hpp.
#pragma once

#include <cstddef>
#include <vector>

#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/mesh.hpp"

struct CUstream_st;  // cudaStream_t is CUstream_st*; CUDA types stay out of this header

namespace snag {

/// Milliseconds measured with CUDA events on the stream.
struct TriangleBoundsTimings {
  float upload_ms = 0;    ///< positions and triangles to the device
  float kernels_ms = 0;   ///< radii kernel and the reductions
  float download_ms = 0;  ///< radii, box and sums back to the host
};

struct TriangleBounds {
  std::vector<double> static_radii;  ///< #F radii of the triangles' spheres at t0, scene units
  std::vector<double> swept_radii;   ///< #F radii of the spheres holding each triangle over the step
  Vec3 scene_lo, scene_hi;           ///< box of every position at t0 and at t1 (not padded)
  double mean_static_radius = 0;     ///< mean of static_radii; 0 when there are no triangles
  double mean_swept_radius = 0;      ///< mean of swept_radii (r_avg); 0 when there are no triangles
  double cell_size = 0;              ///< 3·λ·mean_swept_radius, scene units
  TriangleBoundsTimings timings;
};

/// Computes TriangleBounds on the current CUDA device.
/// @param x_t0, x_t1  #V global positions at the start and end of the step (for
///                    a single frame, pass the same positions twice); same size.
/// @param triangles   #F triangles of global vertex ids, each < #V.
/// @param lambda      λ of the cell size, > 1 (the chapter uses 1.1 to 1.3; kDefaultLambda).
/// @param stream      stream to run on (a cudaStream_t); nullptr = the default stream.
///                    The call returns when the results are on the host.
/// Throws CudaError when a CUDA call fails. Mismatched sizes or out-of-range
/// vertex ids are caller bugs (asserted).
TriangleBounds compute_triangle_bounds_cuda(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                            const std::vector<Triangle>& triangles, double lambda,
                                            CUstream_st* stream = nullptr);

}  // namespace snag
