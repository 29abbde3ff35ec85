#include "libcd/culling/representative_triangles.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cassert>
#include <limits>

#include "libcd/narrow_phase/ccd_separating_direction.hpp"

namespace snag {

RepresentativeTriangles assign_representative_triangles(const Scene& scene) {
  const auto& tris = scene.triangles();
  const auto& edges = scene.edges();
  constexpr Index kNone = std::numeric_limits<Index>::max();
  RepresentativeTriangles reps;
  reps.masks.assign(tris.size(), 0);
  reps.edge_ids.resize(tris.size());
  // The edges are sorted by (low end, high end): those of low end v are
  // edges [first_edge[v], first_edge[v + 1]), a few, so that each of a
  // triangle's edges is found among its low end's (on all threads) rather
  // than searched for among all (a large mesh has millions).
  std::vector<std::size_t> first_edge(scene.vertex_count() + 1, 0);
  for (const Edge& e : edges) ++first_edge[e[0] + 1];
  for (std::size_t v = 0; v < scene.vertex_count(); ++v) first_edge[v + 1] += first_edge[v];
  auto find_edges = [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t f = range.begin(); f < range.end(); ++f) {
      for (int i = 0; i < 3; ++i) {
        const Index a = tris[f][i], b = tris[f][(i + 1) % 3];
        const Edge key{std::min(a, b), std::max(a, b)};
        const auto from = edges.begin() + static_cast<std::ptrdiff_t>(first_edge[key[0]]);
        const auto to = edges.begin() + static_cast<std::ptrdiff_t>(first_edge[key[0] + 1]);
        const auto it = std::lower_bound(from, to, key);
        assert(it != to && *it == key);
        reps.edge_ids[f][i] = static_cast<Index>(it - edges.begin());
      }
    }
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tris.size(), 4096), find_edges);
  std::vector<Index> vertex_owner(scene.vertex_count(), kNone), edge_owner(edges.size(), kNone);
  for (std::size_t f = 0; f < tris.size(); ++f) {  // ascending: the first incident triangle wins
    for (int i = 0; i < 3; ++i) {
      const Index a = tris[f][i], e = reps.edge_ids[f][i];
      if (vertex_owner[a] == kNone) {
        vertex_owner[a] = static_cast<Index>(f);
        reps.masks[f] |= std::uint8_t(1u << i);
      }
      if (edge_owner[e] == kNone) {
        edge_owner[e] = static_cast<Index>(f);
        reps.masks[f] |= std::uint8_t(1u << (3 + i));
      }
    }
  }
  return reps;
}

namespace {

bool is_corner(const Triangle& t, Index v) { return t[0] == v || t[1] == v || t[2] == v; }

/// Whether `separation` proves triangles a and b apart over its step.
bool triangle_pair_separated(const Scene& scene, const TriangleSeparation& separation, Index a, Index b) {
  const Triangle& ta = scene.triangles()[a];
  const Triangle& tb = scene.triangles()[b];
  const auto corner = [&](int c, int i) {
    return (c % 2 == 0 ? separation.x_t0 : separation.x_t1)[(c < 2 ? ta : tb)[i]];
  };
  return triangles_separated_by(corner, separation.thickness);
}

}  // namespace

void representative_feature_pairs(const Scene& scene, const RepresentativeTriangles& reps,
                                  const PrimitiveBounds& bounds, const std::vector<TrianglePair>& triangle_pairs,
                                  std::vector<VertexFaceCandidate>& vf, std::vector<EdgeEdgeCandidate>& ee,
                                  FeatureCounts& counts, const TriangleSeparation* separation) {
  const auto& tris = scene.triangles();
  const auto& edges = scene.edges();
  // Fixed chunks, concatenated in order: deterministic for any thread count.
  constexpr std::size_t kChunk = 4096;
  const std::size_t chunks = (triangle_pairs.size() + kChunk - 1) / kChunk;
  struct ChunkOut {
    std::vector<VertexFaceCandidate> vf;
    std::vector<EdgeEdgeCandidate> ee;
    std::size_t separated = 0, vf_before = 0, ee_before = 0;
  };
  std::vector<ChunkOut> out(chunks);
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    ChunkOut& o = out[c];
    const std::size_t end = std::min(triangle_pairs.size(), (c + 1) * kChunk);
    for (std::size_t p = c * kChunk; p < end; ++p) {
      const Index side[2] = {triangle_pairs[p].a, triangle_pairs[p].b};
      if (separation != nullptr && triangle_pair_separated(scene, *separation, side[0], side[1])) {
        ++o.separated;
        continue;
      }
      for (int s = 0; s < 2; ++s) {
        const Index a = side[s], b = side[1 - s];
        for (int i = 0; i < 3; ++i) {
          if (!(reps.masks[a] & (1u << i))) continue;
          const Index v = tris[a][i];
          if (is_corner(tris[b], v)) continue;
          ++o.vf_before;
          if (dop_overlap(bounds.vertices[v], bounds.triangles[b])) o.vf.push_back({v, b});
        }
      }
      const Index a = side[0], b = side[1];
      for (int i = 0; i < 3; ++i) {
        if (!(reps.masks[a] & (1u << (3 + i)))) continue;
        const Index ea = reps.edge_ids[a][i];
        for (int j = 0; j < 3; ++j) {
          if (!(reps.masks[b] & (1u << (3 + j)))) continue;
          const Index eb = reps.edge_ids[b][j];
          const Edge& ga = edges[ea];
          const Edge& gb = edges[eb];
          if (ga[0] == gb[0] || ga[0] == gb[1] || ga[1] == gb[0] || ga[1] == gb[1]) continue;
          ++o.ee_before;
          if (dop_overlap(bounds.edges[ea], bounds.edges[eb])) o.ee.push_back({std::min(ea, eb), std::max(ea, eb)});
        }
      }
    }
  });
  vf.clear();
  ee.clear();
  counts = FeatureCounts{};
  for (const ChunkOut& o : out) {
    vf.insert(vf.end(), o.vf.begin(), o.vf.end());
    ee.insert(ee.end(), o.ee.begin(), o.ee.end());
    counts.separated += o.separated;
    counts.vf_before += o.vf_before;
    counts.ee_before += o.ee_before;
  }
  tbb::parallel_sort(vf.begin(), vf.end());
  tbb::parallel_sort(ee.begin(), ee.end());
  // Unique triangle pairs give unique feature pairs (see the header).
  assert(std::adjacent_find(vf.begin(), vf.end()) == vf.end());
  assert(std::adjacent_find(ee.begin(), ee.end()) == ee.end());
  counts.vf_after = vf.size();
  counts.ee_after = ee.size();
}

}  // namespace snag
