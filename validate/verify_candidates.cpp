#include "validate/verify_candidates.hpp"

#include <algorithm>
#include <limits>
#include <string>
#include <tuple>

#include "libcd/core/error.hpp"

namespace snag::validate {

namespace {

struct Box {
  double lo[3], hi[3];
};

Box empty_box() {
  Box box;
  for (int k = 0; k < 3; ++k) {
    box.lo[k] = std::numeric_limits<double>::infinity();
    box.hi[k] = -std::numeric_limits<double>::infinity();
  }
  return box;
}

void extend(Box& box, const Vec3& p) {
  const double c[3] = {p.x, p.y, p.z};
  for (int k = 0; k < 3; ++k) {
    box.lo[k] = std::min(box.lo[k], c[k]);
    box.hi[k] = std::max(box.hi[k], c[k]);
  }
}

// True only when the exact gap on some axis exceeds d (see the header: the
// rounded difference is > d only if the exact one is).
bool separated(const Box& a, const Box& b, double d) {
  for (int k = 0; k < 3; ++k) {
    if (b.lo[k] - a.hi[k] > d || a.lo[k] - b.hi[k] > d) return true;
  }
  return false;
}

struct SweepEntry {
  double lo_x;
  int set;  // 0 or 1
  Index index;
};

// Calls emit(i, j) for every i of set 0 and j of set 1 (or, when `self`, for
// every i < j of set 0 ... in any order) whose boxes are not separated by more
// than d. The x axis is swept after sorting on lo.x; a box leaves the active
// list once the current lo.x is more than d beyond its hi.x, which then holds
// for every later box too (lo.x only grows, and rounding is monotone).
template <typename Emit>
void sweep(const std::vector<Box>& boxes_a, const std::vector<Index>& ids_a, const std::vector<Box>& boxes_b,
           const std::vector<Index>& ids_b, bool self, double d, Emit emit) {
  std::vector<SweepEntry> entries;
  entries.reserve(ids_a.size() + (self ? 0 : ids_b.size()));
  for (Index i : ids_a) entries.push_back({boxes_a[i].lo[0], 0, i});
  if (!self)
    for (Index j : ids_b) entries.push_back({boxes_b[j].lo[0], 1, j});
  std::sort(entries.begin(), entries.end(), [](const SweepEntry& p, const SweepEntry& q) {
    return std::tie(p.lo_x, p.set, p.index) < std::tie(q.lo_x, q.set, q.index);
  });
  std::vector<Index> active[2];
  for (const SweepEntry& entry : entries) {
    const int other = self ? 0 : 1 - entry.set;
    const std::vector<Box>& own_boxes = entry.set == 0 ? boxes_a : boxes_b;
    const std::vector<Box>& other_boxes = other == 0 ? boxes_a : boxes_b;
    const Box& box = own_boxes[entry.index];
    std::vector<Index>& candidates = active[other];
    for (std::size_t k = 0; k < candidates.size();) {
      const Box& previous = other_boxes[candidates[k]];
      if (entry.lo_x - previous.hi[0] > d) {
        candidates[k] = candidates.back();
        candidates.pop_back();
        continue;
      }
      if (!separated(box, previous, d)) {
        if (entry.set == 0 && !self) {
          emit(entry.index, candidates[k]);
        } else if (self) {
          emit(std::min(entry.index, candidates[k]), std::max(entry.index, candidates[k]));
        } else {
          emit(candidates[k], entry.index);
        }
      }
      ++k;
    }
    active[entry.set].push_back(entry.index);
  }
}

void check_positions(const Scene& scene, const std::vector<Vec3>& x, const char* what) {
  if (x.size() != scene.vertex_count()) {
    throw UsageError(std::string("exhaustive candidates: ") + what + " has " + std::to_string(x.size()) +
                     " positions, the scene has " + std::to_string(scene.vertex_count()) + " vertices");
  }
}

bool shares_vertex(const Edge& a, const Edge& b) {
  return a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1];
}

}  // namespace

void complete_ccd_candidates(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                             double thickness, std::vector<VertexFaceCandidate>& vf,
                             std::vector<EdgeEdgeCandidate>& ee) {
  check_positions(scene, x_t0, "x_t0");
  check_positions(scene, x_t1, "x_t1");
  if (!(thickness >= 0)) throw UsageError("exhaustive candidates: thickness must be >= 0");
  vf.clear();
  ee.clear();
  const auto& triangles = scene.triangles();
  const auto& edges = scene.edges();

  std::vector<Box> vertex_boxes(scene.vertex_count(), empty_box());
  std::vector<unsigned char> used(scene.vertex_count(), 0);
  for (const Triangle& t : triangles)
    for (Index v : t) used[v] = 1;
  std::vector<Index> vertices;
  for (Index v = 0; v < scene.vertex_count(); ++v) {
    extend(vertex_boxes[v], x_t0[v]);
    extend(vertex_boxes[v], x_t1[v]);
    if (used[v]) vertices.push_back(v);
  }
  std::vector<Box> face_boxes(triangles.size(), empty_box());
  std::vector<Index> faces(triangles.size());
  for (Index f = 0; f < triangles.size(); ++f) {
    for (Index v : triangles[f]) {
      extend(face_boxes[f], x_t0[v]);
      extend(face_boxes[f], x_t1[v]);
    }
    faces[f] = f;
  }
  sweep(vertex_boxes, vertices, face_boxes, faces, false, thickness, [&](Index v, Index f) {
    const Triangle& t = triangles[f];
    if (v != t[0] && v != t[1] && v != t[2]) vf.push_back({v, f});
  });

  std::vector<Box> edge_boxes(edges.size(), empty_box());
  std::vector<Index> edge_ids(edges.size());
  for (Index e = 0; e < edges.size(); ++e) {
    for (Index v : edges[e]) {
      extend(edge_boxes[e], x_t0[v]);
      extend(edge_boxes[e], x_t1[v]);
    }
    edge_ids[e] = e;
  }
  sweep(edge_boxes, edge_ids, edge_boxes, edge_ids, true, thickness, [&](Index a, Index b) {
    if (!shares_vertex(edges[a], edges[b])) ee.push_back({a, b});
  });

  std::sort(vf.begin(), vf.end());
  std::sort(ee.begin(), ee.end());
}

std::vector<TrianglePair> complete_triangle_candidates(const Scene& scene, const std::vector<Vec3>& x) {
  check_positions(scene, x, "x");
  const auto& triangles = scene.triangles();
  std::vector<Box> boxes(triangles.size(), empty_box());
  std::vector<Index> ids(triangles.size());
  for (Index f = 0; f < triangles.size(); ++f) {
    for (Index v : triangles[f]) extend(boxes[f], x[v]);
    ids[f] = f;
  }
  std::vector<TrianglePair> pairs;
  sweep(boxes, ids, boxes, ids, true, 0.0, [&](Index a, Index b) { pairs.push_back({a, b}); });
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace snag::validate
