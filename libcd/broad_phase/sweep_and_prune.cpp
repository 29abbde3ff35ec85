#include "libcd/broad_phase/sweep_and_prune.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>

#include <algorithm>

#include "libcd/broad_phase/broad_phase_support.hpp"
#include "libcd/broad_phase/feature_stage.hpp"
#include "libcd/core/error.hpp"

namespace snag {

namespace {

using namespace broad_phase_support;

/// Sweeps per output block: fixed, so that the blocks (and the output
/// order before the sort) do not depend on the thread count.
constexpr std::size_t kBlock = 512;

}  // namespace

void SweepAndPruneBroadPhase::build(const Scene& scene, const BroadPhaseSettings& settings) {
  if (!(settings.thickness >= 0.0)) throw UsageError("broad phase: thickness must be >= 0");
  scene_ = &scene;
  settings_ = settings;
  arena_ = std::make_unique<tbb::task_arena>(arena_threads(settings.threads));
  arena_->execute([&] { reps_ = assign_representative_triangles(scene); });
}

void SweepAndPruneBroadPhase::sort_boxes(const std::vector<Dop18>& dops, const std::function<void()>& find_apart) {
  const std::size_t n = dops.size();
  // The axis along which the boxes' mean extent is the smallest share of
  // the scene's extent.
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300}, extent[3] = {0, 0, 0};
  for (const Dop18& d : dops) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], d.lo[a]);
      hi[a] = std::max(hi[a], d.hi[a]);
      extent[a] += d.hi[a] - d.lo[a];
    }
  }
  axis_ = 0;
  double best = -1;
  for (int a = 0; a < 3; ++a) {
    const double spread = n ? (hi[a] - lo[a]) / (extent[a] / double(n) + 1e-300) : 0.0;
    if (spread > best) {
      best = spread;
      axis_ = a;
    }
  }
  const int other1 = (axis_ + 1) % 3, other2 = (axis_ + 2) % 3;
  keys_.resize(n);
  sorted_.resize(n);
  const auto sort = [&] {
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t t) { keys_[t] = {dops[t].lo[axis_], Index(t)}; });
    tbb::parallel_sort(keys_.begin(), keys_.end());
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
      const Index t = keys_[i].second;
      const Dop18& d = dops[t];
      sorted_[i] = {d.lo[axis_], d.hi[axis_], d.lo[other1], d.hi[other1], d.lo[other2], d.hi[other2], t};
    });
  };
  if (find_apart)
    tbb::parallel_invoke(sort, find_apart);
  else
    sort();
}

void SweepAndPruneBroadPhase::sweep(const std::vector<Dop18>& dops, std::vector<TrianglePair>& pairs,
                                    const unsigned char* apart) {
  const std::size_t n = sorted_.size();
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  block_pairs_.resize(blocks);
  block_tests_.assign(blocks, 0);
  block_culled_.assign(blocks, 0);
  block_left_out_.assign(blocks, 0);
  const auto& triangles = scene_->triangles();
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
    std::vector<TrianglePair>& out = block_pairs_[block];
    out.clear();
    std::size_t tests = 0, culled = 0, left_out = 0;
    for (std::size_t i = block * kBlock; i < std::min(n, (block + 1) * kBlock); ++i) {
      const SortedBox a = sorted_[i];
      const Triangle& ta = triangles[a.triangle];
      for (std::size_t j = i + 1; j < n && sorted_[j].lo <= a.hi; ++j) {
        const SortedBox& b = sorted_[j];
        ++tests;
        if (b.lo1 > a.hi1 || b.hi1 < a.lo1 || b.lo2 > a.hi2 || b.hi2 < a.lo2) continue;
        if (apart) {
          const Triangle& tb = triangles[b.triangle];
          bool shares = false;
          for (int u = 0; u < 3; ++u)
            shares |= apart[ta[u]] && (tb[0] == ta[u] || tb[1] == ta[u] || tb[2] == ta[u]);
          if (shares) {
            ++left_out;
            continue;
          }
        }
        if (dop_overlap(dops[a.triangle], dops[b.triangle]))
          out.push_back({std::min(a.triangle, b.triangle), std::max(a.triangle, b.triangle)});
        else
          ++culled;
      }
    }
    block_tests_[block] = tests;
    block_culled_[block] = culled;
    block_left_out_[block] = left_out;
  });
  std::size_t total = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    total += block_pairs_[b].size();
    stats_.tests += block_tests_[b];
    stats_.culled_by_dop += block_culled_[b];
    stats_.left_out_apart += block_left_out_[b];
  }
  pairs.clear();
  pairs.reserve(total);
  for (const auto& block : block_pairs_) pairs.insert(pairs.end(), block.begin(), block.end());
  tbb::parallel_sort(pairs.begin(), pairs.end());
  stats_.root_triangles = n;
  stats_.leaf_triangles = n;
  stats_.tests_after_control_bits = stats_.tests;
  stats_.triangle_pairs = pairs.size();
  stats_.memory_bytes = dops.size() * sizeof(Dop18) + keys_.capacity() * sizeof(keys_[0]) +
                        sorted_.capacity() * sizeof(SortedBox) + pairs.capacity() * sizeof(TrianglePair);
}

void SweepAndPruneBroadPhase::detect_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                         std::vector<VertexFaceCandidate>& vf, std::vector<EdgeEdgeCandidate>& ee) {
  check_positions(scene_, x_t0, "x_t0");
  check_positions(scene_, x_t1, "x_t1");
  arena_->execute([&] {
    stats_ = BroadPhaseStats{};
    const auto start = Clock::now();
    compute_primitive_bounds(*scene_, x_t0, x_t1, settings_.thickness, bounds_);
    stats_.seconds_bounds = seconds_since(start);
    const auto sort_start = Clock::now();
    sort_boxes(bounds_.triangles, {});
    stats_.seconds_registration = seconds_since(sort_start);
    const auto sweep_start = Clock::now();
    sweep(bounds_.triangles, pairs_, nullptr);
    stats_.seconds_pairs = seconds_since(sweep_start);
    feature_stage(*scene_, reps_, bounds_, pairs_, x_t0, x_t1, settings_, vf, ee, stats_);
    stats_.memory_bytes += (bounds_.edges.size() + bounds_.vertices.size()) * sizeof(Dop18);
    stats_.seconds_total = seconds_since(start);
  });
}

void SweepAndPruneBroadPhase::detect_static(const std::vector<Vec3>& x, std::vector<TrianglePair>& pairs) {
  static_pairs(x, nullptr, {}, pairs);
}

void SweepAndPruneBroadPhase::detect_static_leaving_out(const std::vector<Vec3>& x,
                                                        const std::vector<unsigned char>& apart,
                                                        std::vector<TrianglePair>& pairs,
                                                        const std::function<void()>& find_apart) {
  static_pairs(x, &apart, find_apart, pairs);
}

void SweepAndPruneBroadPhase::static_pairs(const std::vector<Vec3>& x, const std::vector<unsigned char>* apart,
                                           const std::function<void()>& find_apart,
                                           std::vector<TrianglePair>& pairs) {
  check_positions(scene_, x, "x");
  arena_->execute([&] {
    stats_ = BroadPhaseStats{};
    const auto start = Clock::now();
    compute_static_triangle_dops(*scene_, x, settings_.thickness, static_dops_);
    stats_.seconds_bounds = seconds_since(start);
    const auto sort_start = Clock::now();
    sort_boxes(static_dops_, find_apart);
    stats_.seconds_registration = seconds_since(sort_start);
    if (apart && apart->size() != x.size()) throw UsageError("broad phase: apart flags must have one per vertex");
    const auto sweep_start = Clock::now();
    sweep(static_dops_, pairs, apart ? apart->data() : nullptr);
    stats_.seconds_pairs = seconds_since(sweep_start);
    stats_.candidates = pairs.size();
    stats_.seconds_total = seconds_since(start);
  });
}

}  // namespace snag
