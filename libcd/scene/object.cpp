#include "libcd/scene/object.hpp"

#include <algorithm>
#include <cassert>

namespace snag {

static std::vector<Edge> triangle_edges_with_repeats(const std::vector<Triangle>& triangles) {
  std::vector<Edge> edges;
  edges.reserve(triangles.size() * 3);
  for (const Triangle& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      Index a = t[k], b = t[(k + 1) % 3];
      edges.push_back(a < b ? Edge{a, b} : Edge{b, a});
    }
  }
  std::sort(edges.begin(), edges.end());
  return edges;
}

Object make_object(std::string name, Index vertex_count, std::vector<Triangle> triangles) {
  for ([[maybe_unused]] const Triangle& t : triangles) {
    assert(t[0] < vertex_count && t[1] < vertex_count && t[2] < vertex_count);
  }
  Object object;
  object.name = std::move(name);
  object.vertex_count = vertex_count;
  object.edges = triangle_edges_with_repeats(triangles);
  object.edges.erase(std::unique(object.edges.begin(), object.edges.end()), object.edges.end());
  object.triangles = std::move(triangles);
  return object;
}

EdgeCounts count_edge_kinds(const Object& object) {
  std::vector<Edge> all = triangle_edges_with_repeats(object.triangles);
  EdgeCounts counts;
  for (std::size_t i = 0; i < all.size();) {
    std::size_t j = i;
    while (j < all.size() && all[j] == all[i]) ++j;
    if (j - i == 1) ++counts.boundary;
    if (j - i >= 3) ++counts.non_manifold;
    i = j;
  }
  return counts;
}

}  // namespace snag
