#include "libcd/narrow_phase/triangle_triangle.hpp"

namespace snag {

const char* to_string(TriangleAdjacency adjacency) {
  switch (adjacency) {
    case TriangleAdjacency::none: return "none";
    case TriangleAdjacency::shared_vertex: return "shared_vertex";
    case TriangleAdjacency::shared_edge: return "shared_edge";
    case TriangleAdjacency::same_vertices: return "same_vertices";
    case TriangleAdjacency::degenerate: return "degenerate";
  }
  return "unknown";
}

}  // namespace snag
