// One object of one frame as a plain triangle mesh, and the boxes the volume
// measures work in.
#pragma once

#include <cstddef>
#include <vector>

#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/mesh.hpp"
#include "libcd/scene/scene.hpp"

namespace snag::volume {

/// #V positions (scene units) and #F by 3 vertex ids into them.
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;
};

/// An axis-aligned box, lo <= hi (scene units).
struct Box {
  Vec3 lo, hi;
};

/// Object `object` of `scene` at the global positions `positions` (#V of the
/// scene), with its local vertex and triangle ids.
TriangleMesh object_mesh(const Scene& scene, std::size_t object, const std::vector<Vec3>& positions);

/// The bounding box of triangle `t`'s corners.
Box triangle_box(const TriangleMesh& mesh, std::size_t t);
/// The bounding box of every vertex (lo > hi when there are none).
Box mesh_box(const TriangleMesh& mesh);

Box grown(const Box& box, double margin);
bool overlaps(const Box& a, const Box& b);
/// The overlap of two boxes (lo > hi somewhere when they do not meet).
Box intersection(const Box& a, const Box& b);
bool contains(const Box& outer, const Box& inner);
double longest_side(const Box& box);

/// The signed volume the triangles enclose (divergence theorem): positive for
/// a closed mesh whose faces are ordered counter-clockwise seen from outside.
double signed_volume(const TriangleMesh& mesh);

}  // namespace snag::volume
