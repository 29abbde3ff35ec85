#include "libcd/narrow_phase/vertex_fans.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "libcd/geometry/predicates.hpp"

namespace snag {

namespace {

/// Chains the far edges (p, q) of one vertex's k triangles into a ring
/// r_0 ... r_k (r_k = r_0 when closed) appended to `ring`; false (ring
/// unchanged) when they do not form one path or one cycle of 3 or more.
bool chain_fan(const std::vector<std::array<Index, 2>>& far_edges, std::vector<Index>& ring) {
  const std::size_t k = far_edges.size();
  // A path starts at a ring vertex met once; a cycle anywhere.
  Index start = far_edges[0][0];
  std::size_t ends = 0;
  for (const auto& edge : far_edges) {
    for (const Index end : edge) {
      std::size_t degree = 0;
      for (const auto& other : far_edges) degree += std::size_t(other[0] == end) + std::size_t(other[1] == end);
      if (degree > 2) return false;
      if (degree == 1) {
        start = end;
        ++ends;
      }
    }
  }
  if (ends != 0 && ends != 2) return false;
  if (ends == 0 && k < 3) return false;
  const std::size_t begin = ring.size();
  std::vector<bool> used(k, false);
  Index current = start;
  ring.push_back(current);
  for (std::size_t step = 0; step < k; ++step) {
    std::size_t next = k;
    for (std::size_t e = 0; e < k && next == k; ++e)
      if (!used[e] && (far_edges[e][0] == current || far_edges[e][1] == current)) next = e;
    if (next == k) {  // the triangles form more than one fan
      ring.resize(begin);
      return false;
    }
    used[next] = true;
    current = far_edges[next][0] == current ? far_edges[next][1] : far_edges[next][0];
    ring.push_back(current);
  }
  if ((ends == 0) != (current == start)) {
    ring.resize(begin);
    return false;
  }
  return true;
}

/// For q on the line through v and r0 (r0 and q apart from v), in the
/// projection dropping `axis`: whether q lies on the ray from v through r0
/// (rather than on the opposite ray). Coordinate comparisons, exact.
bool same_direction(Vec3 v, Vec3 r0, Vec3 q, int axis) {
  const int u = axis == 2 ? 0 : axis + 1;
  const int w = u == 2 ? 0 : u + 1;
  if (r0[u] != v[u]) return (q[u] > v[u]) == (r0[u] > v[u]);
  return (q[w] > v[w]) == (r0[w] > v[w]);
}

/// Whether the fan of v with ring r (k + 1 points) is apart at positions x
/// (the header's conditions), in the projection dropping `axis`.
bool fan_is_apart(Vec3 v, const Index* r, std::size_t k, const std::vector<Vec3>& x, int axis) {
  const Vec3 r0 = x[r[0]];
  const bool closed = r[k] == r[0];
  int turn = 0;  // the sign of every wedge
  int previous = 0;  // the side of v→r_0 that r_i lies on, times turn
  for (std::size_t i = 0; i < k; ++i) {
    const Vec3 p = x[r[i]], q = x[r[i + 1]];
    const int wedge = orient2d_projected(v, p, q, axis);
    if (wedge == 0) return false;
    if (i == 0) turn = wedge;
    if (wedge != turn) return false;
    if (i == 0) {
      previous = 1;  // r_1 is on the turning side of v→r_0
      continue;
    }
    // Wedge i, from r_i to r_{i+1}; a closed fan's last ends on r_0.
    if (closed && i + 1 == k) break;
    const int side = turn * orient2d_projected(v, r0, q, axis);
    if (side == 0 && same_direction(v, r0, q, axis)) return false;  // r_{i+1} on the ray v→r_0
    if (previous < 0 && side > 0) return false;  // the wedge holds v→r_0's direction
    previous = side;
  }
  return true;
}

}  // namespace

VertexFans::VertexFans(const std::vector<Triangle>& triangles, std::size_t vertex_count)
    : vertex_count_(vertex_count) {
  // The triangles of each vertex (a counting sort); a repeated id spoils
  // the fans of the triangle's vertices.
  std::vector<std::uint64_t> first_incident(vertex_count + 1, 0);
  std::vector<unsigned char> spoiled(vertex_count, 0);
  for (const Triangle& t : triangles) {
    for (const Index v : t) ++first_incident[v + 1];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
      for (const Index v : t) spoiled[v] = 1;
  }
  for (std::size_t v = 0; v < vertex_count; ++v) first_incident[v + 1] += first_incident[v];
  std::vector<std::uint64_t> next(first_incident.begin(), first_incident.end() - 1);
  std::vector<std::array<Index, 2>> far_edge_of(first_incident[vertex_count]);
  for (const Triangle& t : triangles)
    for (int i = 0; i < 3; ++i) far_edge_of[next[t[i]]++] = {t[(i + 1) % 3], t[(i + 2) % 3]};
  first_.assign(vertex_count + 1, 0);
  ring_.reserve(far_edge_of.size() + vertex_count);
  std::vector<std::array<Index, 2>> far_edges;
  for (std::size_t v = 0; v < vertex_count; ++v) {
    const std::size_t k = first_incident[v + 1] - first_incident[v];
    if (!spoiled[v] && k != 0 && k <= kMaxFan) {
      far_edges.assign(far_edge_of.begin() + std::ptrdiff_t(first_incident[v]),
                       far_edge_of.begin() + std::ptrdiff_t(first_incident[v + 1]));
      chained_ += chain_fan(far_edges, ring_);
    }
    first_[v + 1] = ring_.size();
  }
}

void VertexFans::find_apart(const std::vector<Vec3>& x, std::vector<unsigned char>& apart) const {
  apart.resize(vertex_count_);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertex_count_, 512), [&](const auto& range) {
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      const std::size_t begin = first_[v], end = first_[v + 1];
      if (begin == end) {
        apart[v] = 0;
        continue;
      }
      const Index* r = ring_.data() + begin;
      const std::size_t k = end - begin - 1;
      // The projection that keeps the fan's summed normal best conditioned.
      const Vec3 p = x[v];
      Vec3 normal{0, 0, 0};
      for (std::size_t i = 0; i < k; ++i) normal = normal + cross(x[r[i]] - p, x[r[i + 1]] - p);
      const double nx = std::fabs(normal.x), ny = std::fabs(normal.y), nz = std::fabs(normal.z);
      const int axis = (nx >= ny && nx >= nz) ? 0 : (ny >= nz ? 1 : 2);
      apart[v] = fan_is_apart(p, r, k, x, axis) ? 1 : 0;
    }
  });
}

}  // namespace snag
