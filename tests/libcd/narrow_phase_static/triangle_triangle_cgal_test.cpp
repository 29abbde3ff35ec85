// triangles_intersect against CGAL, pair for pair:
//   - on every reference mesh and on crumpled grids, against
//     CGAL::Polygon_mesh_processing::self_intersections on a Surface_mesh with
//     the EPICK kernel (our side enumerates candidates with an AABB sweep);
//   - on random triangle soups over tiny integer grids (many coplanar,
//     touching and shared-vertex cases), against CGAL's own per-pair rules
//     (do_faces_intersect in self_intersections.h) evaluated with EPICK, and
//     the CPU back end's per-frame form (frame_triangles_intersect, with and
//     without its filter) against triangles_intersect there.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "libcd/narrow_phase/triangle_triangle.hpp"
#include "libcd/narrow_phase/triangle_triangle_frame.hpp"

namespace snag {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;
using FacePair = std::pair<std::uint32_t, std::uint32_t>;

struct TriangleSoup {
  std::vector<Vec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// What CGAL reports: intersecting pairs (smaller face first, sorted) and the
/// degenerate faces it reports as (f, f).
struct CgalReport {
  std::vector<FacePair> pairs;
  std::vector<std::uint32_t> degenerate;
};

Mesh mesh_from_soup(std::vector<Point> points, std::vector<std::vector<std::size_t>> polygons) {
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) PMP::orient_polygon_soup(points, polygons);
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  return mesh;
}

Mesh read_mesh(const std::string& path) {
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  if (!CGAL::IO::read_polygon_soup(path, points, polygons)) throw std::runtime_error("cannot read " + path);
  return mesh_from_soup(std::move(points), std::move(polygons));
}

/// The mesh's own vertex and face numbering, so that both sides agree on ids.
TriangleSoup soup_of(const Mesh& mesh) {
  TriangleSoup soup;
  for (Mesh::Vertex_index v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    EXPECT_EQ(std::size_t(v), soup.positions.size());
    soup.positions.push_back({p.x(), p.y(), p.z()});
  }
  for (Mesh::Face_index f : mesh.faces()) {
    EXPECT_EQ(std::size_t(f), soup.triangles.size());
    std::array<std::uint32_t, 3> ids{};
    int k = 0;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) ids[k++] = std::uint32_t(v);
    EXPECT_EQ(k, 3);
    soup.triangles.push_back(ids);
  }
  return soup;
}

CgalReport cgal_self_intersections(const Mesh& mesh) {
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> found;
  PMP::self_intersections<CGAL::Parallel_if_available_tag>(mesh, std::back_inserter(found));
  CgalReport report;
  for (const auto& [f, g] : found) {
    const std::uint32_t a = std::uint32_t(f), b = std::uint32_t(g);
    if (a == b)
      report.degenerate.push_back(a);
    else
      report.pairs.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(report.pairs.begin(), report.pairs.end());
  std::sort(report.degenerate.begin(), report.degenerate.end());
  return report;
}

struct OurReport {
  std::vector<FacePair> pairs;
  std::vector<std::uint32_t> degenerate;
  std::size_t candidate_pairs = 0;
  PredicateCounters counters;
  double seconds_in_tests = 0;
};

/// All pairs of triangles with overlapping closed bounding boxes (a sweep
/// along x), tested with triangles_separated_in_projection, then
/// triangles_intersect.
OurReport our_self_intersections(const TriangleSoup& soup) {
  struct Box {
    Vec3 lo, hi;
    std::uint32_t face;
  };
  OurReport report;
  std::vector<Box> boxes;
  for (std::uint32_t f = 0; f < soup.triangles.size(); ++f) {
    const auto& t = soup.triangles[f];
    const Vec3 p0 = soup.positions[t[0]], p1 = soup.positions[t[1]], p2 = soup.positions[t[2]];
    if (is_degenerate_triangle(p0, p1, p2)) report.degenerate.push_back(f);
    boxes.push_back({min(min(p0, p1), p2), max(max(p0, p1), p2), f});
  }
  std::sort(boxes.begin(), boxes.end(), [](const Box& a, const Box& b) { return a.lo.x < b.lo.x; });
  std::vector<std::pair<std::uint32_t, std::uint32_t>> candidates;
  for (std::size_t i = 0; i < boxes.size(); ++i)
    for (std::size_t j = i + 1; j < boxes.size() && boxes[j].lo.x <= boxes[i].hi.x; ++j) {
      const Box &a = boxes[i], &b = boxes[j];
      if (a.lo.y <= b.hi.y && b.lo.y <= a.hi.y && a.lo.z <= b.hi.z && b.lo.z <= a.hi.z)
        candidates.emplace_back(a.face, b.face);
    }
  report.candidate_pairs = candidates.size();
  const auto start = std::chrono::steady_clock::now();
  for (const auto& [fa, fb] : candidates) {
    const auto &ta = soup.triangles[fa], &tb = soup.triangles[fb];
    const Vec3 a[3] = {soup.positions[ta[0]], soup.positions[ta[1]], soup.positions[ta[2]]};
    const Vec3 b[3] = {soup.positions[tb[0]], soup.positions[tb[1]], soup.positions[tb[2]]};
    // As the CPU back end tests: the exact-sign 2D filter first.
    if (!triangles_separated_in_projection(a, ta.data(), b, tb.data(), &report.counters) &&
        triangles_intersect(a, ta.data(), b, tb.data(), &report.counters))
      report.pairs.emplace_back(std::min(fa, fb), std::max(fa, fb));
  }
  report.seconds_in_tests = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::sort(report.pairs.begin(), report.pairs.end());
  return report;
}

void expect_same_as_cgal(const Mesh& mesh, const std::string& name) {
  const TriangleSoup soup = soup_of(mesh);
  for (const Vec3& p : soup.positions) ASSERT_TRUE(is_in_exact_range(p));
  const CgalReport cgal = cgal_self_intersections(mesh);
  const OurReport ours = our_self_intersections(soup);
  std::cout << "[" << name << "] vertices " << soup.positions.size() << ", faces " << soup.triangles.size()
            << ", candidate pairs " << ours.candidate_pairs
            << ", intersecting pairs ours " << ours.pairs.size() << " / CGAL " << cgal.pairs.size()
            << ", degenerate faces ours " << ours.degenerate.size() << " / CGAL " << cgal.degenerate.size()
            << ", predicates " << ours.counters.calls << " (exact stage " << ours.counters.exact << "), "
            << (ours.candidate_pairs ? 1e9 * ours.seconds_in_tests / double(ours.candidate_pairs) : 0.0)
            << " ns per pair test\n";
  EXPECT_EQ(ours.degenerate, cgal.degenerate) << name;
  // Pairs with a degenerate face are ours to skip as well: triangles_intersect
  // returns false for them, as CGAL never tests them.
  std::vector<FacePair> only_ours, only_cgal;
  std::set_difference(ours.pairs.begin(), ours.pairs.end(), cgal.pairs.begin(), cgal.pairs.end(),
                      std::back_inserter(only_ours));
  std::set_difference(cgal.pairs.begin(), cgal.pairs.end(), ours.pairs.begin(), ours.pairs.end(),
                      std::back_inserter(only_cgal));
  EXPECT_TRUE(only_ours.empty()) << name << ": " << only_ours.size() << " pairs only we report, first ("
                                 << (only_ours.empty() ? 0 : only_ours[0].first) << ", "
                                 << (only_ours.empty() ? 0 : only_ours[0].second) << ")";
  EXPECT_TRUE(only_cgal.empty()) << name << ": " << only_cgal.size() << " pairs only CGAL reports, first ("
                                 << (only_cgal.empty() ? 0 : only_cgal[0].first) << ", "
                                 << (only_cgal.empty() ? 0 : only_cgal[0].second) << ")";
}

const std::string kMeshes = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/";

TEST(TrianglesIntersectVsCgal, MatchesSelfIntersectionsOnSmallReferenceMeshes) {
  for (const char* name : {"cube.ply", "bunny.ply", "two-cubes-far.ply", "two-cubes-close.ply",
                           "two-cubes-intersecting.ply", "thick-cloth/t0.ply", "thick-cloth/t1.ply"})
    expect_same_as_cgal(read_mesh(kMeshes + name), name);
}

TEST(TrianglesIntersectVsCgal, MatchesSelfIntersectionsOnClothBallFrames) {
  for (const char* name : {"cloth_ball92.ply", "cloth_ball93.ply"}) expect_same_as_cgal(read_mesh(kMeshes + name), name);
}

TEST(TrianglesIntersectVsCgal, MatchesSelfIntersectionsOnCrumpledIntegerGrids) {
  // A grid mesh whose vertices jump by whole units: folds, flat coplanar
  // neighbours, overlaps, degenerate faces and exact touching everywhere.
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> jump(-1, 1);
  for (int trial = 0; trial < 4; ++trial) {
    const int n = 24;
    std::vector<Point> points;
    std::vector<std::vector<std::size_t>> polygons;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        points.emplace_back(i + jump(rng) * (trial % 2 ? 1.0 : 0.5), j + jump(rng), jump(rng) * 0.5);
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) {
        const std::size_t v = std::size_t(j) * n + i;
        polygons.push_back({v, v + 1, v + n + 1});
        polygons.push_back({v, v + n + 1, v + n});
      }
    expect_same_as_cgal(mesh_from_soup(points, polygons), "crumpled grid " + std::to_string(trial));
  }
}

/// CGAL's per-pair rules (self_intersections.h, do_faces_intersect) with
/// EPICK: the oracle for arbitrary pairs, shared ids included.
bool cgal_rule(const Vec3 a[3], const std::uint32_t a_ids[3], const Vec3 b[3], const std::uint32_t b_ids[3]) {
  auto point = [](Vec3 p) { return Point(p.x, p.y, p.z); };
  const Kernel::Triangle_3 ta(point(a[0]), point(a[1]), point(a[2]));
  const Kernel::Triangle_3 tb(point(b[0]), point(b[1]), point(b[2]));
  int shared = 0, ia = -1, ib = -1;
  bool a_shared[3] = {}, b_shared[3] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a_ids[i] == b_ids[j]) {
        ++shared;
        ia = i;
        ib = j;
        a_shared[i] = b_shared[j] = true;
      }
  if (shared == 2) {
    int ra = 0, sb = 0;
    for (int i = 0; i < 3; ++i) {
      if (!a_shared[i]) ra = i;
      if (!b_shared[i]) sb = i;
    }
    const Point p = point(a[(ra + 1) % 3]), q = point(a[(ra + 2) % 3]), r = point(a[ra]), s = point(b[sb]);
    return CGAL::coplanar(p, q, r, s) && CGAL::coplanar_orientation(p, q, r, s) == CGAL::POSITIVE;
  }
  if (shared == 1) {
    const Kernel::Segment_3 sa(point(a[(ia + 1) % 3]), point(a[(ia + 2) % 3]));
    const Kernel::Segment_3 sb(point(b[(ib + 1) % 3]), point(b[(ib + 2) % 3]));
    return CGAL::do_intersect(ta, sb) || CGAL::do_intersect(tb, sa);
  }
  return CGAL::do_intersect(ta, tb);
}

TEST(TrianglesIntersectVsCgal, MatchesCgalRulesOnRandomSoupsWithSharedAndCoincidentVertices) {
  std::mt19937_64 rng(11);
  std::size_t intersecting = 0, tested = 0, filtered = 0;
  PredicateCounters counters;
  StaticTestCounters frame_counters;
  for (int trial = 0; trial < 6; ++trial) {
    // 40 grid points (0..2 per axis, some scaled by 2^-30 or nudged by an
    // ulp), then 12 extra ids at the positions of earlier ones.
    std::uniform_int_distribution<int> coord(0, 2);
    std::vector<Vec3> positions;
    for (int v = 0; v < 40; ++v) {
      Vec3 p{double(coord(rng)), double(coord(rng)), double(coord(rng))};
      if (trial >= 2) p = p * std::ldexp(1.0, -30);
      // One ulp up (an in-range tiny value instead of a subnormal at zero).
      if (trial >= 4 && v % 3 == 0) p.z = p.z == 0.0 ? std::ldexp(1.0, -200) : std::nextafter(p.z, 1.0);
      positions.push_back(p);
    }
    for (int v = 0; v < 12; ++v) positions.push_back(positions[std::size_t(v) * 3]);
    std::uniform_int_distribution<std::uint32_t> pick(0, std::uint32_t(positions.size() - 1));
    std::vector<std::array<std::uint32_t, 3>> triangles;
    while (triangles.size() < 220) {
      const std::array<std::uint32_t, 3> t{pick(rng), pick(rng), pick(rng)};
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      triangles.push_back(t);
    }
    // The CPU back end's per-frame form (triangle_triangle_frame.hpp) must
    // give the same answer for every pair, with and without its filter.
    std::vector<TriangleAxes> axes;
    compute_triangle_axes(triangles, positions, axes, frame_counters.axes);
    for (std::size_t i = 0; i < triangles.size(); ++i)
      for (std::size_t j = i + 1; j < triangles.size(); ++j) {
        const auto &ta = triangles[i], &tb = triangles[j];
        const Vec3 a[3] = {positions[ta[0]], positions[ta[1]], positions[ta[2]]};
        const Vec3 b[3] = {positions[tb[0]], positions[tb[1]], positions[tb[2]]};
        TriangleAdjacency adjacency;
        for (const Vec3& p : a) ASSERT_TRUE(is_in_exact_range(p));
        const bool ours = triangles_intersect(a, ta.data(), b, tb.data(), &counters, &adjacency);
        const TrianglePair pair{Index(i), Index(j)};
        ASSERT_EQ(frame_triangles_intersect(triangles, positions, axes, pair, true, frame_counters), ours)
            << "trial " << trial << " faces " << i << ", " << j;
        ASSERT_EQ(frame_triangles_intersect(triangles, positions, axes, pair, false, frame_counters), ours)
            << "trial " << trial << " faces " << i << ", " << j;
        const bool a_degenerate = CGAL::collinear(Point(a[0].x, a[0].y, a[0].z), Point(a[1].x, a[1].y, a[1].z),
                                                  Point(a[2].x, a[2].y, a[2].z));
        const bool b_degenerate = CGAL::collinear(Point(b[0].x, b[0].y, b[0].z), Point(b[1].x, b[1].y, b[1].z),
                                                  Point(b[2].x, b[2].y, b[2].z));
        if (a_degenerate || b_degenerate) {
          ASSERT_EQ(adjacency, TriangleAdjacency::degenerate);
          ASSERT_FALSE(ours);
          continue;
        }
        ASSERT_NE(adjacency, TriangleAdjacency::degenerate);
        if (adjacency == TriangleAdjacency::same_vertices) {
          ASSERT_TRUE(ours);
          continue;
        }
        ++tested;
        intersecting += ours;
        const bool cgal = cgal_rule(a, ta.data(), b, tb.data());
        ASSERT_EQ(ours, cgal) << "trial " << trial << " faces " << i << ", " << j << " adjacency "
                              << to_string(adjacency);
        if (triangles_separated_in_projection(a, ta.data(), b, tb.data())) {
          ++filtered;
          ASSERT_FALSE(cgal) << "the filter rejected an intersecting pair: trial " << trial << " faces " << i << ", "
                             << j << " adjacency " << to_string(adjacency);
        }
      }
  }
  std::cout << "[random soups] pairs " << tested << ", intersecting " << intersecting << ", rejected by the 2D filter "
            << filtered << ", predicates " << counters.calls << " (exact stage " << counters.exact << ")\n";
  EXPECT_GT(filtered, tested / 10);
  // Both early exits of the per-frame form ran (counts of both calls per pair).
  EXPECT_GT(frame_counters.decided_by_filter, tested / 50);
  EXPECT_GT(frame_counters.decided_by_plane, tested / 20);
  EXPECT_GT(intersecting, tested / 10);
  EXPECT_LT(intersecting, tested);
}

}  // namespace
}  // namespace snag
