// Hand-made configurations of triangles_intersect: each kind of contact, with
// and without shared vertex ids, exact touching and just-missing variants.
// Every case is also checked in swapped order and under vertex rotations, and
// the exact-sign filter in front of the test (triangles_separated_in_projection)
// never rejects an intersecting pair.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "libcd/narrow_phase/triangle_triangle.hpp"

namespace snag {
namespace {

struct Tri {
  Vec3 p[3];
  std::uint32_t id[3];
};

Tri rotated(const Tri& t, int r) {
  Tri out;
  for (int i = 0; i < 3; ++i) {
    out.p[i] = t.p[(i + r) % 3];
    out.id[i] = t.id[(i + r) % 3];
  }
  return out;
}

Tri reversed(const Tri& t) { return {{t.p[0], t.p[2], t.p[1]}, {t.id[0], t.id[2], t.id[1]}}; }

/// The answer for (a, b), after checking that swapping the triangles, rotating
/// and reversing their vertex orders all give the same answer and adjacency.
bool intersects(const Tri& a, const Tri& b, TriangleAdjacency* adjacency = nullptr) {
  TriangleAdjacency first_adjacency;
  const bool first = triangles_intersect(a.p, a.id, b.p, b.id, nullptr, &first_adjacency);
  for (int ra = 0; ra < 3; ++ra)
    for (int rb = 0; rb < 3; ++rb)
      for (int flip = 0; flip < 4; ++flip) {
        Tri a2 = rotated(a, ra), b2 = rotated(b, rb);
        if (flip & 1) a2 = reversed(a2);
        if (flip & 2) b2 = reversed(b2);
        TriangleAdjacency adj_ab, adj_ba;
        EXPECT_EQ(triangles_intersect(a2.p, a2.id, b2.p, b2.id, nullptr, &adj_ab), first);
        EXPECT_EQ(triangles_intersect(b2.p, b2.id, a2.p, a2.id, nullptr, &adj_ba), first);
        // The filter in front of the test may only reject pairs the test rejects.
        if (first) {
          EXPECT_FALSE(triangles_separated_in_projection(a2.p, a2.id, b2.p, b2.id));
          EXPECT_FALSE(triangles_separated_in_projection(b2.p, b2.id, a2.p, a2.id));
        }
        EXPECT_EQ(adj_ab, first_adjacency);
        EXPECT_EQ(adj_ba, first_adjacency);
      }
  if (adjacency) *adjacency = first_adjacency;
  return first;
}

// The reference triangle: the right triangle in z = 0 with legs of length 2.
const Tri kBase{{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}, {0, 1, 2}};
const double kTiny = std::ldexp(1.0, -200);  // a gap next to zero
const double kGap = std::ldexp(1.0, -40);    // a gap next to 1 or 2

Tri unrelated(Vec3 p0, Vec3 p1, Vec3 p2) { return {{p0, p1, p2}, {10, 11, 12}}; }
Tri sharing(std::uint32_t id0, Vec3 p0, std::uint32_t id1, Vec3 p1, std::uint32_t id2, Vec3 p2) {
  return {{p0, p1, p2}, {id0, id1, id2}};
}

TEST(TrianglesIntersect, RejectsDisjointTriangles) {
  TriangleAdjacency adjacency;
  EXPECT_FALSE(intersects(kBase, unrelated({5, 5, 5}, {6, 5, 5}, {5, 6, 5}), &adjacency));
  EXPECT_EQ(adjacency, TriangleAdjacency::none);
  // Straddles the plane but passes beside the triangle.
  EXPECT_FALSE(intersects(kBase, unrelated({1.5, 1.5, -1}, {1.5, 1.5, 1}, {3, 3, 0})));
}

TEST(TrianglesIntersect, FindsCrossingTriangles) {
  EXPECT_TRUE(intersects(kBase, unrelated({0.5, 0.5, -1}, {0.5, 0.5, 1}, {-1, -1, 0})));
  // Each pierces the other through an edge.
  EXPECT_TRUE(intersects(kBase, unrelated({1, -1, -1}, {1, -1, 1}, {1, 1, 0})));
}

TEST(TrianglesIntersect, FindsVertexTouchingFaceAndMissesItByTinyGap) {
  EXPECT_TRUE(intersects(kBase, unrelated({0.5, 0.5, 0}, {1, 1, 1}, {0, 1, 1})));
  EXPECT_FALSE(intersects(kBase, unrelated({0.5, 0.5, kTiny}, {1, 1, 1}, {0, 1, 1})));
  // Vertex on an edge, and vertex on a vertex (different ids).
  EXPECT_TRUE(intersects(kBase, unrelated({1, 0, 0}, {1, -1, 1}, {1, -1, -1})));
  EXPECT_TRUE(intersects(kBase, unrelated({2, 0, 0}, {3, 0, 1}, {3, 1, 1})));
  EXPECT_FALSE(intersects(kBase, unrelated({2 + kGap, 0, 0}, {3, 0, 1}, {3, 1, 1})));
}

TEST(TrianglesIntersect, FindsEdgeTouchingEdge) {
  // T2 lies in the plane x = y and meets the hypotenuse x + y = 2 at (1, 1, 0) only.
  EXPECT_TRUE(intersects(kBase, unrelated({2, 2, -1}, {0, 0, 1}, {3, 3, 0})));
  const Vec3 shift{kGap, kGap, 0};
  EXPECT_FALSE(intersects(kBase, unrelated(Vec3{2, 2, -1} + shift, Vec3{0, 0, 1} + shift, Vec3{3, 3, 0} + shift)));
}

TEST(TrianglesIntersect, FindsEdgeLyingOnFace) {
  EXPECT_TRUE(intersects(kBase, unrelated({0.2, 0.2, 0}, {1, 0.5, 0}, {0.5, 0.5, 1})));
  // An edge in the plane, outside the triangle.
  EXPECT_FALSE(intersects(kBase, unrelated({3, 3, 0}, {4, 3, 0}, {3, 3, 1})));
  // An edge in the plane that crosses the triangle without a vertex inside it.
  EXPECT_TRUE(intersects(kBase, unrelated({-1, 0.5, 0}, {3, 0.5, 0}, {1, 0.5, 1})));
}

TEST(TrianglesIntersect, FindsCoplanarOverlapAndContainment) {
  EXPECT_TRUE(intersects(kBase, unrelated({0.5, 0.5, 0}, {3, 0.5, 0}, {0.5, 3, 0})));
  EXPECT_TRUE(intersects(kBase, unrelated({0.2, 0.2, 0}, {0.4, 0.2, 0}, {0.2, 0.4, 0})));
  EXPECT_TRUE(intersects(kBase, unrelated({-1, -1, 0}, {5, -1, 0}, {-1, 5, 0})));
  // Star of David: edges cross, no vertex of either inside the other.
  EXPECT_TRUE(intersects(kBase, unrelated({-0.5, 1, 0}, {1, -0.5, 0}, {1.5, 1.5, 0})));
}

TEST(TrianglesIntersect, HandlesCoplanarTouchingAndDisjoint) {
  EXPECT_FALSE(intersects(kBase, unrelated({3, 3, 0}, {4, 3, 0}, {3, 4, 0})));
  // Vertex on the hypotenuse; the same, a tiny gap away.
  EXPECT_TRUE(intersects(kBase, unrelated({1, 1, 0}, {2, 2, 0}, {3, 0.5, 0})));
  EXPECT_FALSE(intersects(kBase, unrelated({1 + kGap, 1, 0}, {2, 2, 0}, {3, 0.5, 0})));
  // The same geometric edge under different ids counts as a contact.
  EXPECT_TRUE(intersects(kBase, unrelated({2, 0, 0}, {0, 2, 0}, {2, 2, 0})));
  // Collinear edges that overlap, and ones that only continue each other.
  EXPECT_TRUE(intersects(kBase, unrelated({1, 0, 0}, {3, 0, 0}, {2, -1, 0})));
  EXPECT_TRUE(intersects(kBase, unrelated({2, 0, 0}, {3, 0, 0}, {2.5, -1, 0})));
  EXPECT_FALSE(intersects(kBase, unrelated({2 + kGap, 0, 0}, {3, 0, 0}, {2.5, -1, 0})));
}

TEST(TrianglesIntersect, SharedVertexCountsOnlyOverlapBeyondIt) {
  TriangleAdjacency adjacency;
  EXPECT_FALSE(intersects(kBase, sharing(0, {0, 0, 0}, 13, {-1, 0, 1}, 14, {0, -1, 1}), &adjacency));
  EXPECT_EQ(adjacency, TriangleAdjacency::shared_vertex);
  EXPECT_TRUE(intersects(kBase, sharing(0, {0, 0, 0}, 13, {1, 1, 1}, 14, {1, 1, -1})));
  // Coplanar: overlapping wedge, and touching only at the shared vertex.
  EXPECT_TRUE(intersects(kBase, sharing(0, {0, 0, 0}, 13, {3, 1, 0}, 14, {1, 3, 0})));
  EXPECT_FALSE(intersects(kBase, sharing(0, {0, 0, 0}, 13, {-1, 0, 0}, 14, {0, -1, 0})));
  // Coplanar, along a common edge direction from the shared vertex.
  EXPECT_TRUE(intersects(kBase, sharing(0, {0, 0, 0}, 13, {1, 0, 0}, 14, {1, -1, 0})));
  // Touching the face only along a line from the shared vertex in the plane
  // of the face (an edge lying in the plane, outside the triangle).
  EXPECT_FALSE(intersects(kBase, sharing(0, {0, 0, 0}, 13, {-1, -1, 0}, 14, {-1, -1, 1})));
}

TEST(TrianglesIntersect, SharedEdgeCountsOnlyCoplanarOverlap) {
  TriangleAdjacency adjacency;
  EXPECT_FALSE(intersects(kBase, sharing(1, {2, 0, 0}, 0, {0, 0, 0}, 3, {1, 1, 1}), &adjacency));
  EXPECT_EQ(adjacency, TriangleAdjacency::shared_edge);
  // Flat, on the other side of the shared edge: a regular mesh neighbour.
  EXPECT_FALSE(intersects(kBase, sharing(1, {2, 0, 0}, 0, {0, 0, 0}, 3, {1, -1, 0})));
  // Folded flat onto the base triangle.
  EXPECT_TRUE(intersects(kBase, sharing(1, {2, 0, 0}, 0, {0, 0, 0}, 3, {1, 0.5, 0})));
  EXPECT_TRUE(intersects(kBase, sharing(1, {2, 0, 0}, 0, {0, 0, 0}, 3, {5, 7, 0})));
  // Folded almost flat: not coplanar, so no overlap beyond the edge.
  EXPECT_FALSE(intersects(kBase, sharing(1, {2, 0, 0}, 0, {0, 0, 0}, 3, {1, 0.5, kTiny})));
}

TEST(TrianglesIntersect, ReportsDegenerateTrianglesApart) {
  TriangleAdjacency adjacency;
  // Collinear vertices crossing the base triangle's interior: not tested.
  EXPECT_FALSE(intersects(kBase, unrelated({0.5, 0.5, -1}, {0.5, 0.5, 0}, {0.5, 0.5, 1}), &adjacency));
  EXPECT_EQ(adjacency, TriangleAdjacency::degenerate);
  EXPECT_TRUE(is_degenerate_triangle({0.5, 0.5, -1}, {0.5, 0.5, 0}, {0.5, 0.5, 1}));
  EXPECT_TRUE(is_degenerate_triangle({1, 2, 3}, {1, 2, 3}, {4, 5, 6}));
  EXPECT_FALSE(is_degenerate_triangle({0, 0, 0}, {1, 0, 0}, {1, kTiny, 0}));
  EXPECT_TRUE(is_degenerate_triangle({0, 0, 0}, {0.5, 0.25, 0.125}, {1, 0.5, 0.25}));
}

TEST(TrianglesIntersect, TreatsDuplicatedFacesAsIntersecting) {
  TriangleAdjacency adjacency;
  EXPECT_TRUE(intersects(kBase, sharing(2, {0, 2, 0}, 0, {0, 0, 0}, 1, {2, 0, 0}), &adjacency));
  EXPECT_EQ(adjacency, TriangleAdjacency::same_vertices);
}

}  // namespace
}  // namespace snag
