#include "libcd/scene/scene.hpp"

#include <algorithm>

namespace snag {

Scene::Scene(std::vector<Object> objects) : objects_(std::move(objects)) {
  for (const Object& object : objects_) {
    const Index base = vertex_offset_.back();
    for (const Triangle& t : object.triangles) triangles_.push_back({t[0] + base, t[1] + base, t[2] + base});
    for (const Edge& e : object.edges) edges_.push_back({e[0] + base, e[1] + base});
    vertex_offset_.push_back(base + object.vertex_count);
    triangle_offset_.push_back(static_cast<Index>(triangles_.size()));
    edge_offset_.push_back(static_cast<Index>(edges_.size()));
  }
}

static std::size_t range_of(const std::vector<Index>& offsets, Index id) {
  // offsets is ascending with offsets[0] = 0; the object is the last offset <= id
  // among those that start a non-empty range.
  auto it = std::upper_bound(offsets.begin(), offsets.end(), id);
  return static_cast<std::size_t>(it - offsets.begin()) - 1;
}

std::size_t Scene::object_of_vertex(Index v) const { return range_of(vertex_offset_, v); }
std::size_t Scene::object_of_triangle(Index f) const { return range_of(triangle_offset_, f); }
std::size_t Scene::object_of_edge(Index e) const { return range_of(edge_offset_, e); }

}  // namespace snag
