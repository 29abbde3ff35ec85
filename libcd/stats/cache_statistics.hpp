// What snag-info reports about a cache: per-object topology counts, and per-
// cache geometry statistics gathered frame by frame (streamed: one frame and
// the previous one are held at a time).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "libcd/geometry/vec3.hpp"
#include "libcd/grid/cell_size.hpp"
#include "libcd/scene/frame_source.hpp"

namespace snag {

struct ObjectStatistics {
  std::string name;
  std::size_t vertices = 0, triangles = 0, edges = 0;
  std::size_t boundary_edges = 0, non_manifold_edges = 0;
  /// Triangles with a repeated vertex id or three collinear corners in the
  /// first frame (exact test).
  std::size_t degenerate_triangles = 0;
};

/// Minimum, mean and maximum of a sample.
struct Range {
  double min = 0, mean = 0, max = 0;
};

struct CacheStatistics {
  std::vector<ObjectStatistics> objects;
  std::size_t frames = 0;
  double first_time = 0, last_time = 0;  ///< frame times as the cache numbers them
  Vec3 bounds_min, bounds_max;           ///< over every vertex of every frame
  /// Triangle bounding-sphere radius over every triangle of every frame.
  Range sphere_radius;
  /// The virtual subdivision scheme's cell size, 3 × λ × mean radius, per frame.
  Range cell_size;
  double lambda = kDefaultLambda;
  /// Triangles that exceed a third of their frame's cell (the most in any
  /// frame), and the most Loop levels any triangle needs.
  std::size_t subdivided_triangles = 0;
  int subdivision_levels = 0;
  /// Largest vertex displacement between consecutive frames, divided by the
  /// cell size of the earlier frame, and where it happens.
  double max_displacement_over_cell = 0;
  std::size_t max_displacement_frame = 0;    ///< the earlier frame of the pair
  std::size_t max_displacement_vertex = 0;   ///< global vertex id
};

/// Reads every frame of `source` once, in order, and gathers the statistics.
/// `lambda` is the cell-size coefficient (> 1). Throws what read_frame throws.
CacheStatistics compute_cache_statistics(const FrameSource& source, double lambda = kDefaultLambda);

}  // namespace snag
