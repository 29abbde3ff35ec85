// RuleSet: collision groups and self-collision, thickness per object, the
// allow-list (first match wins), the neighbourhood test against brute-force
// ring distances on a hand-made grid, and judge().
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <thread>

#include "libcd/core/error.hpp"
#include "report/rules.hpp"
#include "tests/common/grid_object.hpp"

namespace snag::report {
namespace {

Object grid(const std::string& name, Index n) { return test::grid_object(name, n); }

Object triangle(const std::string& name) { return make_object(name, 3, {Triangle{0, 1, 2}}); }

Event vertex_face(Index vertex, Index face, std::size_t frame = 0, Vec3 position = {}) {
  Event e;
  e.kind = EventKind::kCollision;
  e.type = ContactType::kVertexFace;
  e.a = vertex;
  e.b = face;
  e.frame = frame;
  e.position = position;
  return e;
}

Event edge_edge(Index a, Index b) {
  Event e;
  e.type = ContactType::kEdgeEdge;
  e.a = a;
  e.b = b;
  return e;
}

Event intersection(Index a, Index b, std::size_t frame = 0, Vec3 position = {}) {
  Event e;
  e.kind = EventKind::kIntersection;
  e.type = ContactType::kTriangleTriangle;
  e.a = a;
  e.b = b;
  e.frame = frame;
  e.position = position;
  return e;
}

/// Three one-triangle objects a, b, c: global vertices 3o..3o+2, face o.
Scene three_triangles() { return Scene({triangle("a"), triangle("b"), triangle("c")}); }

TEST(RuleSet, ChecksEveryPairByDefault) {
  const Scene scene = three_triangles();
  const RuleSet rules(scene, ScanRules{}, 0);
  for (std::size_t a = 0; a < 3; ++a) {
    for (std::size_t b = 0; b < 3; ++b) EXPECT_TRUE(rules.pair_checked(a, b));
  }
  EXPECT_EQ(rules.classify(vertex_face(0, 2)).kind, Disposition::kChecked);
}

TEST(RuleSet, PairsRestrictOtherObjectsAndNoSelfTurnsSelfOff) {
  const Scene scene = three_triangles();
  ScanRules r;
  r.pairs = {{"b", "a"}};
  r.no_self = {"b"};
  const RuleSet rules(scene, r, 0);
  EXPECT_TRUE(rules.pair_checked(0, 1));
  EXPECT_TRUE(rules.pair_checked(1, 0));
  EXPECT_FALSE(rules.pair_checked(0, 2));
  EXPECT_FALSE(rules.pair_checked(2, 1));
  EXPECT_TRUE(rules.pair_checked(0, 0));
  EXPECT_FALSE(rules.pair_checked(1, 1));
  EXPECT_TRUE(rules.pair_checked(2, 2));
  EXPECT_EQ(rules.classify(vertex_face(0, 1)).kind, Disposition::kChecked);       // a vertex, b face
  EXPECT_EQ(rules.classify(vertex_face(3, 0)).kind, Disposition::kChecked);       // b vertex, a face
  EXPECT_EQ(rules.classify(vertex_face(6, 0)).kind, Disposition::kNotChecked);    // c vertex, a face
  EXPECT_EQ(rules.classify(intersection(1, 2)).kind, Disposition::kNotChecked);   // b, c
  EXPECT_EQ(rules.classify(edge_edge(3, 4)).kind, Disposition::kNotChecked);      // b's edges: self
  EXPECT_EQ(rules.classify(edge_edge(6, 7)).kind, Disposition::kChecked);         // c's edges: self
}

TEST(RuleSet, UnknownObjectIsAUsageErrorListingTheScenesObjects) {
  const Scene scene = three_triangles();
  ScanRules r;
  r.no_self = {"cloth"};
  try {
    RuleSet rules(scene, r, 0);
    FAIL() << "no error";
  } catch (const UsageError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("'cloth'"), std::string::npos) << what;
    EXPECT_NE(what.find("'a', 'b', 'c'"), std::string::npos) << what;
  }
  ScanRules pair;
  pair.pairs = {{"a", "body"}};
  EXPECT_THROW(RuleSet(scene, pair, 0), UsageError);
  ScanRules allow;
  allow.allow.push_back(AllowRule{"", "body", {}, 0, 1, {}, ""});
  EXPECT_THROW(RuleSet(scene, allow, 0), UsageError);
  ScanRules thick;
  thick.thickness = {{"body", 0.1}};
  EXPECT_THROW(RuleSet(scene, thick, 0), UsageError);
}

TEST(RuleSet, RefusesNegativeOrNonFiniteThickness) {
  const Scene scene = three_triangles();
  EXPECT_THROW(RuleSet(scene, ScanRules{}, -1e-3), UsageError);
  EXPECT_THROW(RuleSet(scene, ScanRules{}, std::nan("")), UsageError);
  ScanRules r;
  r.thickness = {{"a", -0.5}};
  EXPECT_THROW(RuleSet(scene, r, 0), UsageError);
  r.thickness = {{"a", std::numeric_limits<double>::infinity()}};
  EXPECT_THROW(RuleSet(scene, r, 0), UsageError);
}

TEST(RuleSet, PairThicknessIsTheMeanAndTheRunUsesTheLargestCheckedPair) {
  const Scene scene = three_triangles();
  ScanRules r;
  r.thickness = {{"a", 0.3}, {"b", 0.2}, {"b", 0.1}};  // a later value wins
  const RuleSet rules(scene, r, 0.05);
  EXPECT_DOUBLE_EQ(rules.object_thickness(0), 0.3);
  EXPECT_DOUBLE_EQ(rules.object_thickness(1), 0.1);
  EXPECT_DOUBLE_EQ(rules.object_thickness(2), 0.05);
  EXPECT_DOUBLE_EQ(rules.pair_thickness(0, 1), 0.2);
  EXPECT_DOUBLE_EQ(rules.max_thickness(), 0.3);  // a against itself
  EXPECT_TRUE(rules.thickness_varies());

  r.no_self = {"a"};
  const RuleSet without_a_self(scene, r, 0.05);
  EXPECT_DOUBLE_EQ(without_a_self.max_thickness(), 0.5 * (0.3 + 0.1));

  const RuleSet uniform(scene, ScanRules{}, 0.25);
  EXPECT_DOUBLE_EQ(uniform.max_thickness(), 0.25);
  EXPECT_FALSE(uniform.thickness_varies());
}

TEST(RuleSet, AllowRulesMatchPairKindFramesAndBoxFirstMatchWins) {
  const Scene scene = three_triangles();
  ScanRules r;
  // 0: a against b, collisions, frames 10..20, inside the unit box
  r.allow.push_back(AllowRule{"a", "b", EventKind::kCollision, 10, 20, std::array<Vec3, 2>{Vec3{0, 0, 0}, Vec3{1, 1, 1}},
                              "hand on hip"});
  // 1: c against anything, any kind, any frame
  r.allow.push_back(AllowRule{"c", "", {}, 0, static_cast<std::size_t>(-1), {}, ""});
  // 2: any pair, intersections, frame 5 only
  r.allow.push_back(AllowRule{"", "", EventKind::kIntersection, 5, 5, {}, ""});
  // 3: b against a (other order), frames 10..30: also matches what rule 0 matches
  r.allow.push_back(AllowRule{"b", "a", {}, 10, 30, {}, ""});
  const RuleSet rules(scene, r, 0);

  auto classify = [&](const Event& e) { return rules.classify(e); };
  // a vertex against b's face, frame 15, inside the box: rule 0
  Disposition d = classify(vertex_face(0, 1, 15, {0.5, 1, 0}));
  EXPECT_EQ(d.kind, Disposition::kAllowed);
  EXPECT_EQ(d.rule, 0u);
  // b vertex against a's face (the pair in the other order), box corner (closed): rule 0
  d = classify(vertex_face(3, 0, 20, {1, 1, 1}));
  EXPECT_EQ(d.kind, Disposition::kAllowed);
  EXPECT_EQ(d.rule, 0u);
  // outside the box: rule 3
  d = classify(vertex_face(0, 1, 15, {1.5, 0, 0}));
  EXPECT_EQ(d.kind, Disposition::kAllowed);
  EXPECT_EQ(d.rule, 3u);
  // frame 21: rule 3; frame 31: checked
  EXPECT_EQ(classify(vertex_face(0, 1, 21, {0.5, 0.5, 0.5})).rule, 3u);
  EXPECT_EQ(classify(vertex_face(0, 1, 31, {0.5, 0.5, 0.5})).kind, Disposition::kChecked);
  EXPECT_EQ(classify(vertex_face(0, 1, 9, {0.5, 0.5, 0.5})).kind, Disposition::kChecked);
  // an intersection of a and b at frame 15 in the box: not rule 0 (kind), rule 3
  EXPECT_EQ(classify(intersection(0, 1, 15, {0.5, 0.5, 0.5})).rule, 3u);
  // an intersection of a and b at frame 5: rule 2
  d = classify(intersection(0, 1, 5));
  EXPECT_EQ(d.kind, Disposition::kAllowed);
  EXPECT_EQ(d.rule, 2u);
  // c against a, c against itself: rule 1 on either side
  EXPECT_EQ(classify(vertex_face(0, 2, 99)).rule, 1u);
  EXPECT_EQ(classify(vertex_face(6, 0, 99)).rule, 1u);
  EXPECT_EQ(classify(edge_edge(6, 7)).rule, 1u);
  // a against itself, frame 15: no rule names a twice
  EXPECT_EQ(classify(edge_edge(0, 1)).kind, Disposition::kChecked);
}

TEST(RuleSet, RefusesEmptyFrameRangesAndInvertedBoxes) {
  const Scene scene = three_triangles();
  ScanRules r;
  r.allow.push_back(AllowRule{"a", "", {}, 5, 4, {}, ""});
  EXPECT_THROW(RuleSet(scene, r, 0), UsageError);
  r.allow = {AllowRule{"a", "", {}, 0, 4, std::array<Vec3, 2>{Vec3{1, 0, 0}, Vec3{0, 1, 1}}, ""}};
  EXPECT_THROW(RuleSet(scene, r, 0), UsageError);
}

TEST(RuleSet, NotCheckedComesBeforeAllowed) {
  const Scene scene = three_triangles();
  ScanRules r;
  r.no_self = {"a"};
  r.allow.push_back(AllowRule{});
  const RuleSet rules(scene, r, 0);
  EXPECT_EQ(rules.classify(edge_edge(0, 1)).kind, Disposition::kNotChecked);
  EXPECT_EQ(rules.classify(edge_edge(3, 4)).kind, Disposition::kAllowed);
}

/// All-pairs vertex distances (in edges) of a scene by one BFS per vertex.
std::vector<std::vector<unsigned>> ring_distances(const Scene& scene) {
  const std::size_t n = scene.vertex_count();
  std::vector<std::vector<Index>> adjacent(n);
  for (const Edge& e : scene.edges()) {
    adjacent[e[0]].push_back(e[1]);
    adjacent[e[1]].push_back(e[0]);
  }
  const unsigned far = std::numeric_limits<unsigned>::max();
  std::vector<std::vector<unsigned>> distance(n, std::vector<unsigned>(n, far));
  for (std::size_t s = 0; s < n; ++s) {
    std::queue<Index> queue;
    distance[s][s] = 0;
    queue.push(static_cast<Index>(s));
    while (!queue.empty()) {
      const Index v = queue.front();
      queue.pop();
      for (Index w : adjacent[v]) {
        if (distance[s][w] != far) continue;
        distance[s][w] = distance[s][v] + 1;
        queue.push(w);
      }
    }
  }
  return distance;
}

unsigned closest(const std::vector<std::vector<unsigned>>& distance, const std::vector<Index>& a,
                 const std::vector<Index>& b) {
  unsigned best = std::numeric_limits<unsigned>::max();
  for (Index u : a) {
    for (Index v : b) best = std::min(best, distance[u][v]);
  }
  return best;
}

TEST(RuleSet, NeighbourhoodMatchesBruteForceRingDistances) {
  // A 5 x 5 grid (object 0) and a lone triangle (object 1) that is never a neighbour.
  const Scene scene({grid("cloth", 5), triangle("pin")});
  const auto distance = ring_distances(scene);
  const auto& triangles = scene.triangles();
  const auto& edges = scene.edges();
  auto corners = [&](const Triangle& t) { return std::vector<Index>(t.begin(), t.end()); };
  auto ends = [&](const Edge& e) { return std::vector<Index>(e.begin(), e.end()); };

  for (unsigned k : {0u, 1u, 2u, 3u}) {
    ScanRules r;
    r.neighbourhood = k;
    const RuleSet rules(scene, r, 0);
    auto expect = [&](const Event& e, unsigned d, bool same_object) {
      const bool near = same_object && k > 0 && d <= k;
      EXPECT_EQ(rules.classify(e).kind, near ? Disposition::kNeighbourhood : Disposition::kChecked)
          << "k " << k << " type " << int(e.type) << " a " << e.a << " b " << e.b << " distance " << d;
    };
    std::size_t near_vf = 0;
    for (Index v = 0; v < scene.vertex_count(); ++v) {
      for (Index f = 0; f < triangles.size(); ++f) {
        const unsigned d = closest(distance, {v}, corners(triangles[f]));
        const bool same = scene.object_of_vertex(v) == scene.object_of_triangle(f);
        expect(vertex_face(v, f), d, same);
        near_vf += same && k > 0 && d <= k;
      }
    }
    if (k > 0) EXPECT_GT(near_vf, 0u);
    for (Index a = 0; a < edges.size(); ++a) {
      for (Index b = a + 1; b < edges.size(); ++b) {
        expect(edge_edge(a, b), closest(distance, ends(edges[a]), ends(edges[b])),
               scene.object_of_edge(a) == scene.object_of_edge(b));
      }
    }
    for (Index a = 0; a < triangles.size(); ++a) {
      for (Index b = a + 1; b < triangles.size(); ++b) {
        expect(intersection(a, b), closest(distance, corners(triangles[a]), corners(triangles[b])),
               scene.object_of_triangle(a) == scene.object_of_triangle(b));
      }
    }
  }
}

TEST(RuleSet, NeighbourhoodComesBeforeAllowAndClassifyIsThreadSafe) {
  const Scene scene({grid("cloth", 12)});
  ScanRules r;
  r.neighbourhood = 2;
  r.allow.push_back(AllowRule{});
  const RuleSet rules(scene, r, 0);
  std::vector<Disposition::Kind> serial;
  for (Index v = 0; v < scene.vertex_count(); ++v) {
    for (Index f = 0; f < scene.triangle_count(); ++f) serial.push_back(rules.classify(vertex_face(v, f)).kind);
  }
  EXPECT_NE(std::find(serial.begin(), serial.end(), Disposition::kNeighbourhood), serial.end());
  EXPECT_NE(std::find(serial.begin(), serial.end(), Disposition::kAllowed), serial.end());
  std::vector<std::vector<Disposition::Kind>> parallel(4);
  std::vector<std::thread> threads;
  for (auto& out : parallel) {
    threads.emplace_back([&] {
      for (Index v = 0; v < scene.vertex_count(); ++v) {
        for (Index f = 0; f < scene.triangle_count(); ++f) out.push_back(rules.classify(vertex_face(v, f)).kind);
      }
    });
  }
  for (auto& t : threads) t.join();
  for (const auto& out : parallel) EXPECT_EQ(out, serial);
}

TEST(Judge, ReportsEachThresholdReachedInFieldOrder) {
  FailThresholds fail;  // events 1, others never
  EXPECT_TRUE(judge(fail, Counts{}).empty());
  Counts counts{3, 2, 1, 4, 0};
  auto failed = judge(fail, counts);
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed[0].what, "events");
  EXPECT_EQ(failed[0].count, 3u);
  EXPECT_EQ(failed[0].threshold, 1u);

  fail = FailThresholds{0, 2, 2, 4, 1};
  failed = judge(fail, counts);
  ASSERT_EQ(failed.size(), 2u);
  EXPECT_EQ(failed[0].what, "collisions");  // 2 >= 2
  EXPECT_EQ(failed[1].what, "regions");     // 4 >= 4; intersections 1 < 2, tracks 0 < 1
  EXPECT_TRUE(judge(FailThresholds{0, 0, 0, 0, 0}, Counts{9, 9, 9, 9, 9}).empty());
}

}  // namespace
}  // namespace snag::report
