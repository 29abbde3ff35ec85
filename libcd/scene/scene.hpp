// A scene: several named objects whose vertices, triangles and edges are
// concatenated into global arrays for the pipeline. Global ids map back to
// (object, local id) for reports.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "libcd/scene/object.hpp"

namespace snag {

class Scene {
 public:
  Scene() = default;
  explicit Scene(std::vector<Object> objects);

  const std::vector<Object>& objects() const { return objects_; }
  std::size_t vertex_count() const { return vertex_offset_.back(); }
  std::size_t triangle_count() const { return triangles_.size(); }
  std::size_t edge_count() const { return edges_.size(); }

  /// Global triangles (#F by 3 global vertex ids), objects in order.
  const std::vector<Triangle>& triangles() const { return triangles_; }
  /// Global unique edges (#E by 2 global vertex ids), objects in order.
  const std::vector<Edge>& edges() const { return edges_; }

  /// First global vertex / triangle / edge id of object `o`; index objects().size() gives the totals.
  Index vertex_offset(std::size_t o) const { return vertex_offset_[o]; }
  Index triangle_offset(std::size_t o) const { return triangle_offset_[o]; }
  Index edge_offset(std::size_t o) const { return edge_offset_[o]; }

  /// The object that holds a global vertex / triangle / edge id. Inline:
  /// the report looks up the objects of every event.
  std::size_t object_of_vertex(Index v) const { return range_of(vertex_offset_, v); }
  std::size_t object_of_triangle(Index f) const { return range_of(triangle_offset_, f); }
  std::size_t object_of_edge(Index e) const { return range_of(edge_offset_, e); }

 private:
  /// offsets ascends from offsets[0] = 0: the object is the last offset <= id
  /// among those that start a non-empty range.
  static std::size_t range_of(const std::vector<Index>& offsets, Index id) {
    if (offsets.size() == 2) return 0;  // one object
    const auto it = std::upper_bound(offsets.begin(), offsets.end(), id);
    return static_cast<std::size_t>(it - offsets.begin()) - 1;
  }

  std::vector<Object> objects_;
  std::vector<Triangle> triangles_;
  std::vector<Edge> edges_;
  std::vector<Index> vertex_offset_{0}, triangle_offset_{0}, edge_offset_{0};
};

}  // namespace snag
