// The objects an event's two elements belong to: the one place that maps an
// event's global ids (vertex, edge or face, by its type) to objects.
#pragma once

#include <cstddef>
#include <utility>

#include "libcd/pipeline/event.hpp"
#include "libcd/scene/scene.hpp"

namespace snag {

/// The objects of elements a and b of `event`, in that order.
inline std::pair<std::size_t, std::size_t> element_objects(const Scene& scene, const Event& event) {
  switch (event.type) {
    case ContactType::kVertexFace: return {scene.object_of_vertex(event.a), scene.object_of_triangle(event.b)};
    case ContactType::kEdgeEdge: return {scene.object_of_edge(event.a), scene.object_of_edge(event.b)};
    case ContactType::kTriangleTriangle: break;
  }
  return {scene.object_of_triangle(event.a), scene.object_of_triangle(event.b)};
}

}  // namespace snag
