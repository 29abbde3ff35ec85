#include "libcd/broad_phase/brute_force.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>

#include "libcd/broad_phase/broad_phase_support.hpp"
#include "libcd/broad_phase/feature_stage.hpp"
#include "libcd/core/error.hpp"

namespace snag {

using namespace broad_phase_support;

void BruteForceBroadPhase::build(const Scene& scene, const BroadPhaseSettings& settings) {
  if (!(settings.thickness >= 0.0)) throw UsageError("broad phase: thickness must be >= 0");
  scene_ = &scene;
  settings_ = settings;
  tbb::task_arena arena(arena_threads(settings.threads));
  arena.execute([&] { reps_ = assign_representative_triangles(scene); });
}

std::vector<TrianglePair> BruteForceBroadPhase::triangle_pairs(const std::vector<Vec3>& x_t0,
                                                               const std::vector<Vec3>& x_t1) {
  stats_ = BroadPhaseStats{};
  const auto start = Clock::now();
  compute_primitive_bounds(*scene_, x_t0, x_t1, settings_.thickness, bounds_);
  stats_.seconds_bounds = seconds_since(start);
  const auto t = Clock::now();
  const std::size_t n = scene_->triangle_count();
  stats_.root_triangles = n;
  std::vector<std::vector<TrianglePair>> rows(n);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t a) {
    for (std::size_t b = a + 1; b < n; ++b)
      if (dop_overlap(bounds_.triangles[a], bounds_.triangles[b]))
        rows[a].push_back({static_cast<Index>(a), static_cast<Index>(b)});
  });
  std::vector<TrianglePair> pairs;
  for (auto& row : rows) pairs.insert(pairs.end(), row.begin(), row.end());
  stats_.tests = n < 2 ? 0 : n * (n - 1) / 2;
  stats_.tests_after_control_bits = stats_.tests;
  stats_.culled_by_dop = stats_.tests - pairs.size();
  stats_.triangle_pairs = pairs.size();
  stats_.memory_bytes = pairs.capacity() * sizeof(TrianglePair) +
                        (bounds_.triangles.size() + bounds_.edges.size() + bounds_.vertices.size()) * sizeof(Dop18);
  stats_.seconds_pairs = seconds_since(t);
  stats_.seconds_total = seconds_since(start);
  return pairs;
}

void BruteForceBroadPhase::detect_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                      std::vector<VertexFaceCandidate>& vf, std::vector<EdgeEdgeCandidate>& ee) {
  check_positions(scene_, x_t0, "x_t0");
  check_positions(scene_, x_t1, "x_t1");
  tbb::task_arena arena(arena_threads(settings_.threads));
  arena.execute([&] {
    const auto start = Clock::now();
    const std::vector<TrianglePair> pairs = triangle_pairs(x_t0, x_t1);
    feature_stage(*scene_, reps_, bounds_, pairs, x_t0, x_t1, settings_, vf, ee, stats_);
    stats_.seconds_total = seconds_since(start);
  });
}

void BruteForceBroadPhase::detect_static(const std::vector<Vec3>& x, std::vector<TrianglePair>& pairs) {
  check_positions(scene_, x, "x");
  tbb::task_arena arena(arena_threads(settings_.threads));
  arena.execute([&] {
    pairs = triangle_pairs(x, x);
    stats_.candidates = pairs.size();
  });
}

std::vector<TrianglePair> brute_force_leaf_triangle_pairs(const std::vector<Leaf>& leaves,
                                                          const std::vector<Dop18>& root_dops) {
  const std::size_t n = leaves.size();
  std::vector<std::vector<std::uint64_t>> rows(n);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
    const Leaf& a = leaves[i];
    for (std::size_t j = i + 1; j < n; ++j) {
      const Leaf& b = leaves[j];
      if (a.triangle.root == b.triangle.root || !slots_nested(a.triangle, b.triangle)) continue;
      if (!dop_overlap(a.dop, b.dop)) continue;
      if (!dop_overlap(root_dops[a.triangle.root], root_dops[b.triangle.root])) continue;
      rows[i].push_back(pack_pair(a.triangle.root, b.triangle.root));
    }
  });
  std::vector<std::uint64_t> keys;
  for (auto& row : rows) keys.insert(keys.end(), row.begin(), row.end());
  tbb::parallel_sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<TrianglePair> pairs(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k) pairs[k] = unpack_pair(keys[k]);
  return pairs;
}

}  // namespace snag
