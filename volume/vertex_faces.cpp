#include "volume/vertex_faces.hpp"

namespace snag::volume {

VertexFaces vertex_faces(const std::vector<Triangle>& triangles, std::size_t vertex_count) {
  VertexFaces out;
  out.start.assign(vertex_count + 1, 0);
  for (const Triangle& f : triangles)
    for (Index v : f) ++out.start[v + 1];
  for (std::size_t v = 0; v < vertex_count; ++v) out.start[v + 1] += out.start[v];
  std::vector<std::size_t> next(out.start.begin(), out.start.end() - 1);
  out.faces.resize(out.start.back());
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (Index v : triangles[t]) out.faces[next[v]++] = t;
  return out;
}

}  // namespace snag::volume
