#include "volume/triangle_mesh.hpp"

#include <algorithm>
#include <limits>

namespace snag::volume {

TriangleMesh object_mesh(const Scene& scene, std::size_t object, const std::vector<Vec3>& positions) {
  TriangleMesh mesh;
  const Index first = scene.vertex_offset(object);
  mesh.vertices.assign(positions.begin() + first, positions.begin() + scene.vertex_offset(object + 1));
  mesh.triangles = scene.objects()[object].triangles;
  return mesh;
}

Box triangle_box(const TriangleMesh& mesh, std::size_t t) {
  const Triangle& f = mesh.triangles[t];
  const Vec3 a = mesh.vertices[f[0]], b = mesh.vertices[f[1]], c = mesh.vertices[f[2]];
  return {min(a, min(b, c)), max(a, max(b, c))};
}

Box mesh_box(const TriangleMesh& mesh) {
  const double inf = std::numeric_limits<double>::infinity();
  Box box{{inf, inf, inf}, {-inf, -inf, -inf}};
  for (const Vec3& p : mesh.vertices) {
    box.lo = min(box.lo, p);
    box.hi = max(box.hi, p);
  }
  return box;
}

Box grown(const Box& box, double margin) {
  const Vec3 m{margin, margin, margin};
  return {box.lo - m, box.hi + m};
}

bool overlaps(const Box& a, const Box& b) {
  for (int i = 0; i < 3; ++i) {
    if (a.hi[i] < b.lo[i] || b.hi[i] < a.lo[i]) return false;
  }
  return true;
}

Box intersection(const Box& a, const Box& b) { return {max(a.lo, b.lo), min(a.hi, b.hi)}; }

bool contains(const Box& outer, const Box& inner) {
  for (int i = 0; i < 3; ++i) {
    if (inner.lo[i] < outer.lo[i] || inner.hi[i] > outer.hi[i]) return false;
  }
  return true;
}

double longest_side(const Box& box) {
  return std::max({box.hi.x - box.lo.x, box.hi.y - box.lo.y, box.hi.z - box.lo.z});
}

double signed_volume(const TriangleMesh& mesh) {
  double six_volume = 0;
  for (const Triangle& f : mesh.triangles) {
    six_volume += dot(mesh.vertices[f[0]], cross(mesh.vertices[f[1]], mesh.vertices[f[2]]));
  }
  return six_volume / 6;
}

}  // namespace snag::volume
