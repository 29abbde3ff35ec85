// Exact CCD against the symbolic ground truth of the CCD query sets, against
// hand-built degenerate configurations with known times of impact, and against
// CGAL exact predicates at rational times.
#include "validate/exact_ccd.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Gmpq.h>
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "libcd/core/error.hpp"

namespace snag::validate {
namespace {

namespace fs = std::filesystem;
using Rational = CGAL::Gmpq;
using Epeck = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = Epeck::Point_3;

// ---------------------------------------------------------------------------
// The query files, read with their numerators and denominators kept exact.

struct Query {
  std::array<RationalVec3, 8> points;
  bool truth = false;
};

std::vector<Query> read_queries(const fs::path& csv) {
  std::ifstream in(csv);
  std::vector<Query> queries;
  std::string line;
  std::size_t row = 0;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream fields(line);
    std::string cell;
    while (std::getline(fields, cell, ',')) cells.push_back(cell);
    if (cells.size() != 7) throw std::runtime_error(csv.string() + ": row without 7 columns");
    if (row % 8 == 0) queries.emplace_back();
    Query& q = queries.back();
    q.points[row % 8] = {cells[0] + "/" + cells[1], cells[2] + "/" + cells[3], cells[4] + "/" + cells[5]};
    q.truth = cells[6] == "1";
    ++row;
  }
  return queries;
}

std::vector<Query> all_queries(const std::string& kind) {
  std::vector<Query> queries;
  std::vector<fs::path> files;
  for (const auto& scene : fs::directory_iterator(fs::path(SNAG_SHARED_DATA_DIR) / "ccd-queries"))
    if (scene.is_directory() && fs::is_directory(scene.path() / kind))
      for (const auto& file : fs::directory_iterator(scene.path() / kind))
        if (file.path().extension() == ".csv") files.push_back(file.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    auto part = read_queries(f);
    queries.insert(queries.end(), part.begin(), part.end());
  }
  return queries;
}

// A double equal to the rational, which the query files promise.
double exact_double(const std::string& text) {
  const Rational q(text);
  const auto bounds = CGAL::to_interval(q);
  EXPECT_EQ(bounds.first, bounds.second) << text << " is not a double";
  return bounds.first;
}

template <class Ccd>
void check_against_ground_truth(const std::string& kind, Ccd ccd) {
  const auto queries = all_queries(kind);
  ASSERT_GT(queries.size(), 1000u);
  std::size_t false_positives = 0, false_negatives = 0, positives = 0, double_mismatches = 0;
  const auto start = std::chrono::steady_clock::now();
  for (const auto& q : queries) {
    const ExactCcdResult r = ccd(q.points);
    positives += q.truth;
    false_positives += r.collides && !q.truth;
    false_negatives += !r.collides && q.truth;
    if (r.collides) EXPECT_LE(r.toi_lo, r.toi_hi);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The same queries through the double overload give the same answers.
  for (std::size_t i = 0; i < queries.size(); i += 7) {
    std::array<Vec3, 8> points;
    for (int k = 0; k < 8; ++k)
      points[k] = {exact_double(queries[i].points[k].x), exact_double(queries[i].points[k].y),
                   exact_double(queries[i].points[k].z)};
    const ExactCcdResult from_rational = ccd(queries[i].points);
    const ExactCcdResult from_double = ccd(points);
    double_mismatches += from_rational.collides != from_double.collides ||
                         from_rational.toi_lo_exact != from_double.toi_lo_exact;
  }
  std::cout << kind << ": " << queries.size() << " queries, " << positives << " colliding, "
            << false_positives << " false positives, " << false_negatives << " false negatives, "
            << 1e6 * seconds / queries.size() << " us per query\n";
  EXPECT_EQ(false_positives, 0u);
  EXPECT_EQ(false_negatives, 0u);
  EXPECT_EQ(double_mismatches, 0u);
}

TEST(ExactCcd, MatchesSymbolicGroundTruthOnAllVertexFaceQueries) {
  check_against_ground_truth("vertex-face", [](const auto& p) { return exact_vertex_face_ccd(p); });
}

TEST(ExactCcd, MatchesSymbolicGroundTruthOnAllEdgeEdgeQueries) {
  check_against_ground_truth("edge-edge", [](const auto& p) { return exact_edge_edge_ccd(p); });
}

// ---------------------------------------------------------------------------
// Hand-built configurations with known answers.

using Points = std::array<Vec3, 8>;

/// The 8 rows from start and end positions of the 4 vertices.
Points motion(std::array<Vec3, 4> t0, std::array<Vec3, 4> t1) {
  return {t0[0], t0[1], t0[2], t0[3], t1[0], t1[1], t1[2], t1[3]};
}

void expect_toi(const ExactCcdResult& r, const Rational& toi, double width = 1e-9) {
  ASSERT_TRUE(r.collides);
  const Rational lo(r.toi_lo_exact), hi(r.toi_hi_exact);
  EXPECT_LE(lo, toi);
  EXPECT_LE(toi, hi);
  EXPECT_LE(hi - lo, Rational(width));
  EXPECT_LE(r.toi_lo, CGAL::to_double(toi));
  EXPECT_GE(r.toi_hi, CGAL::to_double(toi));
  EXPECT_LE(Rational(r.toi_lo), lo);
  EXPECT_GE(Rational(r.toi_hi), hi);
}

const Vec3 kA{0, 0, 0}, kB{1, 0, 0}, kC{0, 1, 0};

TEST(ExactCcd, BracketsVertexCrossingFaceAtOneThird) {
  const auto r = exact_vertex_face_ccd(motion({Vec3{0.25, 0.25, 1}, kA, kB, kC}, {Vec3{0.25, 0.25, -2}, kA, kB, kC}));
  expect_toi(r, Rational(1, 3));
  expect_toi(exact_vertex_face_ccd(motion({Vec3{0.25, 0.25, 1}, kA, kB, kC}, {Vec3{0.25, 0.25, -2}, kA, kB, kC}), 0, 1e-15),
             Rational(1, 3), 1e-15);
}

TEST(ExactCcd, FindsVertexEnteringFaceWhileCoplanarForTheWholeStep) {
  // p.x(t) = 2 - 3t reaches the hypotenuse x + y = 1 at y = 1/4 when t = 5/12.
  expect_toi(exact_vertex_face_ccd(motion({Vec3{2, 0.25, 0}, kA, kB, kC}, {Vec3{-1, 0.25, 0}, kA, kB, kC})),
             Rational(5, 12));
  // The same slide beside the face never touches it.
  EXPECT_FALSE(exact_vertex_face_ccd(motion({Vec3{2, -0.25, 0}, kA, kB, kC}, {Vec3{-1, -0.25, 0}, kA, kB, kC})).collides);
}

TEST(ExactCcd, ReportsContactAtStartAndEnd) {
  expect_toi(exact_vertex_face_ccd(motion({Vec3{0.25, 0.25, 0}, kA, kB, kC}, {Vec3{0.25, 0.25, 5}, kA, kB, kC})), 0);
  expect_toi(exact_vertex_face_ccd(motion({Vec3{0.25, 0.25, 5}, kA, kB, kC}, {Vec3{0.5, 0.5, 0}, kA, kB, kC})), 1);
  expect_toi(exact_edge_edge_ccd(motion({Vec3{0, 0, 1}, Vec3{1, 0, 1}, Vec3{0.5, -1, 0}, Vec3{0.5, 1, 0}},
                                        {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0.5, -1, 0}, Vec3{0.5, 1, 0}})),
             1);
}

TEST(ExactCcd, HandlesNoMotion) {
  expect_toi(exact_vertex_face_ccd(motion({Vec3{0.5, 0.5, 0}, kA, kB, kC}, {Vec3{0.5, 0.5, 0}, kA, kB, kC})), 0);
  EXPECT_FALSE(exact_vertex_face_ccd(motion({Vec3{0.5, 0.5 + 0x1p-52, 0}, kA, kB, kC},
                                            {Vec3{0.5, 0.5 + 0x1p-52, 0}, kA, kB, kC})).collides);
}

TEST(ExactCcd, DetectsTouchingWithoutCrossing) {
  // The face tilts about the x axis (plane z = (2t - 1) y) while the vertex
  // rides y = 2t - 1, z = 0: the coplanarity cubic has a double root at 1/2,
  // where the vertex touches edge ab.
  const Vec3 c_t0{0, 1, -1}, c_t1{0, 1, 1};
  expect_toi(exact_vertex_face_ccd(motion({Vec3{0.25, -1, 0}, kA, kB, c_t0}, {Vec3{0.25, 1, 0}, kA, kB, c_t1})),
             Rational(1, 2));
  EXPECT_FALSE(exact_vertex_face_ccd(motion({Vec3{2, -1, 0}, kA, kB, c_t0}, {Vec3{2, 1, 0}, kA, kB, c_t1})).collides);
}

TEST(ExactCcd, HandlesZeroAreaFaces) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{2, 0, 0};
  expect_toi(exact_vertex_face_ccd(motion({Vec3{1.5, 1, 0}, a, b, c}, {Vec3{1.5, -3, 0}, a, b, c})), Rational(1, 4));
  EXPECT_FALSE(exact_vertex_face_ccd(motion({Vec3{2.5, 1, 0}, a, b, c}, {Vec3{2.5, -3, 0}, a, b, c})).collides);
  // All three corners at one point, which the vertex passes through.
  const Vec3 o{1, 1, 1};
  expect_toi(exact_vertex_face_ccd(motion({Vec3{1, 1, 0}, o, o, o}, {Vec3{1, 1, 3}, o, o, o})), Rational(1, 3));
  EXPECT_FALSE(exact_vertex_face_ccd(motion({Vec3{1, 1 + 0x1p-40, 0}, o, o, o}, {Vec3{1, 1 + 0x1p-40, 3}, o, o, o})).collides);
}

TEST(ExactCcd, BracketsEdgesCrossingAtOneThird) {
  expect_toi(exact_edge_edge_ccd(motion({Vec3{0, 0, 1}, Vec3{1, 0, 1}, Vec3{0.5, -1, 0}, Vec3{0.5, 1, 0}},
                                        {Vec3{0, 0, -2}, Vec3{1, 0, -2}, Vec3{0.5, -1, 0}, Vec3{0.5, 1, 0}})),
             Rational(1, 3));
}

TEST(ExactCcd, HandlesParallelAndCollinearEdges) {
  const Vec3 a0{0, 0, 0}, a1{1, 0, 0};
  // Parallel in one plane, moving onto each other: overlap from t = 1/3.
  expect_toi(exact_edge_edge_ccd(motion({a0, a1, Vec3{0.5, 1, 0}, Vec3{1.5, 1, 0}}, {a0, a1, Vec3{0.5, -2, 0}, Vec3{1.5, -2, 0}})),
             Rational(1, 3));
  // Parallel, but side by side along x: they never meet.
  EXPECT_FALSE(exact_edge_edge_ccd(motion({a0, a1, Vec3{2, 1, 0}, Vec3{3, 1, 0}}, {a0, a1, Vec3{2, -2, 0}, Vec3{3, -2, 0}})).collides);
  // Collinear, sliding along their line: end to end at t = 1/2.
  expect_toi(exact_edge_edge_ccd(motion({a0, a1, Vec3{3, 0, 0}, Vec3{4, 0, 0}}, {a0, a1, Vec3{-1, 0, 0}, Vec3{0, 0, 0}})),
             Rational(1, 2));
  // Collinear and sliding apart, touching only at the start.
  expect_toi(exact_edge_edge_ccd(motion({a0, a1, Vec3{1, 0, 0}, Vec3{2, 0, 0}}, {a0, a1, Vec3{2, 0, 0}, Vec3{3, 0, 0}})), 0);
}

TEST(ExactCcd, HandlesZeroLengthEdges) {
  const Vec3 a0{0, 0, 0}, a1{1, 0, 0};
  // A zero-length edge passing through a's interior at t = 2/3.
  expect_toi(exact_edge_edge_ccd(motion({a0, a1, Vec3{0.5, 2, 1}, Vec3{0.5, 2, 1}}, {a0, a1, Vec3{0.5, -1, -0.5}, Vec3{0.5, -1, -0.5}})),
             Rational(2, 3));
  // Two zero-length edges meeting at t = 1/4, and missing by 2^-1000.
  const Vec3 q{0.25, 0, 0}, near_q{0.25, 0x1p-1000, 0};
  const Vec3 p_t0{0, 0, 0}, p_t1{1, 0, 0};
  expect_toi(exact_edge_edge_ccd(motion({p_t0, p_t0, q, q}, {p_t1, p_t1, q, q})), Rational(1, 4));
  EXPECT_FALSE(exact_edge_edge_ccd(motion({p_t0, p_t0, near_q, near_q}, {p_t1, p_t1, near_q, near_q})).collides);
}

TEST(ExactCcd, DetectsEndpointTouchingEdgeInterior) {
  // b's endpoint slides onto a's interior at t = 1/2 and stops there.
  const Vec3 a0{0, 0, 0}, a1{1, 0, 0};
  expect_toi(exact_edge_edge_ccd(motion({a0, a1, Vec3{0.5, 1, 1}, Vec3{0.5, 2, 2}}, {a0, a1, Vec3{0.5, 0, 0}, Vec3{0.5, 1, 1}})), 1);
  expect_toi(exact_edge_edge_ccd(motion({a0, a1, Vec3{0.5, 1, 1}, Vec3{0.5, 2, 2}}, {a0, a1, Vec3{0.5, -1, -1}, Vec3{0.5, 0, 0}})),
             Rational(1, 2));
}

TEST(ExactCcd, DecidesThicknessExactly) {
  // Vertex from z = 1 to z = -1 over the face: within 1/4 from t = 3/8.
  const auto points = motion({Vec3{0.25, 0.25, 1}, kA, kB, kC}, {Vec3{0.25, 0.25, -1}, kA, kB, kC});
  expect_toi(exact_vertex_face_ccd(points, 0.25), Rational(3, 8));
  // Passing beside the face at distance exactly 1/2 from edge ab, and just over it.
  expect_toi(exact_vertex_face_ccd(motion({Vec3{0.5, -0.5, 1}, kA, kB, kC}, {Vec3{0.5, -0.5, -1}, kA, kB, kC}), 0.5),
             Rational(1, 2));
  EXPECT_FALSE(exact_vertex_face_ccd(motion({Vec3{0.5, -0.5, 1}, kA, kB, kC}, {Vec3{0.5, -0.5, -1}, kA, kB, kC}),
                                     0.5 - 0x1p-50).collides);
  // Parallel edges 1 apart approaching at speed 2: within 1/2 from t = 1/4.
  const Vec3 a0{0, 0, 0}, a1{1, 0, 0};
  expect_toi(exact_edge_edge_ccd(motion({a0, a1, Vec3{0, 1, 0}, Vec3{1, 1, 0}}, {a0, a1, Vec3{0, -1, 0}, Vec3{1, -1, 0}}), 0.5),
             Rational(1, 4));
}

TEST(ExactCcd, RejectsBadParameters) {
  const auto points = motion({Vec3{0.25, 0.25, 1}, kA, kB, kC}, {Vec3{0.25, 0.25, -1}, kA, kB, kC});
  EXPECT_THROW(exact_vertex_face_ccd(points, -1), UsageError);
  EXPECT_THROW(exact_vertex_face_ccd(points, 0, 0), UsageError);
  std::array<RationalVec3, 8> text;
  for (auto& p : text) p = {"0", "1/2", "3"};
  EXPECT_NO_THROW(exact_edge_edge_ccd(text));
  text[3].y = "1/0";
  EXPECT_THROW(exact_edge_edge_ccd(text), UsageError);
  text[3].y = "x";
  EXPECT_THROW(exact_edge_edge_ccd(text), UsageError);
}

// ---------------------------------------------------------------------------
// Random cross-check with CGAL predicates at rational times.

Epeck::FT exact_ft(const Rational& q) { return Epeck::FT(mpq_class(q.mpq())); }

Point at(const Vec3& p_t0, const Vec3& p_t1, const Rational& t) {
  const Rational x = Rational(p_t0.x) + t * (Rational(p_t1.x) - Rational(p_t0.x));
  const Rational y = Rational(p_t0.y) + t * (Rational(p_t1.y) - Rational(p_t0.y));
  const Rational z = Rational(p_t0.z) + t * (Rational(p_t1.z) - Rational(p_t0.z));
  return Point(exact_ft(x), exact_ft(y), exact_ft(z));
}

bool point_on_segment(const Point& p, const Point& a, const Point& b) {
  if (a == b) return p == a;
  return CGAL::collinear(a, b, p) && CGAL::collinear_are_ordered_along_line(a, p, b);
}

bool vertex_face_contact_at(const Points& q, const Rational& t) {
  const Point p = at(q[0], q[4], t), a = at(q[1], q[5], t), b = at(q[2], q[6], t), c = at(q[3], q[7], t);
  if (!CGAL::collinear(a, b, c)) return CGAL::do_intersect(Epeck::Triangle_3(a, b, c), p);
  return point_on_segment(p, a, b) || point_on_segment(p, b, c) || point_on_segment(p, c, a);
}

bool edge_edge_contact_at(const Points& q, const Rational& t) {
  const Point a0 = at(q[0], q[4], t), a1 = at(q[1], q[5], t), b0 = at(q[2], q[6], t), b1 = at(q[3], q[7], t);
  if (a0 == a1) return point_on_segment(a0, b0, b1);
  if (b0 == b1) return point_on_segment(b0, a0, a1);
  return CGAL::coplanar(a0, a1, b0, b1) && CGAL::do_intersect(Epeck::Segment_3(a0, a1), Epeck::Segment_3(b0, b1));
}

/// Rational times k/m in [0, 1], m <= 12.
std::vector<Rational> grid_times() {
  std::vector<Rational> times;
  for (int m = 1; m <= 12; ++m)
    for (int k = 0; k <= m; ++k) times.emplace_back(k, m);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  return times;
}

template <class Ccd, class Contact>
void cross_check_small_integer_motions(Ccd ccd, Contact contact_at) {
  std::mt19937 rng(12345);
  std::uniform_int_distribution<int> coordinate(-2, 2);
  const auto times = grid_times();
  int colliding = 0, grid_contacts = 0;
  for (int trial = 0; trial < 400; ++trial) {
    Points q;
    for (auto& p : q) p = {double(coordinate(rng)), double(coordinate(rng)), double(coordinate(rng))};
    const ExactCcdResult r = ccd(q, 0.0);
    colliding += r.collides;
    const Rational lo = r.collides ? Rational(r.toi_lo_exact) : Rational(2);
    for (const auto& t : times) {
      if (!contact_at(q, t)) continue;
      ++grid_contacts;
      // Contact at t: the exact CCD must report it, no later than t.
      ASSERT_TRUE(r.collides) << "trial " << trial << " t " << t;
      EXPECT_LE(lo, t) << "trial " << trial;
      break;
    }
    if (r.collides) {
      // No contact strictly before the reported interval.
      for (const auto& t : times) {
        if (t >= lo) break;
        EXPECT_FALSE(contact_at(q, t)) << "trial " << trial << " t " << t;
      }
      if (r.toi_lo_exact == r.toi_hi_exact) EXPECT_TRUE(contact_at(q, lo)) << "trial " << trial;
      // A thickness only brings the contact earlier.
      const ExactCcdResult thick = ccd(q, 0.125);
      ASSERT_TRUE(thick.collides);
      EXPECT_LE(Rational(thick.toi_lo_exact), Rational(r.toi_hi_exact));
    }
  }
  std::cout << colliding << " of 400 colliding, " << grid_contacts << " with contact at a grid time\n";
  EXPECT_GT(colliding, 20);
}

TEST(ExactCcd, AgreesWithCgalPredicatesOnSmallIntegerVertexFaceMotions) {
  cross_check_small_integer_motions([](const Points& q, double d) { return exact_vertex_face_ccd(q, d); },
                                    vertex_face_contact_at);
}

TEST(ExactCcd, AgreesWithCgalPredicatesOnSmallIntegerEdgeEdgeMotions) {
  cross_check_small_integer_motions([](const Points& q, double d) { return exact_edge_edge_ccd(q, d); },
                                    edge_edge_contact_at);
}

// Within distance d at time t, by CGAL's exact squared distances (the
// degenerate features as the points and segments they are).
Epeck::FT squared_distance_to_segment(const Point& p, const Point& a, const Point& b) {
  return a == b ? CGAL::squared_distance(p, a) : CGAL::squared_distance(p, Epeck::Segment_3(a, b));
}

bool vertex_face_within_at(const Points& q, const Rational& t, const Epeck::FT& d2) {
  const Point p = at(q[0], q[4], t), a = at(q[1], q[5], t), b = at(q[2], q[6], t), c = at(q[3], q[7], t);
  if (!CGAL::collinear(a, b, c)) return CGAL::squared_distance(p, Epeck::Triangle_3(a, b, c)) <= d2;
  return squared_distance_to_segment(p, a, b) <= d2 || squared_distance_to_segment(p, b, c) <= d2 ||
         squared_distance_to_segment(p, c, a) <= d2;
}

bool edge_edge_within_at(const Points& q, const Rational& t, const Epeck::FT& d2) {
  const Point a0 = at(q[0], q[4], t), a1 = at(q[1], q[5], t), b0 = at(q[2], q[6], t), b1 = at(q[3], q[7], t);
  if (a0 == a1) return squared_distance_to_segment(a0, b0, b1) <= d2;
  if (b0 == b1) return squared_distance_to_segment(b0, a0, a1) <= d2;
  return CGAL::squared_distance(Epeck::Segment_3(a0, a1), Epeck::Segment_3(b0, b1)) <= d2;
}

// At a thickness the earliest contact is where the distance first reaches d:
// checked against CGAL's exact distances at the grid times, on small integer
// motions rich in degeneracies (shared points, parallel and collinear
// features, zero motion).
template <class Ccd, class Within>
void cross_check_thick_small_integer_motions(Ccd ccd, Within within_at) {
  std::mt19937 rng(4242);
  std::uniform_int_distribution<int> coordinate(-2, 2);
  const auto times = grid_times();
  const double d = 0.25;
  const Epeck::FT d2 = exact_ft(Rational(1, 16));
  int colliding = 0, grid_contacts = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Points q;
    for (auto& p : q) p = {double(coordinate(rng)), double(coordinate(rng)), double(coordinate(rng))};
    if (trial % 3 == 0) {
      for (int k = 0; k < 4; ++k) q[4 + k] = q[k];  // no motion
    }
    const ExactCcdResult r = ccd(q, d);
    colliding += r.collides;
    const Rational lo = r.collides ? Rational(r.toi_lo_exact) : Rational(2);
    for (const auto& t : times) {
      if (!within_at(q, t, d2)) continue;
      ++grid_contacts;
      ASSERT_TRUE(r.collides) << "trial " << trial << " t " << t;
      EXPECT_LE(lo, t) << "trial " << trial;
      break;
    }
    if (!r.collides) continue;
    for (const auto& t : times) {
      if (t >= lo) break;
      EXPECT_FALSE(within_at(q, t, d2)) << "trial " << trial << " t " << t;
    }
    if (r.toi_lo_exact == r.toi_hi_exact) EXPECT_TRUE(within_at(q, lo, d2)) << "trial " << trial;
  }
  std::cout << colliding << " of 300 within 1/4, " << grid_contacts << " at a grid time\n";
  EXPECT_GT(colliding, 20);
}

TEST(ExactCcd, AgreesWithCgalDistancesOnSmallIntegerVertexFaceMotionsWithThickness) {
  cross_check_thick_small_integer_motions([](const Points& q, double d) { return exact_vertex_face_ccd(q, d); },
                                          vertex_face_within_at);
}

TEST(ExactCcd, AgreesWithCgalDistancesOnSmallIntegerEdgeEdgeMotionsWithThickness) {
  cross_check_thick_small_integer_motions([](const Points& q, double d) { return exact_edge_edge_ccd(q, d); },
                                          edge_edge_within_at);
}

template <class Ccd, class Contact>
void cross_check_in_plane_motions(Ccd ccd, Contact contact_at) {
  // Everything in the plane z = 0 for the whole step: contacts last a while,
  // so the time just after the reported interval must be in contact.
  std::mt19937 rng(777);
  std::uniform_real_distribution<double> coordinate(-1, 1);
  int colliding = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Points q;
    for (auto& p : q) p = {coordinate(rng), coordinate(rng), 0};
    const ExactCcdResult r = ccd(q, 0x1p-40);
    if (!r.collides) {
      for (int k = 0; k <= 64; ++k) EXPECT_FALSE(contact_at(q, Rational(k, 64))) << "trial " << trial;
      continue;
    }
    ++colliding;
    const Rational lo(r.toi_lo_exact), hi(r.toi_hi_exact);
    const Rational after = lo == 0 ? Rational(0) : CGAL::min(hi + Rational(1, 1 << 30), Rational(1));
    EXPECT_TRUE(contact_at(q, after)) << "trial " << trial;
    for (int k = 0; k <= 64 && Rational(k, 64) < lo; ++k)
      EXPECT_FALSE(contact_at(q, Rational(k, 64))) << "trial " << trial;
    if (lo > 0) {
      EXPECT_FALSE(contact_at(q, CGAL::max(lo - Rational(1, 1 << 30), Rational(0)))) << "trial " << trial;
    }
  }
  std::cout << colliding << " of 300 colliding\n";
  EXPECT_GT(colliding, 20);
}

TEST(ExactCcd, AgreesWithCgalPredicatesOnRandomInPlaneVertexFaceMotions) {
  cross_check_in_plane_motions([](const Points& q, double w) { return exact_vertex_face_ccd(q, 0, w); },
                               vertex_face_contact_at);
}

TEST(ExactCcd, AgreesWithCgalPredicatesOnRandomInPlaneEdgeEdgeMotions) {
  cross_check_in_plane_motions([](const Points& q, double w) { return exact_edge_edge_ccd(q, 0, w); },
                               edge_edge_contact_at);
}

// ---------------------------------------------------------------------------
// The interval filter (ExactMethod::kFiltered) against the rational method.

struct FilterTally {
  int queries = 0, filtered = 0, colliding = 0;
};

/// Both methods on one query given as doubles: the same answer, and time of
/// impact intervals that both hold t* (so they meet) within the width asked.
template <class Ccd>
void expect_filter_agrees(Ccd ccd, const Points& q, double thickness, const std::string& where, FilterTally& tally) {
  const ExactCcdResult filtered = ccd(q, thickness, ExactMethod::kFiltered);
  const ExactCcdResult rational = ccd(q, thickness, ExactMethod::kRational);
  ++tally.queries;
  tally.filtered += filtered.filtered;
  tally.colliding += rational.collides;
  EXPECT_FALSE(rational.filtered) << where;
  if (thickness > 0) EXPECT_FALSE(filtered.filtered) << where << ": the filter takes zero thickness only";
  ASSERT_EQ(filtered.collides, rational.collides) << where;
  if (!rational.collides) return;
  const Rational lo(filtered.toi_lo_exact), hi(filtered.toi_hi_exact);
  const Rational rational_lo(rational.toi_lo_exact), rational_hi(rational.toi_hi_exact);
  EXPECT_LE(lo, rational_hi) << where;
  EXPECT_LE(rational_lo, hi) << where;
  EXPECT_LE(hi - lo, Rational(1e-9)) << where;
  EXPECT_LE(filtered.toi_lo, filtered.toi_hi) << where;
  EXPECT_LE(Rational(filtered.toi_lo), lo) << where;
  EXPECT_GE(Rational(filtered.toi_hi), hi) << where;
}

const auto kVertexFace = [](const Points& q, double d, ExactMethod m) { return exact_vertex_face_ccd(q, d, 1e-9, m); };
const auto kEdgeEdge = [](const Points& q, double d, ExactMethod m) { return exact_edge_edge_ccd(q, d, 1e-9, m); };

TEST(ExactCcdFilter, GivesTheRationalMethodsAnswersOnTheQuerySetAsDoubles) {
  for (const std::string kind : {"vertex-face", "edge-edge"}) {
    FilterTally tally;
    int truth_mismatches = 0;
    const auto queries = all_queries(kind);
    for (std::size_t i = 0; i < queries.size(); i += 2) {
      Points points;
      for (int k = 0; k < 8; ++k)
        points[k] = {exact_double(queries[i].points[k].x), exact_double(queries[i].points[k].y),
                     exact_double(queries[i].points[k].z)};
      const std::string where = kind + " query " + std::to_string(i);
      if (kind == "vertex-face") {
        expect_filter_agrees(kVertexFace, points, 0, where, tally);
        truth_mismatches += exact_vertex_face_ccd(points).collides != queries[i].truth;
      } else {
        expect_filter_agrees(kEdgeEdge, points, 0, where, tally);
        truth_mismatches += exact_edge_edge_ccd(points).collides != queries[i].truth;
      }
    }
    std::cout << kind << ": " << tally.queries << " queries, " << tally.colliding << " colliding, " << tally.filtered
              << " decided by the filter\n";
    EXPECT_EQ(truth_mismatches, 0) << kind;
    // The set is mostly degenerate (exact contacts, shared planes): some
    // queries go to the rational method and some do not.
    EXPECT_GT(tally.filtered, 0) << kind;
    EXPECT_LT(tally.filtered, tally.queries) << kind;
  }
}

/// Random motions around a random triangle or edge: the vertex (or edge b)
/// moves through the plane of the face (or across edge a) near its boundary,
/// inside or outside, while the face's corners wobble: near misses and
/// crossings at irrational times, what a cloth step's hard queries are made of.
Points near_contact(std::mt19937_64& rng, bool edge_edge) {
  std::uniform_real_distribution<double> unit(-1, 1), weight(-0.25, 1), small(-1e-3, 1e-3);
  Points q;
  for (int i = 0; i < 4; ++i) q[i] = {unit(rng), unit(rng), unit(rng)};
  const Vec3 up{small(rng), small(rng), 0.5};
  if (edge_edge) {
    // Edge b crosses the line of edge a at parameter s, inside or outside.
    const double s = weight(rng) * 1.25;
    const Vec3 at = q[0] + s * (q[1] - q[0]);
    const Vec3 half{unit(rng), unit(rng), 0};
    q[2] = at + half + up;
    q[3] = at - half + up;
  } else {
    const double w1 = weight(rng), w2 = weight(rng);
    q[0] = q[1] + w1 * (q[2] - q[1]) + w2 * (q[3] - q[1]) + up;
  }
  const Vec3 push{small(rng), small(rng), -1};
  for (int i = 0; i < 4; ++i) {
    const bool moving = i == 0 || (edge_edge && i >= 2);
    q[i + 4] = q[i] + (moving ? push : Vec3{small(rng), small(rng), small(rng)});
  }
  return q;
}

TEST(ExactCcdFilter, DecidesNearContactsAsTheRationalMethodDoes) {
  std::mt19937_64 rng(2026);
  for (const bool edge_edge : {false, true}) {
    FilterTally tally;
    for (int trial = 0; trial < 300; ++trial) {
      const Points q = near_contact(rng, edge_edge);
      const std::string where = std::string(edge_edge ? "EE" : "VF") + " trial " + std::to_string(trial);
      expect_filter_agrees(edge_edge ? +kEdgeEdge : +kVertexFace, q, 0, where, tally);
      if (trial % 10 == 0) expect_filter_agrees(edge_edge ? +kEdgeEdge : +kVertexFace, q, 0x1p-10, where, tally);
    }
    std::cout << (edge_edge ? "edge-edge" : "vertex-face") << ": " << tally.queries << " near contacts, "
              << tally.colliding << " colliding, " << tally.filtered << " decided by the filter\n";
    // Nothing here is exactly degenerate: every zero-thickness query is the
    // filter's, and there are both answers.
    EXPECT_EQ(tally.filtered, 300);
    EXPECT_GT(tally.colliding, 30);
    EXPECT_LT(tally.colliding, 300);
  }
}

TEST(ExactCcdFilter, LeavesExactDegeneraciesToTheRationalMethod) {
  // A generic crossing at t = 1/3: the filter's.
  const Points crossing = motion({Vec3{0.25, 0.25, 1}, kA, kB, kC}, {Vec3{0.25, 0.25, -2}, kA, kB, kC});
  EXPECT_TRUE(exact_vertex_face_ccd(crossing).filtered);
  expect_toi(exact_vertex_face_ccd(crossing), Rational(1, 3));
  // The vertex crosses the face's plane exactly on edge ab (y = 0) at
  // t = 1/3, which no interval around 1/3 can tell from inside or outside.
  const Points on_edge = motion({Vec3{0.25, 1, 1}, kA, kB, kC}, {Vec3{0.25, -2, -2}, kA, kB, kC});
  EXPECT_FALSE(exact_vertex_face_ccd(on_edge).filtered);
  expect_toi(exact_vertex_face_ccd(on_edge), Rational(1, 3));
  // Coplanar for the whole step: the cubic is the zero polynomial.
  const Points sliding = motion({Vec3{2, 0.25, 0}, kA, kB, kC}, {Vec3{-1, 0.25, 0}, kA, kB, kC});
  EXPECT_FALSE(exact_vertex_face_ccd(sliding).filtered);
  expect_toi(exact_vertex_face_ccd(sliding), Rational(5, 12));
  // A thickness: the rational method.
  EXPECT_FALSE(exact_vertex_face_ccd(crossing, 0.125).filtered);
  // Contact at t = 0 read from the start's signs, and a clear miss.
  EXPECT_TRUE(exact_vertex_face_ccd(motion({Vec3{0.25, 0.25, 0}, kA, kB, kC}, {Vec3{0.25, 0.25, 5}, kA, kB, kC})).filtered);
  const ExactCcdResult miss = exact_edge_edge_ccd(motion({Vec3{0, 0, 1}, Vec3{1, 0, 1}, Vec3{3, -1, 0}, Vec3{3, 1, 0}},
                                                         {Vec3{0, 0, -2}, Vec3{1, 0, -2}, Vec3{3, -1, 0}, Vec3{3, 1, 0}}));
  EXPECT_TRUE(miss.filtered);
  EXPECT_FALSE(miss.collides);
  // Not finite: the rational method names the problem.
  Points bad = crossing;
  bad[2].y = std::nan("");
  EXPECT_THROW(exact_vertex_face_ccd(bad), UsageError);
}

}  // namespace
}  // namespace snag::validate
