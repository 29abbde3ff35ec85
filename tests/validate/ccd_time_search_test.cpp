// The CCD time search (libcd/narrow_phase/ccd_time_search.hpp) against exact
// CCD (CGAL): every answer it gives is right, its enclosure holds the exact
// earliest time of impact, and it decides the plain crossings it is for.
#include "libcd/narrow_phase/ccd_time_search.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "validate/exact_ccd.hpp"

namespace snag {
namespace {

using Points = std::array<Vec3, 8>;
using ccd_detail::coplanarity_cubic;
using ccd_detail::time_search;

/// The time search alone on a vertex-face (points p, a, b, c at t0 then t1)
/// or edge-edge (ea0, ea1, eb0, eb1) query; false when it gives up.
bool search(const Points& x, bool is_edge_edge, double tolerance, CcdResult* result) {
  if (is_edge_edge) {
    const ccd_detail::EdgeEdgeContact contact{{x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]}};
    const Vec3 p[2] = {x[2] - x[0], x[6] - x[4]}, b[2] = {x[1] - x[0], x[5] - x[4]}, c[2] = {x[3] - x[2], x[7] - x[6]};
    return time_search(contact, coplanarity_cubic(p, b, c), tolerance, result);
  }
  const ccd_detail::VertexFaceContact contact{{x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]}};
  const Vec3 p[2] = {x[0] - x[1], x[4] - x[5]}, b[2] = {x[2] - x[1], x[6] - x[5]}, c[2] = {x[3] - x[1], x[7] - x[5]};
  return time_search(contact, coplanarity_cubic(p, b, c), tolerance, result);
}

validate::ExactCcdResult exact(const Points& x, bool is_edge_edge) {
  return is_edge_edge ? validate::exact_edge_edge_ccd(x) : validate::exact_vertex_face_ccd(x);
}

/// Random queries of a unit-sized scene whose primitives pass close to each
/// other: one is steered to a random point of the other at a random time and
/// pushed off by a random gap (negative: through it) along the normal, so
/// the mix holds crossings, near misses and cubics with several roots.
Points random_near_contact(std::mt19937_64& rng, bool is_edge_edge) {
  std::uniform_real_distribution<double> unit(0.0, 1.0), coordinate(-1.0, 1.0), gap(-0.05, 0.05);
  while (true) {
    Points x;
    for (Vec3& p : x) p = {coordinate(rng), coordinate(rng), coordinate(rng)};
    const double t = unit(rng);
    const auto at = [t](const Vec3& x_t0, const Vec3& x_t1) { return (1 - t) * x_t0 + t * x_t1; };
    Vec3 target, normal, moving;
    double u = unit(rng), v = unit(rng);
    if (is_edge_edge) {
      const Vec3 a0 = at(x[0], x[4]), a1 = at(x[1], x[5]), b0 = at(x[2], x[6]), b1 = at(x[3], x[7]);
      normal = cross(a1 - a0, b1 - b0);
      target = (1 - u) * a0 + u * a1;
      moving = (1 - v) * b0 + v * b1;
    } else {
      if (u + v > 1) u = 1 - u, v = 1 - v;
      const Vec3 a = at(x[1], x[5]), b = at(x[2], x[6]), c = at(x[3], x[7]);
      normal = cross(b - a, c - a);
      target = (1 - u - v) * a + u * b + v * c;
      moving = at(x[0], x[4]);
    }
    const double length = std::sqrt(squared_norm(normal));
    if (length < 1e-3 || t < 1e-3) continue;
    const Vec3 shift = (target + (gap(rng) / length) * normal - moving) / t;
    for (int k : is_edge_edge ? std::array<int, 2>{6, 7} : std::array<int, 2>{4, 4}) x[k] = x[k] + shift;
    return x;
  }
}

void check_random_queries(bool is_edge_edge) {
  std::mt19937_64 rng(is_edge_edge ? 12 : 11);
  const double tolerance = 1e-6;
  int decided = 0, hits = 0, proven = 0;
  const int count = 3000;
  for (int i = 0; i < count; ++i) {
    const Points x = random_near_contact(rng, is_edge_edge);
    const validate::ExactCcdResult truth = exact(x, is_edge_edge);
    hits += truth.collides;
    CcdResult r;
    if (!search(x, is_edge_edge, tolerance, &r)) continue;
    ++decided;
    ASSERT_NE(r.answer, CcdAnswer::kUncertain);
    ASSERT_EQ(r.answer == CcdAnswer::kYes, truth.collides) << "query " << i;
    if (!truth.collides) continue;
    ++proven;
    // The enclosure holds the exact earliest time and is at most a few
    // tolerances wide.
    EXPECT_LE(r.toi_lo, truth.toi_hi) << "query " << i;
    EXPECT_GE(r.toi_hi, truth.toi_lo) << "query " << i;
    EXPECT_LE(r.toi_hi - r.toi_lo, 3 * tolerance) << "query " << i;
  }
  // Random crossings are transversal: the search decides nearly all of them.
  EXPECT_GE(decided, count * 99 / 100);
  EXPECT_GE(proven, hits * 99 / 100);
  EXPECT_GT(hits, count / 10);
  EXPECT_LT(hits, count * 9 / 10);
}

TEST(CcdTimeSearch, AgreesWithExactCcdOnRandomVertexFaceQueries) { check_random_queries(false); }
TEST(CcdTimeSearch, AgreesWithExactCcdOnRandomEdgeEdgeQueries) { check_random_queries(true); }

// The time search lets the halves of an interval over which inside_over gave
// +1 inherit it without asking again; that is the answer inside_over gives
// them only if it is inclusion-monotone. Checked over every interval of the
// search tree down to level 11 of random queries: where an interval gives
// +1, both its halves give +1.
int inside(const Points& x, bool is_edge_edge, double ta, double tb) {
  if (is_edge_edge) {
    return ccd_detail::EdgeEdgeContact{{x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]}}.inside_over(ta, tb);
  }
  return ccd_detail::VertexFaceContact{{x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]}}.inside_over(ta, tb);
}

void check_inside_inherited(bool is_edge_edge) {
  std::mt19937_64 rng(is_edge_edge ? 32 : 31);
  int inherited = 0;
  for (int i = 0; i < 100; ++i) {
    const Points x = random_near_contact(rng, is_edge_edge);
    for (int level = 0; level < 11; ++level) {
      for (std::uint32_t num = 0; num < (1u << level); ++num) {
        if (inside(x, is_edge_edge, ccd_detail::lower(num, level), ccd_detail::upper(num, level)) <= 0) continue;
        for (std::uint32_t half = 2 * num; half <= 2 * num + 1; ++half) {
          ++inherited;
          ASSERT_EQ(inside(x, is_edge_edge, ccd_detail::lower(half, level + 1), ccd_detail::upper(half, level + 1)), 1)
              << "query " << i << ", interval " << num << " of level " << level;
        }
      }
    }
  }
  EXPECT_GT(inherited, 10000);
}

TEST(CcdTimeSearch, InsideOverHoldsOnBothHalvesWhereItHoldsOnVertexFaceQueries) { check_inside_inherited(false); }
TEST(CcdTimeSearch, InsideOverHoldsOnBothHalvesWhereItHoldsOnEdgeEdgeQueries) { check_inside_inherited(true); }

// The quick part in two calls (isolating, then refining the interval it
// hands over, as the GPU's quick and refine kernels run it) ends as the quick
// part in one call, with the same result bit for bit, on random queries and
// on those whose earlier crossing beside the feature the search must skip.
// The handed-over interval is wider than the tolerance, has inside +1 and
// opposite signs of g at its ends.
bool same_result(const CcdResult& p, const CcdResult& q) {
  return p.answer == q.answer && std::memcmp(&p.toi_lo, &q.toi_lo, sizeof p.toi_lo) == 0 &&
         std::memcmp(&p.toi_hi, &q.toi_hi, sizeof p.toi_hi) == 0;
}

/// The quick part of the query in one call (`whole`) and in two; returns
/// whether it was handed over.
bool quick_both_ways(const Points& x, bool is_edge_edge, const CcdSettings& settings, bool* whole_decided,
                     CcdResult* whole, bool* split_decided, CcdResult* split) {
  ccd_detail::IsolatedTimeInterval isolated{};
  ccd_detail::TimeSearchEnd end;
  if (is_edge_edge) {
    *whole_decided = edge_edge_quick_search(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings, whole);
    end = edge_edge_quick_isolating(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings, &isolated, split);
  } else {
    *whole_decided = vertex_face_quick_search(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings, whole);
    end = vertex_face_quick_isolating(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings, &isolated, split);
  }
  if (end != ccd_detail::TimeSearchEnd::kIsolated) {
    *split_decided = end == ccd_detail::TimeSearchEnd::kDecided;
    return false;
  }
  const ccd_detail::TimeInterval& node = isolated.node;
  EXPECT_TRUE(node.inside);
  EXPECT_TRUE(opposite_signs(node.b[0], node.b[3]));
  EXPECT_GT(ccd_detail::upper(node.num, node.level) - ccd_detail::lower(node.num, node.level),
            settings.time_tolerance);
  EXPECT_GE(isolated.examined, 1);
  *split_decided = is_edge_edge ? edge_edge_quick_refine(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], isolated,
                                                         settings, split)
                                : vertex_face_quick_refine(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], isolated,
                                                           settings, split);
  return true;
}

void check_isolated_then_refined(bool is_edge_edge) {
  std::mt19937_64 rng(is_edge_edge ? 52 : 51);
  CcdSettings settings;
  int handed_over = 0, hits = 0;
  const int count = 3000;
  for (int i = 0; i < count; ++i) {
    const Points x = random_near_contact(rng, is_edge_edge);
    bool whole_decided = false, split_decided = false;
    CcdResult whole, split;
    handed_over += quick_both_ways(x, is_edge_edge, settings, &whole_decided, &whole, &split_decided, &split);
    ASSERT_EQ(split_decided, whole_decided) << "query " << i;
    if (!whole_decided) continue;
    hits += whole.answer == CcdAnswer::kYes;
    ASSERT_TRUE(same_result(split, whole)) << "query " << i;
  }
  // Nearly every crossing is handed over, and nothing else is.
  EXPECT_GE(handed_over, hits * 9 / 10);
  EXPECT_LE(handed_over, count - (count - hits) * 9 / 10);
  EXPECT_GT(hits, count / 10);
}

TEST(CcdTimeSearch, IsolatedThenRefinedEqualsOneSearchOnVertexFaceQueries) { check_isolated_then_refined(false); }
TEST(CcdTimeSearch, IsolatedThenRefinedEqualsOneSearchOnEdgeEdgeQueries) { check_isolated_then_refined(true); }

TEST(CcdTimeSearch, IsolatedThenRefinedSkipsTheEarlierCrossingBesideTheTriangle) {
  const Vec3 a{-1, 0, 0}, b{1, 0, 0}, c_t0{0, 1, 1}, c_t1{0, 1, -1};
  const Points x{Vec3{0, -0.5, -0.08}, a, b, c_t0, Vec3{0, 0.5, -0.08}, a, b, c_t1};
  bool whole_decided = false, split_decided = false;
  CcdResult whole, split;
  EXPECT_TRUE(quick_both_ways(x, false, CcdSettings{}, &whole_decided, &whole, &split_decided, &split));
  ASSERT_TRUE(whole_decided);
  ASSERT_TRUE(split_decided);
  EXPECT_EQ(whole.answer, CcdAnswer::kYes);
  EXPECT_TRUE(same_result(split, whole));
}

// A triangle turning about its edge a-b (the x axis), its plane z = (1 - 2t) y,
// while a vertex moves along y at z = -0.08: it meets the plane at t = 0.3
// beside the triangle (y = -0.2), then at t = 0.7 inside it (y = 0.2). The
// search must skip the first root and enclose the second.
TEST(CcdTimeSearch, SkipsAnEarlierCrossingOfThePlaneBesideTheTriangle) {
  const Vec3 a{-1, 0, 0}, b{1, 0, 0}, c_t0{0, 1, 1}, c_t1{0, 1, -1};
  const Vec3 p_t0{0, -0.5, -0.08}, p_t1{0, 0.5, -0.08};
  const Points x{p_t0, a, b, c_t0, p_t1, a, b, c_t1};
  const validate::ExactCcdResult truth = validate::exact_vertex_face_ccd(x);
  ASSERT_TRUE(truth.collides);
  CcdResult r;
  ASSERT_TRUE(search(x, false, 1e-6, &r));
  ASSERT_EQ(r.answer, CcdAnswer::kYes);
  EXPECT_LE(r.toi_lo, truth.toi_hi);
  EXPECT_GE(r.toi_hi, truth.toi_lo);
  EXPECT_LE(r.toi_hi - r.toi_lo, 3e-6);
  EXPECT_NEAR(r.toi_lo, 0.7, 1e-5);
}

// Where the time search cannot decide, it gives up rather than guess: a
// contact at t = 0, and a vertex sliding in the triangle's plane.
TEST(CcdTimeSearch, GivesUpOnContactAtTheStartAndOnCoplanarMotion) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  CcdResult r;
  EXPECT_FALSE(search({Vec3{0.25, 0.25, 0}, a, b, c, Vec3{0.25, 0.25, 1}, a, b, c}, false, 1e-6, &r));
  EXPECT_FALSE(search({Vec3{2, 0.25, 0}, a, b, c, Vec3{-1, 0.25, 0}, a, b, c}, false, 1e-6, &r));
  // The full kernels still answer them: a contact, proven or left to exact
  // arithmetic, never a miss.
  EXPECT_NE(vertex_face_ccd(Vec3{0.25, 0.25, 0}, a, b, c, Vec3{0.25, 0.25, 1}, a, b, c, CcdSettings{}).answer,
            CcdAnswer::kNo);
  EXPECT_NE(vertex_face_ccd(Vec3{2, 0.25, 0}, a, b, c, Vec3{-1, 0.25, 0}, a, b, c, CcdSettings{}).answer,
            CcdAnswer::kNo);
}

}  // namespace
}  // namespace snag
