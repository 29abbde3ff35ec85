#include "libcd/scene/object.hpp"

#include <algorithm>
#include <cassert>

namespace snag {

// Each triangle side as (low end, high end), sorted, repeats kept: counted
// into one run per low end, then each run (a vertex's few edges) sorted by
// the high end, which takes linear time where a sort of all the sides (a
// large mesh has millions) took most of opening the mesh.
static std::vector<Edge> triangle_edges_with_repeats(const std::vector<Triangle>& triangles) {
  Index highest = 0;  // corner
  for (const Triangle& t : triangles) highest = std::max({highest, t[0], t[1], t[2]});
  std::vector<std::size_t> run(triangles.empty() ? 1 : std::size_t{highest} + 2, 0);  // run[v + 1]: sides of low end v
  auto side = [](const Triangle& t, int k) {
    const Index a = t[k], b = t[(k + 1) % 3];
    return a < b ? Edge{a, b} : Edge{b, a};
  };
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) ++run[side(t, k)[0] + std::size_t{1}];
  for (std::size_t v = 1; v < run.size(); ++v) run[v] += run[v - 1];
  std::vector<Edge> edges(triangles.size() * 3);
  std::vector<std::size_t> next(run.begin(), run.end() - 1);
  for (const Triangle& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const Edge e = side(t, k);
      edges[next[e[0]]++] = e;
    }
  }
  for (std::size_t v = 0; v + 1 < run.size(); ++v) {
    std::sort(edges.begin() + static_cast<std::ptrdiff_t>(run[v]),
              edges.begin() + static_cast<std::ptrdiff_t>(run[v + 1]),
              [](const Edge& x, const Edge& y) { return x[1] < y[1]; });
  }
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
