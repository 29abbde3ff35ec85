// Exact triangle–triangle intersection against CGAL's self_intersections, pair
// for pair, on reference meshes, and on hand-built shared-feature cases.
#include "validate/exact_triangle_intersection.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace snag::validate {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Face = Mesh::Face_index;

struct FaceData {
  std::array<Vec3, 3> corners;
  std::array<Index, 3> ids;
};

Mesh read_mesh(const std::string& relative_path) {
  const std::string path = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/" + relative_path;
  std::ifstream in(path, std::ios::binary);
  Mesh mesh;
  EXPECT_TRUE(in && CGAL::IO::read_PLY(in, mesh)) << path;
  return mesh;
}

void check_against_self_intersections(const Mesh& mesh, const std::string& name) {
  ASSERT_GT(mesh.number_of_faces(), 0u);

  std::vector<std::pair<Face, Face>> cgal_pairs;
  CGAL::Polygon_mesh_processing::self_intersections(mesh, std::back_inserter(cgal_pairs));
  std::set<std::pair<std::size_t, std::size_t>> expected;
  for (auto [f, g] : cgal_pairs) {
    std::size_t i = f, j = g;
    expected.insert({std::min(i, j), std::max(i, j)});
  }

  std::vector<FaceData> faces;
  std::vector<std::array<double, 6>> boxes;
  for (Face f : mesh.faces()) {
    FaceData data;
    int k = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      const auto& p = mesh.point(v);
      data.corners[k] = {p.x(), p.y(), p.z()};
      data.ids[k] = static_cast<Index>(v);
      ++k;
    }
    ASSERT_EQ(k, 3);
    std::array<double, 6> box;
    for (int axis = 0; axis < 3; ++axis) {
      box[axis] = std::min({data.corners[0][axis], data.corners[1][axis], data.corners[2][axis]});
      box[axis + 3] = std::max({data.corners[0][axis], data.corners[1][axis], data.corners[2][axis]});
    }
    faces.push_back(data);
    boxes.push_back(box);
  }

  std::set<std::pair<std::size_t, std::size_t>> found;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    if (exact_triangle_is_degenerate(faces[i].corners)) {
      found.insert({i, i});
      continue;
    }
    for (std::size_t j = i + 1; j < faces.size(); ++j) {
      const auto& a = boxes[i];
      const auto& b = boxes[j];
      bool overlap = true;
      for (int axis = 0; axis < 3; ++axis)
        overlap = overlap && a[axis] <= b[axis + 3] && b[axis] <= a[axis + 3];
      if (!overlap || exact_triangle_is_degenerate(faces[j].corners)) continue;
      if (exact_triangles_intersect(faces[i].corners, faces[i].ids, faces[j].corners, faces[j].ids))
        found.insert({i, j});
    }
  }
  std::cout << name << ": " << faces.size() << " faces, " << expected.size()
            << " intersecting pairs from CGAL, " << found.size() << " found\n";
  EXPECT_EQ(found, expected);
}

void check_against_self_intersections(const std::string& relative_path) {
  check_against_self_intersections(read_mesh(relative_path), relative_path);
}

TEST(ExactTriangleIntersection, MatchesSelfIntersectionsOnBunny) { check_against_self_intersections("bunny.ply"); }

TEST(ExactTriangleIntersection, MatchesSelfIntersectionsOnIntersectingCubes) {
  check_against_self_intersections("two-cubes-intersecting.ply");
}

TEST(ExactTriangleIntersection, MatchesSelfIntersectionsOnThickCloth) {
  check_against_self_intersections("thick-cloth/t0.ply");
}

TEST(ExactTriangleIntersection, MatchesSelfIntersectionsOnFoldedCloth) {
  // Vertices of the cloth moved onto other vertices' positions (so neighbours
  // fold over shared edges and vertices, often coplanar) or thrown off
  // through the cloth.
  const Mesh original = read_mesh("thick-cloth/t0.ply");
  ASSERT_GT(original.number_of_vertices(), 0u);  // a mesh that could not be read fails here, not in the draws below
  std::mt19937 rng(2024);
  std::uniform_int_distribution<std::size_t> vertex(0, original.number_of_vertices() - 1);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int trial = 0; trial < 6; ++trial) {
    Mesh mesh = original;
    for (int k = 0; k < 12; ++k) {
      const auto moved = Mesh::Vertex_index(static_cast<Mesh::size_type>(vertex(rng)));
      const auto target = mesh.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(vertex(rng))));
      if (trial % 2 == 0)
        mesh.point(moved) = target;
      else
        mesh.point(moved) = Kernel::Point_3(target.x() + unit(rng), target.y() + unit(rng), target.z() + unit(rng));
    }
    check_against_self_intersections(mesh, "folded cloth " + std::to_string(trial));
  }
}

TEST(ExactTriangleIntersection, IgnoresSharedEdgeUnlessFacesFoldOntoEachOther) {
  const Vec3 u{0, 0, 0}, v{1, 0, 0}, w{0, 1, 0};
  // Flat neighbours on opposite sides of the shared edge: no intersection.
  EXPECT_FALSE(exact_triangles_intersect({u, v, w}, {0, 1, 2}, {v, u, Vec3{0.5, -1, 0}}, {1, 0, 3}));
  // Bent neighbours: no intersection.
  EXPECT_FALSE(exact_triangles_intersect({u, v, w}, {0, 1, 2}, {v, u, Vec3{0.5, 0.5, 1}}, {1, 0, 3}));
  // Folded flat onto the same side: they overlap.
  EXPECT_TRUE(exact_triangles_intersect({u, v, w}, {0, 1, 2}, {v, u, Vec3{0.5, 0.25, 0}}, {1, 0, 3}));
  // The fourth corner on the shared edge's line: not an overlap by CGAL's rule.
  EXPECT_FALSE(exact_triangles_intersect({u, v, w}, {0, 1, 2}, {v, u, Vec3{2, 0, 0}}, {1, 0, 3}));
}

TEST(ExactTriangleIntersection, IgnoresSharedVertexUnlessOppositeEdgePierces) {
  const Vec3 o{0, 0, 0};
  const std::array<Vec3, 3> a{o, Vec3{1, 0, 0}, Vec3{0, 1, 0}};
  // A fan neighbour touching only at the shared vertex.
  EXPECT_FALSE(exact_triangles_intersect(a, {0, 1, 2}, {o, Vec3{-1, 0, 0}, Vec3{0, -1, 0}}, {0, 3, 4}));
  // b's opposite edge passes through a's interior.
  EXPECT_TRUE(exact_triangles_intersect(a, {0, 1, 2}, {o, Vec3{0.25, 0.25, -1}, Vec3{0.25, 0.25, 1}}, {0, 3, 4}));
  // The same geometry without a shared id counts the common corner.
  EXPECT_TRUE(exact_triangles_intersect(a, {0, 1, 2}, {o, Vec3{-1, 0, 0}, Vec3{0, -1, 0}}, {5, 3, 4}));
}

TEST(ExactTriangleIntersection, DecidesDisjointAndCrossingTriangles) {
  const std::array<Vec3, 3> a{Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}};
  EXPECT_TRUE(exact_triangles_intersect(a, {0, 1, 2}, {Vec3{0.2, 0.2, -1}, Vec3{0.2, 0.2, 1}, Vec3{2, 2, 0}}, {3, 4, 5}));
  EXPECT_FALSE(exact_triangles_intersect(a, {0, 1, 2}, {Vec3{0, 0, 0x1p-60}, Vec3{1, 0, 0x1p-60}, Vec3{0, 1, 0x1p-60}}, {3, 4, 5}));
  EXPECT_TRUE(exact_triangle_is_degenerate({Vec3{0, 0, 0}, Vec3{1, 1, 1}, Vec3{3, 3, 3}}));
  EXPECT_FALSE(exact_triangle_is_degenerate(a));
}

}  // namespace
}  // namespace snag::validate
