// Tests for culling/: representative triangles assign every vertex and edge
// once, and enumerating all triangle pairs yields every feature pair once.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "libcd/culling/representative_triangles.hpp"

namespace snag {
namespace {

// A 3×3-vertex grid of 8 triangles plus a separate triangle.
Scene small_scene(std::vector<Vec3>& x) {
  std::vector<Triangle> tris;
  for (Index j = 0; j < 2; ++j)
    for (Index i = 0; i < 2; ++i) {
      const Index v = j * 3 + i;
      tris.push_back({v, v + 1, v + 4});
      tris.push_back({v, v + 4, v + 3});
    }
  tris.push_back({9, 10, 11});
  x.clear();
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) x.push_back({double(i), double(j), 0});
  x.push_back({0, 0, 1});
  x.push_back({1, 0, 1});
  x.push_back({0, 1, 1});
  return Scene({make_object("grid", 12, tris)});
}

TEST(RepresentativeTriangles, EachVertexAndEdgeHasExactlyOneRepresentative) {
  std::vector<Vec3> x;
  const Scene scene = small_scene(x);
  const RepresentativeTriangles reps = assign_representative_triangles(scene);
  std::vector<int> vertex_reps(scene.vertex_count(), 0), edge_reps(scene.edge_count(), 0);
  for (std::size_t f = 0; f < scene.triangle_count(); ++f)
    for (int i = 0; i < 3; ++i) {
      if (reps.masks[f] & (1u << i)) ++vertex_reps[scene.triangles()[f][i]];
      if (reps.masks[f] & (1u << (3 + i))) ++edge_reps[reps.edge_ids[f][i]];
      const Edge& e = scene.edges()[reps.edge_ids[f][i]];
      const Index a = scene.triangles()[f][i], b = scene.triangles()[f][(i + 1) % 3];
      EXPECT_EQ(e, (Edge{std::min(a, b), std::max(a, b)}));
    }
  for (int n : vertex_reps) EXPECT_EQ(n, 1);
  for (int n : edge_reps) EXPECT_EQ(n, 1);
}

// The rule itself, by brute force: each vertex and edge is represented by its
// incident triangle of smallest id, on a grid whose triangles come in a
// scrambled order (so that owners are not the first triangles of a row)
// with a few sharing an edge three ways and a vertex in no triangle.
TEST(RepresentativeTriangles, EachFeatureBelongsToItsIncidentTriangleOfSmallestId) {
  constexpr Index kSide = 40;
  std::vector<Triangle> tris;
  for (Index j = 0; j + 1 < kSide; ++j)
    for (Index i = 0; i + 1 < kSide; ++i) {
      const Index v = j * kSide + i;
      tris.push_back({v, v + 1, v + kSide + 1});
      tris.push_back({v, v + kSide + 1, v + kSide});
    }
  const Index extra = kSide * kSide;  // fins on diagonals of the first row: three triangles share each
  for (Index i = 0; i + 1 < kSide; i += 3) tris.push_back({i + kSide + 1, i, extra + i / 3});
  const Index vertices = extra + kSide / 3 + 2;  // the last vertex is in no triangle
  for (std::size_t k = 0; k < tris.size(); ++k) std::swap(tris[k], tris[(k * 7919) % tris.size()]);
  for (std::size_t k = 0; k < tris.size(); k += 5) std::rotate(tris[k].begin(), tris[k].begin() + 1, tris[k].end());
  const Scene scene({make_object("scrambled", vertices, tris)});
  const RepresentativeTriangles reps = assign_representative_triangles(scene);

  const auto& edges = scene.edges();
  constexpr Index kNone = ~Index{0};
  std::vector<Index> vertex_owner(scene.vertex_count(), kNone), edge_owner(edges.size(), kNone);
  for (Index f = static_cast<Index>(tris.size()); f-- > 0;) {  // descending: the smallest id writes last
    for (int i = 0; i < 3; ++i) {
      const Index a = tris[f][i], b = tris[f][(i + 1) % 3];
      vertex_owner[a] = f;
      for (Index e = 0; e < edges.size(); ++e)
        if (edges[e] == Edge{std::min(a, b), std::max(a, b)}) edge_owner[e] = f;
    }
  }
  ASSERT_EQ(reps.masks.size(), tris.size());
  for (Index f = 0; f < tris.size(); ++f)
    for (int i = 0; i < 3; ++i) {
      const Index e = reps.edge_ids[f][i];
      ASSERT_LT(e, edges.size());
      const Index a = tris[f][i], b = tris[f][(i + 1) % 3];
      EXPECT_EQ(edges[e], (Edge{std::min(a, b), std::max(a, b)}));
      EXPECT_EQ((reps.masks[f] >> i) & 1u, vertex_owner[a] == f ? 1u : 0u) << "triangle " << f << " corner " << i;
      EXPECT_EQ((reps.masks[f] >> (3 + i)) & 1u, edge_owner[e] == f ? 1u : 0u) << "triangle " << f << " edge " << i;
    }
  EXPECT_EQ(vertex_owner.back(), kNone);
}

TEST(RepresentativeTriangles, AllTrianglePairsGiveEveryFeaturePairOnce) {
  std::vector<Vec3> x;
  const Scene scene = small_scene(x);
  const RepresentativeTriangles reps = assign_representative_triangles(scene);
  const PrimitiveBounds bounds = compute_primitive_bounds(scene, x, x, 100.0);  // nothing culled
  std::vector<TrianglePair> all;
  for (Index a = 0; a < scene.triangle_count(); ++a)
    for (Index b = a + 1; b < scene.triangle_count(); ++b) all.push_back({a, b});
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  FeatureCounts counts;
  representative_feature_pairs(scene, reps, bounds, all, vf, ee, counts);
  std::set<std::pair<Index, Index>> expected_vf, expected_ee;
  for (Index v = 0; v < scene.vertex_count(); ++v)
    for (Index f = 0; f < scene.triangle_count(); ++f) {
      const Triangle& t = scene.triangles()[f];
      if (t[0] != v && t[1] != v && t[2] != v) expected_vf.insert({v, f});
    }
  const auto& edges = scene.edges();
  for (Index a = 0; a < edges.size(); ++a)
    for (Index b = a + 1; b < edges.size(); ++b)
      if (edges[a][0] != edges[b][0] && edges[a][0] != edges[b][1] && edges[a][1] != edges[b][0] &&
          edges[a][1] != edges[b][1])
        expected_ee.insert({a, b});
  ASSERT_EQ(vf.size(), expected_vf.size());
  ASSERT_EQ(ee.size(), expected_ee.size());
  EXPECT_EQ(counts.vf_before, vf.size());  // produced once each: no duplicates before sorting
  EXPECT_EQ(counts.ee_before, ee.size());
  for (const auto& c : vf) EXPECT_TRUE(expected_vf.count({c.vertex, c.face}));
  for (const auto& c : ee) EXPECT_TRUE(expected_ee.count({c.edge_a, c.edge_b}));
}

TEST(FeatureCulling, DropsPairsWhoseSweptBoundsAreApart) {
  std::vector<Vec3> x;
  const Scene scene = small_scene(x);
  const RepresentativeTriangles reps = assign_representative_triangles(scene);
  const PrimitiveBounds bounds = compute_primitive_bounds(scene, x, x, 0.0);
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  FeatureCounts counts;
  // Triangle 8 (z = 1 plane) against triangle 7 (far corner of the z = 0 grid).
  representative_feature_pairs(scene, reps, bounds, {{7, 8}}, vf, ee, counts);
  EXPECT_GT(counts.vf_before + counts.ee_before, 0u);
  EXPECT_TRUE(vf.empty());
  EXPECT_TRUE(ee.empty());
}

}  // namespace
}  // namespace snag
