// Tests for scene/: an object's edges are its triangles' sides, sorted and
// unique, as a sort of all the sides gives them.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "libcd/scene/object.hpp"

namespace snag {
namespace {

// The sides of `triangles` as (low end, high end), sorted, repeats kept.
std::vector<Edge> sorted_sides(const std::vector<Triangle>& triangles) {
  std::vector<Edge> sides;
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) sides.push_back({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  std::sort(sides.begin(), sides.end());
  return sides;
}

TEST(ObjectEdges, AreTheSortedUniqueSidesOfItsTriangles) {
  // A random soup (shared, repeated and non-manifold sides, unused vertices,
  // corners in any order) over 500 vertices of which the last are unused.
  std::mt19937 random(7);
  std::uniform_int_distribution<Index> corner(0, 400);
  std::vector<Triangle> soup;
  while (soup.size() < 3000) {
    const Triangle t{corner(random), corner(random), corner(random)};
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) soup.push_back(t);
  }
  soup.push_back(soup[10]);  // a repeated triangle: each of its sides three or more times
  std::vector<Edge> expected = sorted_sides(soup);
  expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
  const Object object = make_object("soup", 500, soup);
  EXPECT_EQ(object.edges, expected);
  EXPECT_EQ(object.triangles, soup);

  // The counts of boundary (one triangle) and non-manifold (three or more) edges.
  const std::vector<Edge> sides = sorted_sides(soup);
  std::size_t boundary = 0, non_manifold = 0;
  for (const Edge& e : expected) {
    const auto n = std::count(sides.begin(), sides.end(), e);
    boundary += n == 1;
    non_manifold += n >= 3;
  }
  const EdgeCounts counts = count_edge_kinds(object);
  EXPECT_EQ(counts.boundary, boundary);
  EXPECT_EQ(counts.non_manifold, non_manifold);
  EXPECT_GT(non_manifold, 0u);
}

TEST(ObjectEdges, OfNoTrianglesAreNone) {
  EXPECT_TRUE(make_object("empty", 3, {}).edges.empty());
  EXPECT_TRUE(make_object("nothing", 0, {}).edges.empty());
}

}  // namespace
}  // namespace snag
