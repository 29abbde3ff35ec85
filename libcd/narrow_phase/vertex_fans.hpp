// Neighbouring triangles shown apart a vertex at a time: the static test's
// shortcut for the pairs that share a vertex, most of a cloth's candidate
// pairs (about 6 per triangle, against well under 1 that share none).
//
// The triangles around a vertex v of a manifold mesh form a fan: their far
// edges chain into a ring r_0, r_1, ..., r_k around v (r_k = r_0 when the
// fan is closed), triangle i being (v, r_i, r_{i+1}). Projected along a
// coordinate axis, triangle i covers the wedge at v between rays v→r_i and
// v→r_{i+1}. When every wedge turns the same way (orient2d(v, r_i, r_{i+1})
// all non-zero, of one sign) and the wedges, swept in turn, do not reach the
// direction of v→r_0 again before the fan ends (no r_j, j ≥ 1, on the line
// of v→r_0, and no wedge after the first holding that direction strictly
// inside; a closed fan ends on it), the wedges meet only along the rays
// between consecutive ones. Then two triangles of the fan project into
// wedges that meet only at v (triangles sharing only v) or only along their
// shared edge's ray, on opposite sides of it (triangles sharing an edge).
// A non-degenerate triangle projects one to one, so the two triangles meet
// in 3D only at v or only on their shared edge: neither pair intersects by
// triangles_intersect's rules (a shared edge counts only when coplanar
// with the opposite vertices strictly on one side). Such a vertex is
// "apart": every pair of triangles sharing it is known not to intersect.
// About 2 orientation signs per fan triangle, against 4 or 5 per pair for
// the 2D filter (triangles_separated_in_projection), with each pair met in
// the fan of each vertex it shares.
//
// A vertex whose triangles do not chain into one fan (a non-manifold vertex
// or edge, a repeated vertex id, a fan of more than kMaxFan triangles) is
// never apart; nor is one whose fan folds over in the projection (the
// signs are exact, see predicates.hpp; any axis is sound, the dominant axis
// of the fan's summed normals is tried).
#pragma once

#include <cstdint>
#include <vector>

#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag {

/// The fans of a mesh's vertices, from its topology alone (build once per scene).
class VertexFans {
 public:
  /// Fans with more triangles than this are not chained (never apart).
  static constexpr std::size_t kMaxFan = 64;

  /// Chains the fans of every vertex of `triangles` (#F, ids < vertex_count).
  VertexFans(const std::vector<Triangle>& triangles, std::size_t vertex_count);

  /// Per vertex (#V): 1 when every pair of triangles sharing it is shown not
  /// to intersect at positions x (#V), else 0, on the calling arena's threads.
  /// `apart` is resized to #V.
  void find_apart(const std::vector<Vec3>& x, std::vector<unsigned char>& apart) const;

  /// Vertices whose triangles chain into one fan (a path or a cycle).
  std::size_t chained_count() const { return chained_; }

 private:
  std::size_t vertex_count_ = 0;
  std::size_t chained_ = 0;
  /// #V + 1: start of each vertex's ring in ring_; an empty ring (no
  /// triangles, or not chained) is never apart.
  std::vector<std::uint64_t> first_;
  std::vector<Index> ring_;  ///< r_0 ... r_k per vertex (k triangles), r_k = r_0 when closed
};

}  // namespace snag
