// Loop subdivision of a triangle mesh animated over several frames, for the
// GPU benchmark's scaling scene (a cloth refined to about 1.5 million
// triangles). One level splits each triangle into four; the new positions of
// every frame use the same weights, so the refined frames keep one topology.
//
// C. Loop, "Smooth Subdivision Surfaces Based on Triangles", MSc thesis,
// University of Utah, 1987; vertex weights beta = 3/(8n) for n > 3, 3/16 for
// n = 3 (J. Warren's simplification). Boundary and non-manifold edges use the
// cubic B-spline rules (edge midpoint; vertex 3/4 itself + 1/8 each boundary
// neighbour).
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag::bench {

/// One level of Loop subdivision.
///   triangles: [in,out] #F triangles, replaced by the 4 #F refined ones
///   frames: [in,out] each #V positions, replaced by the refined positions
///     (#V + #E each: old vertices first, then one per edge)
inline void loop_subdivide(std::vector<Triangle>& triangles, std::vector<std::vector<Vec3>>& frames) {
  const std::size_t vertex_count = frames.empty() ? 0 : frames[0].size();
  struct EdgeInfo {
    Index id;
    Index opposite[2];
    int faces;
  };
  std::unordered_map<std::uint64_t, EdgeInfo> edges;
  edges.reserve(triangles.size() * 2);
  auto key = [](Index a, Index b) { return a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a; };
  std::vector<std::uint64_t> edge_keys;  // by edge id
  for (const Triangle& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
      auto [it, inserted] = edges.try_emplace(key(a, b), EdgeInfo{Index(vertex_count + edge_keys.size()), {c, c}, 0});
      if (inserted) edge_keys.push_back(key(a, b));
      if (it->second.faces < 2) it->second.opposite[it->second.faces] = c;
      ++it->second.faces;
    }
  }
  // Vertex neighbourhoods: all neighbours, and boundary neighbours.
  std::vector<std::uint32_t> valence(vertex_count, 0), boundary_count(vertex_count, 0);
  std::vector<std::vector<Vec3>> neighbour_sum(frames.size(), std::vector<Vec3>(vertex_count, Vec3{0, 0, 0}));
  std::vector<std::vector<Vec3>> boundary_sum(frames.size(), std::vector<Vec3>(vertex_count, Vec3{0, 0, 0}));
  for (const std::uint64_t k : edge_keys) {
    const Index a = Index(k >> 32), b = Index(k & 0xffffffffu);
    const bool boundary = edges[k].faces != 2;
    ++valence[a];
    ++valence[b];
    if (boundary) {
      ++boundary_count[a];
      ++boundary_count[b];
    }
    for (std::size_t f = 0; f < frames.size(); ++f) {
      neighbour_sum[f][a] = neighbour_sum[f][a] + frames[f][b];
      neighbour_sum[f][b] = neighbour_sum[f][b] + frames[f][a];
      if (boundary) {
        boundary_sum[f][a] = boundary_sum[f][a] + frames[f][b];
        boundary_sum[f][b] = boundary_sum[f][b] + frames[f][a];
      }
    }
  }
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const std::vector<Vec3>& x = frames[f];
    std::vector<Vec3> refined(vertex_count + edge_keys.size());
    for (std::size_t v = 0; v < vertex_count; ++v) {
      if (boundary_count[v] == 2) {
        refined[v] = 0.75 * x[v] + 0.125 * boundary_sum[f][v];
      } else if (boundary_count[v] > 0 || valence[v] < 3) {
        refined[v] = x[v];  // a corner or non-manifold vertex stays put
      } else {
        const double n = valence[v];
        const double beta = valence[v] == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * n);
        refined[v] = (1 - n * beta) * x[v] + beta * neighbour_sum[f][v];
      }
    }
    for (std::size_t e = 0; e < edge_keys.size(); ++e) {
      const EdgeInfo& info = edges[edge_keys[e]];
      const Index a = Index(edge_keys[e] >> 32), b = Index(edge_keys[e] & 0xffffffffu);
      refined[vertex_count + e] =
          info.faces == 2 ? 0.375 * (x[a] + x[b]) + 0.125 * (x[info.opposite[0]] + x[info.opposite[1]])
                          : 0.5 * (x[a] + x[b]);
    }
    frames[f] = std::move(refined);
  }
  std::vector<Triangle> refined_triangles;
  refined_triangles.reserve(4 * triangles.size());
  for (const Triangle& t : triangles) {
    const Index m01 = edges[key(t[0], t[1])].id, m12 = edges[key(t[1], t[2])].id, m20 = edges[key(t[2], t[0])].id;
    refined_triangles.push_back({t[0], m01, m20});
    refined_triangles.push_back({t[1], m12, m01});
    refined_triangles.push_back({t[2], m20, m12});
    refined_triangles.push_back({m01, m12, m20});
  }
  triangles = std::move(refined_triangles);
}

}  // namespace snag::bench
