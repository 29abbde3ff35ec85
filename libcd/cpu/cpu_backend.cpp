// The CPU back end: the box grid broad phase (or another, cpu_backend.hpp),
// then the conservative floating-point CCD filter and the exact-sign static
// test on all cores, then exact certification of the answers the filter left
// uncertain.
#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>

#include "libcd/core/error.hpp"
#include "libcd/cpu/cpu_backend.hpp"
#include "libcd/narrow_phase/triangle_triangle_frame.hpp"
#include "libcd/narrow_phase/vertex_fans.hpp"
#include "libcd/pipeline/backend.hpp"
#include "libcd/pipeline/event_builder.hpp"

namespace snag {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The pair tests of one range of `pairs` (frame_triangles_intersect), with
// every predicate on the fast path inlined into one loop (flatten): the 2D
// filter's orient2d calls were left out of line. The exact stages stay out
// of line (noinline).
__attribute__((flatten)) void test_pair_range(const std::vector<Triangle>& triangles, const std::vector<Vec3>& x,
                                              const std::vector<TriangleAxes>& axes,
                                              const std::vector<TrianglePair>& pairs, std::size_t begin,
                                              std::size_t end, std::vector<unsigned char>& hit,
                                              StaticTestCounters& counters) {
  for (std::size_t i = begin; i != end; ++i) {
    prefetch_pair_data(triangles, x, pairs, i);
    hit[i] = frame_triangles_intersect(triangles, x, axes, pairs[i], true, counters);
  }
}

class CpuBackend final : public Backend {
 public:
  explicit CpuBackend(const CpuBackendOptions& options) : options_(options) {}
  std::string name() const override { return "cpu"; }

  void bind(const Scene& scene, const BackendSettings& settings) override {
    scene_ = &scene;
    settings_ = settings;
    settings_.ccd.thickness = settings.thickness;
    BroadPhaseSettings broad;
    broad.lambda = settings.lambda;
    broad.thickness = settings.thickness;
    broad.threads = settings.threads;
    ccd_broad_ = make_broad_phase(options_.broad_phase);
    static_broad_ = make_broad_phase(options_.broad_phase);
    ccd_broad_->build(scene, broad);
    BroadPhaseSettings static_settings = broad;
    static_settings.thickness = 0;
    static_broad_->build(scene, static_settings);
    fans_.reset();  // chained on the first intersections() that uses them
    arena_ = std::make_unique<tbb::task_arena>(settings.threads == 0 ? tbb::task_arena::automatic
                                                                     : static_cast<int>(settings.threads));
  }

  void collisions(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, std::vector<Event>& events) override {
    stats_ = PipelineStats{};
    stats_.steps = 1;
    arena_->execute([&] {
      ccd_broad_->detect_ccd(x_t0, x_t1, vf_, ee_);
      stats_.ccd_broad = ccd_broad_->stats();
      const auto start = std::chrono::steady_clock::now();
      const std::size_t first = events.size();
      run_ccd(x_t0, x_t1, vf_, events);
      run_ccd(x_t0, x_t1, ee_, events);
      sort_events_from(events, first, &event_scratch_);
      stats_.narrow.seconds_ccd = seconds_since(start) - stats_.narrow.seconds_certify;
    });
  }

  void intersections(const std::vector<Vec3>& x, std::vector<Event>& events) override {
    stats_ = PipelineStats{};
    stats_.frames = 1;
    arena_->execute([&] {
      // With the test by frame, the pairs that share a vertex whose fan is
      // apart are known not to intersect: the broad phase may leave them out.
      // The fans and the triangles' axes are found while it builds its grid
      // (their time is in the broad phase's registration stage).
      PredicateCounters axes_counters;
      if (options_.frame_static_test) {
        if (!fans_) fans_ = std::make_unique<VertexFans>(scene_->triangles(), scene_->vertex_count());
        static_broad_->detect_static_leaving_out(x, apart_, pairs_, [&] {
          fans_->find_apart(x, apart_);
          compute_triangle_axes(scene_->triangles(), x, axes_, axes_counters);
        });
      } else {
        static_broad_->detect_static(x, pairs_);
      }
      stats_.static_broad = static_broad_->stats();
      const auto start = std::chrono::steady_clock::now();
      hit_.assign(pairs_.size(), 0);
      if (options_.frame_static_test) {
        test_pairs_by_frame(x, axes_counters);
      } else {
        test_pairs_one_by_one(x);
      }
      stats_.narrow.triangle_tests = pairs_.size();
      intersecting_.clear();
      for (std::size_t i = 0; i < pairs_.size(); ++i) {
        if (hit_[i]) intersecting_.push_back(pairs_[i]);
      }
      const auto events_start = std::chrono::steady_clock::now();
      append_intersection_events(*scene_, x, intersecting_, events);
      stats_.narrow.seconds_static_events = seconds_since(events_start);
      stats_.narrow.triangles_intersecting += intersecting_.size();
      stats_.narrow.seconds_static = seconds_since(start);
    });
  }

  const PipelineStats& stats() const override { return stats_; }

 private:
  // The static test by frame (CpuBackendOptions::frame_static_test): each
  // pair on all cores, with the triangles' axes (axes_, found with the fans
  // and counted in `axes_counters`), answers kept by index.
  void test_pairs_by_frame(const std::vector<Vec3>& x, const PredicateCounters& axes_counters) {
    const auto& triangles = scene_->triangles();
    tbb::combinable<StaticTestCounters> counters;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pairs_.size(), 256), [&](const auto& range) {
      test_pair_range(triangles, x, axes_, pairs_, range.begin(), range.end(), hit_, counters.local());
    });
    stats_.narrow.predicate_calls += axes_counters.calls;
    stats_.narrow.predicate_exact += axes_counters.exact;
    counters.combine_each([&](const StaticTestCounters& local) {
      stats_.narrow.predicate_calls += local.plane.calls + local.filter.calls + local.test.calls;
      stats_.narrow.predicate_exact += local.plane.exact + local.filter.exact + local.test.exact;
    });
  }

  // The CUDA back end's static test (its narrow phase's kernel), pair by pair.
  void test_pairs_one_by_one(const std::vector<Vec3>& x) {
    const auto& triangles = scene_->triangles();
    tbb::combinable<PredicateCounters> counters;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pairs_.size(), 1024), [&](const auto& range) {
      PredicateCounters& local = counters.local();
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const Triangle& ta = triangles[pairs_[i].a];
        const Triangle& tb = triangles[pairs_[i].b];
        const Vec3 a[3] = {x[ta[0]], x[ta[1]], x[ta[2]]};
        const Vec3 b[3] = {x[tb[0]], x[tb[1]], x[tb[2]]};
        hit_[i] = triangles_intersect(a, ta.data(), b, tb.data(), &local) ? 1 : 0;
      }
    });
    counters.combine_each([&](const PredicateCounters& local) {
      stats_.narrow.predicate_calls += local.calls;
      stats_.narrow.predicate_exact += local.exact;
    });
  }

  // Tests every candidate on all cores (answers kept by index, so the order
  // does not depend on the thread schedule), then counts, certifies and emits
  // as every back end does (append_collision_events).
  template <typename Candidate>
  void run_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, const std::vector<Candidate>& candidates,
               std::vector<Event>& events) {
    std::vector<CcdResult> results(candidates.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 256), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i)
        results[i] = ccd_test(*scene_, x_t0, x_t1, candidates[i], settings_.ccd);
    });
    CcdHits<Candidate> hits;
    for (std::size_t i = 0; i < results.size(); ++i) {
      if (results[i].answer == CcdAnswer::kNo) continue;
      hits.candidates.push_back(candidates[i]);
      hits.results.push_back(results[i]);
    }
    const double certify_before = stats_.narrow.seconds_certify;
    const auto events_start = std::chrono::steady_clock::now();
    append_collision_events(*scene_, x_t0, x_t1, candidates.size(), hits, settings_.certifier, settings_.thickness,
                            stats_.narrow, events);
    stats_.narrow.seconds_ccd_events +=
        seconds_since(events_start) - (stats_.narrow.seconds_certify - certify_before);
  }

  const CpuBackendOptions options_;
  const Scene* scene_ = nullptr;
  BackendSettings settings_;
  std::unique_ptr<BroadPhase> ccd_broad_, static_broad_;
  std::unique_ptr<tbb::task_arena> arena_;
  std::vector<VertexFaceCandidate> vf_;
  std::vector<EdgeEdgeCandidate> ee_;
  EventScratch event_scratch_;  ///< the sort's room, kept from step to step
  // Static detection's arrays, reused from frame to frame.
  std::vector<TrianglePair> pairs_, intersecting_;
  std::vector<TriangleAxes> axes_;
  std::vector<unsigned char> hit_;
  std::unique_ptr<VertexFans> fans_;   ///< the scene's vertex fans, for the test by frame
  std::vector<unsigned char> apart_;   ///< #V: this frame's apart vertices
  PipelineStats stats_;
};

}  // namespace

std::unique_ptr<Backend> make_cpu_backend(const CpuBackendOptions& options) {
  return std::make_unique<CpuBackend>(options);
}

std::unique_ptr<Backend> make_cpu_backend() { return make_cpu_backend(CpuBackendOptions{}); }

}  // namespace snag
