// The complete candidate sets of exhaustive verification, checked against the
// oracle of all pairs decided exactly: nothing that touches may be missing.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "validate/exact_ccd.hpp"
#include "validate/exact_triangle_intersection.hpp"
#include "validate/verify_candidates.hpp"
#include "validate/verify_exclusion.hpp"

namespace snag::validate {
namespace {

// Two small objects of random triangles in a unit cube, with random motion:
// close enough that many pairs collide, sparse enough that boxes prune some.
struct RandomScene {
  Scene scene;
  std::vector<Vec3> x_t0, x_t1;
};

RandomScene make_random_scene(unsigned seed, double motion) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coordinate(0.0, 1.0), step(-motion, motion);
  std::uniform_int_distribution<int> pick(0, 9);
  std::vector<Object> objects;
  RandomScene out;
  for (int o = 0; o < 2; ++o) {
    std::vector<Triangle> triangles;
    while (triangles.size() < 8) {
      Triangle t{Index(pick(rng)), Index(pick(rng)), Index(pick(rng))};
      if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) triangles.push_back(t);
    }
    objects.push_back(make_object("object" + std::to_string(o), 10, triangles));
    for (int v = 0; v < 10; ++v) {
      const Vec3 p{coordinate(rng), coordinate(rng), coordinate(rng)};
      out.x_t0.push_back(p);
      out.x_t1.push_back(p + Vec3{step(rng), step(rng), step(rng)});
    }
  }
  out.scene = Scene(std::move(objects));
  return out;
}

std::array<Vec3, 8> vf_points(const RandomScene& s, Index v, Index f) {
  const Triangle& t = s.scene.triangles()[f];
  return {s.x_t0[v], s.x_t0[t[0]], s.x_t0[t[1]], s.x_t0[t[2]], s.x_t1[v], s.x_t1[t[0]], s.x_t1[t[1]], s.x_t1[t[2]]};
}

std::array<Vec3, 8> ee_points(const RandomScene& s, Index a, Index b) {
  const Edge& ea = s.scene.edges()[a];
  const Edge& eb = s.scene.edges()[b];
  return {s.x_t0[ea[0]], s.x_t0[ea[1]], s.x_t0[eb[0]], s.x_t0[eb[1]],
          s.x_t1[ea[0]], s.x_t1[ea[1]], s.x_t1[eb[0]], s.x_t1[eb[1]]};
}

class CompleteCandidates : public ::testing::TestWithParam<unsigned> {};

TEST_P(CompleteCandidates, HoldEveryCollidingPairOfAllPairsAndNoneIsExcluded) {
  const RandomScene s = make_random_scene(GetParam(), 0.3);
  const double thickness = GetParam() % 2 == 0 ? 0.0 : 0.02;
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  complete_ccd_candidates(s.scene, s.x_t0, s.x_t1, thickness, vf, ee);
  ASSERT_TRUE(std::is_sorted(vf.begin(), vf.end()));
  ASSERT_TRUE(std::adjacent_find(vf.begin(), vf.end()) == vf.end());
  ASSERT_TRUE(std::is_sorted(ee.begin(), ee.end()));
  ASSERT_TRUE(std::adjacent_find(ee.begin(), ee.end()) == ee.end());

  std::size_t colliding = 0, pruned = 0;
  const auto& triangles = s.scene.triangles();
  for (Index v = 0; v < s.scene.vertex_count(); ++v) {
    const bool used = std::any_of(triangles.begin(), triangles.end(), [&](const Triangle& t) {
      return t[0] == v || t[1] == v || t[2] == v;
    });
    for (Index f = 0; f < triangles.size(); ++f) {
      const Triangle& t = triangles[f];
      const bool corner = v == t[0] || v == t[1] || v == t[2];
      const bool listed = std::binary_search(vf.begin(), vf.end(), VertexFaceCandidate{v, f});
      if (corner || !used) {
        EXPECT_FALSE(listed) << "vertex " << v << " face " << f;
        continue;
      }
      pruned += !listed;
      if (exact_vertex_face_ccd(vf_points(s, v, f), thickness).collides) {
        ++colliding;
        EXPECT_FALSE(certainly_apart(vf_points(s, v, f), false, thickness)) << "vertex " << v << " face " << f;
        EXPECT_TRUE(listed) << "colliding vertex " << v << " face " << f << " is missing";
      }
    }
  }
  const auto& edges = s.scene.edges();
  for (Index a = 0; a < edges.size(); ++a) {
    for (Index b = a + 1; b < edges.size(); ++b) {
      const bool shared = edges[a][0] == edges[b][0] || edges[a][0] == edges[b][1] || edges[a][1] == edges[b][0] ||
                          edges[a][1] == edges[b][1];
      const bool listed = std::binary_search(ee.begin(), ee.end(), EdgeEdgeCandidate{a, b});
      if (shared) {
        EXPECT_FALSE(listed) << "edges " << a << ", " << b << " share a vertex";
        continue;
      }
      pruned += !listed;
      if (exact_edge_edge_ccd(ee_points(s, a, b), thickness).collides) {
        ++colliding;
        EXPECT_FALSE(certainly_apart(ee_points(s, a, b), true, thickness)) << "edges " << a << ", " << b;
        EXPECT_TRUE(listed) << "colliding edges " << a << ", " << b << " are missing";
      }
    }
  }
  // The scenes are built so that both sides of the oracle are exercised.
  EXPECT_GT(colliding, 0u);
  EXPECT_GT(pruned, 0u);
  std::size_t excluded = 0;
  for (const VertexFaceCandidate& c : vf) excluded += certainly_apart(vf_points(s, c.vertex, c.face), false, thickness);
  for (const EdgeEdgeCandidate& c : ee) excluded += certainly_apart(ee_points(s, c.edge_a, c.edge_b), true, thickness);
  EXPECT_GT(excluded, 0u) << "the exclusion should decide some candidates";
}

TEST_P(CompleteCandidates, HoldEveryIntersectingTrianglePair) {
  const RandomScene s = make_random_scene(GetParam() + 100, 0.0);
  const std::vector<TrianglePair> pairs = complete_triangle_candidates(s.scene, s.x_t0);
  ASSERT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));
  const auto& triangles = s.scene.triangles();
  std::size_t intersecting = 0;
  for (Index a = 0; a < triangles.size(); ++a) {
    for (Index b = a + 1; b < triangles.size(); ++b) {
      const Triangle& ta = triangles[a];
      const Triangle& tb = triangles[b];
      const std::array<Vec3, 3> pa{s.x_t0[ta[0]], s.x_t0[ta[1]], s.x_t0[ta[2]]};
      const std::array<Vec3, 3> pb{s.x_t0[tb[0]], s.x_t0[tb[1]], s.x_t0[tb[2]]};
      int shared = 0;
      for (Index u : ta)
        for (Index w : tb) shared += u == w;
      if (shared == 3 || exact_triangle_is_degenerate(pa) || exact_triangle_is_degenerate(pb)) continue;
      if (exact_triangles_intersect(pa, ta, pb, tb)) {
        ++intersecting;
        EXPECT_TRUE(std::binary_search(pairs.begin(), pairs.end(), TrianglePair{a, b}))
            << "intersecting faces " << a << ", " << b << " are missing";
      }
    }
  }
  EXPECT_GT(intersecting, 0u);
}

INSTANTIATE_TEST_SUITE_P(Seeds, CompleteCandidates, ::testing::Values(1u, 2u));

TEST(CompleteCandidates, DropPairsWhoseBoxesAreFartherApartThanTheThickness) {
  // Two still triangles whose boxes are exactly 1.0 apart along x.
  std::vector<Object> objects;
  objects.push_back(make_object("left", 3, {{0, 1, 2}}));
  objects.push_back(make_object("right", 3, {{0, 1, 2}}));
  const Scene scene(std::move(objects));
  const std::vector<Vec3> x{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {3, 0, 0}, {2, 1, 0}};
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  complete_ccd_candidates(scene, x, x, 0.5, vf, ee);
  EXPECT_TRUE(vf.empty());
  EXPECT_TRUE(ee.empty());
  complete_ccd_candidates(scene, x, x, 1.0, vf, ee);  // gap exactly 1.0: not more than d, kept
  EXPECT_FALSE(vf.empty());
  EXPECT_FALSE(ee.empty());
}

}  // namespace
}  // namespace snag::validate
