// Time per triangles_intersect call, on the candidate pairs (overlapping
// bounding boxes) of the cloth-ball frames and on synthetic pair mixes.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "libcd/narrow_phase/triangle_triangle.hpp"
#include "snag/config.hpp"

#if SNAG_HAVE_CGAL
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>
#endif

namespace snag {
namespace {

struct PairSet {
  std::vector<Vec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
};

/// Candidate pairs: closed bounding boxes overlap (sweep along x).
void add_box_overlap_pairs(PairSet& set) {
  struct Box {
    Vec3 lo, hi;
    std::uint32_t face;
  };
  std::vector<Box> boxes;
  for (std::uint32_t f = 0; f < set.triangles.size(); ++f) {
    const auto& t = set.triangles[f];
    const Vec3 p0 = set.positions[t[0]], p1 = set.positions[t[1]], p2 = set.positions[t[2]];
    boxes.push_back({min(min(p0, p1), p2), max(max(p0, p1), p2), f});
  }
  std::sort(boxes.begin(), boxes.end(), [](const Box& a, const Box& b) { return a.lo.x < b.lo.x; });
  for (std::size_t i = 0; i < boxes.size(); ++i)
    for (std::size_t j = i + 1; j < boxes.size() && boxes[j].lo.x <= boxes[i].hi.x; ++j) {
      const Box &a = boxes[i], &b = boxes[j];
      if (a.lo.y <= b.hi.y && b.lo.y <= a.hi.y && a.lo.z <= b.hi.z && b.lo.z <= a.hi.z)
        set.pairs.emplace_back(a.face, b.face);
    }
  std::sort(set.pairs.begin(), set.pairs.end());  // face order: memory-friendly, like a real scan
}

void run_pairs(benchmark::State& state, const PairSet& set) {
  PredicateCounters counters;
  std::size_t intersecting = 0;
  for (auto _ : state) {
    for (const auto& [fa, fb] : set.pairs) {
      const auto &ta = set.triangles[fa], &tb = set.triangles[fb];
      const Vec3 a[3] = {set.positions[ta[0]], set.positions[ta[1]], set.positions[ta[2]]};
      const Vec3 b[3] = {set.positions[tb[0]], set.positions[tb[1]], set.positions[tb[2]]};
      intersecting += triangles_intersect(a, ta.data(), b, tb.data(), &counters);
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(set.pairs.size()));
  state.counters["pairs"] = double(set.pairs.size());
  state.counters["intersecting"] = double(intersecting) / double(state.iterations());
  state.counters["exact_fraction"] = double(counters.exact) / double(std::max(1ull, counters.calls));
}

#if SNAG_HAVE_CGAL
void BM_ClothBallCandidatePairs(benchmark::State& state, const std::string& name) {
  static std::vector<PairSet> cache(2);
  PairSet& set = cache[name == "cloth_ball92.ply" ? 0 : 1];
  if (set.pairs.empty()) {
    std::vector<CGAL::Epick::Point_3> points;
    std::vector<std::vector<std::size_t>> polygons;
    if (!CGAL::IO::read_polygon_soup(std::string(SNAG_SHARED_DATA_DIR) + "/meshes/" + name, points, polygons)) {
      state.SkipWithError("cannot read the mesh");
      return;
    }
    for (const auto& p : points) set.positions.push_back({p.x(), p.y(), p.z()});
    for (const auto& polygon : polygons)
      set.triangles.push_back({std::uint32_t(polygon[0]), std::uint32_t(polygon[1]), std::uint32_t(polygon[2])});
    add_box_overlap_pairs(set);
  }
  run_pairs(state, set);
}
BENCHMARK_CAPTURE(BM_ClothBallCandidatePairs, frame92, std::string("cloth_ball92.ply"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ClothBallCandidatePairs, frame93, std::string("cloth_ball93.ply"))->Unit(benchmark::kMillisecond);
#endif

/// Unrelated random triangles of size about 1 in a box of side `extent`: a
/// large extent gives mostly plane-side rejections, a small one crossings.
void BM_RandomUnrelatedPairs(benchmark::State& state) {
  const double extent = double(state.range(0)) / 4.0;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> corner(0, extent), offset(-0.5, 0.5);
  PairSet set;
  for (std::uint32_t t = 0; t < 20000; ++t) {
    const Vec3 c{corner(rng), corner(rng), corner(rng)};
    for (int k = 0; k < 3; ++k) set.positions.push_back(c + Vec3{offset(rng), offset(rng), offset(rng)});
    set.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  for (std::uint32_t t = 0; t + 1 < 20000; t += 2) set.pairs.emplace_back(t, t + 1);
  run_pairs(state, set);
}
BENCHMARK(BM_RandomUnrelatedPairs)->Arg(1)->Arg(4)->Arg(16);

}  // namespace
}  // namespace snag

BENCHMARK_MAIN();
