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

}  // namespace snag
