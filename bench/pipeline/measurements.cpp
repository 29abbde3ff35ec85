#include "bench/pipeline/measurements.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <functional>
#include <iterator>
#include <memory>
#include <vector>

#include "bench/pipeline/cgal_self_intersections.hpp"
#include "bench/pipeline/process_cpu_time.hpp"
#include "libcd/cpu/cpu_backend.hpp"
#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/triangle_triangle_frame.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "libcd/narrow_phase/vertex_fans.hpp"
#include "libcd/pipeline/backend.hpp"
#include "validate/exact_ccd.hpp"
#include "validate/exact_certifier.hpp"

namespace snag::bench {

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

/// Runs `pass` once to warm up, then `settings.repeat` times; returns each
/// timed pass's result. When the warm-up alone took longer than
/// `settings.slow_pass_seconds`, the warm-up is the only pass reported (the
/// JSON's "passes" says how many the medians are of).
template <typename Result>
std::vector<Result> timed_passes(const MeasureSettings& settings, const std::function<Result()>& pass) {
  const auto start = Clock::now();
  Result warm_up = pass();
  if (seconds_since(start) > settings.slow_pass_seconds) return {warm_up};
  std::vector<Result> results;
  for (int k = 0; k < settings.repeat; ++k) results.push_back(pass());
  return results;
}

BroadPhaseSettings broad_settings(const MeasureSettings& settings, bool ccd) {
  BroadPhaseSettings broad;
  broad.lambda = settings.lambda;
  broad.thickness = ccd ? settings.thickness : 0;
  broad.threads = settings.threads;
  return broad;
}

BackendSettings backend_settings(const MeasureSettings& settings, const Certifier* certifier) {
  BackendSettings backend;
  backend.lambda = settings.lambda;
  backend.thickness = settings.thickness;
  backend.threads = settings.threads;
  backend.certifier = certifier;
  return backend;
}

json broad_counts(const BroadPhaseStats& s) {
  return {{"cell_size", s.cell_size},
          {"cells_used", s.cells_used},
          {"root_triangles", s.root_triangles},
          {"triangles_subdivided", s.triangles_subdivided},
          {"time_halvings", s.time_halvings},
          {"leaf_triangles", s.leaf_triangles},
          {"registrations", s.registrations},
          {"duplicate_registrations_removed", s.duplicate_registrations_removed},
          {"tests", s.tests},
          {"tests_after_control_bits", s.tests_after_control_bits},
          {"duplicate_root_pair_tests", s.duplicate_root_pair_tests},
          {"duplicate_root_pair_percent", s.tests ? 100.0 * double(s.duplicate_root_pair_tests) / double(s.tests) : 0.0},
          {"culled_by_dop", s.culled_by_dop},
          {"triangle_pairs", s.triangle_pairs},
          {"separated_triangle_pairs", s.separated_triangle_pairs},
          {"vf_candidates", s.vf_after_culling},
          {"ee_candidates", s.ee_after_culling},
          {"candidates", s.candidates},
          {"memory_bytes", s.memory_bytes}};
}

json stage_seconds(const BroadPhaseStats& s) {
  return {{"bounds", s.seconds_bounds},         {"subdivision", s.seconds_subdivision},
          {"registration", s.seconds_registration}, {"pairs", s.seconds_pairs},
          {"features", s.seconds_features},     {"total", s.seconds_total}};
}

/// How the static triangle pairs of every frame were decided, as the CPU
/// back end decides them: left out by the broad phase because they share an
/// apart vertex (vertex_fans.hpp), or tested in its order
/// (triangle_triangle_frame.hpp) and decided by the plane-side rejection, the
/// 2D exact-sign filter or the exact-sign test after them; and how often an
/// orientation predicate of each (and of the per-triangle axes) needed its
/// exact stage (the fans' predicates are not counted).
json static_filter_counts(const BenchScene& bench) {
  auto phase = make_broad_phase(BroadPhaseMethod::kBoxGrid);
  phase->build(bench.scene, BroadPhaseSettings{});
  const auto& triangles = bench.scene.triangles();
  const VertexFans fans(triangles, bench.scene.vertex_count());
  std::vector<TrianglePair> pairs;
  std::vector<TriangleAxes> axes;
  std::vector<unsigned char> apart;
  StaticTestCounters counters;
  std::size_t all_pairs = 0;
  for (const std::vector<Vec3>& x : bench.frames) {
    phase->detect_static(x, pairs);
    all_pairs += pairs.size();
    fans.find_apart(x, apart);
    phase->detect_static_leaving_out(x, apart, pairs);
    compute_triangle_axes(triangles, x, axes, counters.axes);
    for (const TrianglePair& p : pairs) frame_triangles_intersect(triangles, x, axes, p, true, counters);
  }
  return {{"pairs", all_pairs},
          {"tested", counters.pairs},
          {"fan_vertices", fans.chained_count()},
          {"decided_by_plane", counters.decided_by_plane},
          {"plane_predicates", counters.plane.calls},
          {"plane_predicates_exact", counters.plane.exact},
          {"decided_by_filter", counters.decided_by_filter},
          {"axes_predicates", counters.axes.calls},
          {"axes_predicates_exact", counters.axes.exact},
          {"filter_predicates", counters.filter.calls},
          {"filter_predicates_exact", counters.filter.exact},
          {"test_predicates", counters.test.calls},
          {"test_predicates_exact", counters.test.exact}};
}

json narrow_counts(const NarrowPhaseStats& s) {
  return {{"vf", {{"tests", s.vf_tests}, {"yes", s.vf_yes}, {"no", s.vf_no}, {"uncertain", s.vf_uncertain}}},
          {"ee", {{"tests", s.ee_tests}, {"yes", s.ee_yes}, {"no", s.ee_no}, {"uncertain", s.ee_uncertain}}},
          {"certified", s.certified},
          {"certified_true", s.certified_true}};
}

/// Tallies of the filter against exact CCD, for one kind (VF or EE).
struct AccuracyTally {
  std::size_t candidates = 0, sampled = 0, checked = 0;
  std::size_t sampled_filter_no = 0, false_negatives = 0;    // in the sample
  std::size_t filter_yes = 0, false_positives = 0;          // all
  std::size_t toi_enclosure_violations = 0;                 // filter yes whose [lo, hi] misses exact's
  std::size_t uncertain = 0, uncertain_exact_yes = 0, uncertain_exact_no = 0;
  std::size_t exact_yes = 0;  // of all checked
  double seconds_exact = 0;
  json to_json() const {
    return {{"candidates", candidates}, {"sampled", sampled}, {"checked_exactly", checked},
            {"sampled_filter_no", sampled_filter_no}, {"false_negatives", false_negatives},
            {"filter_yes", filter_yes}, {"false_positives", false_positives},
            {"toi_enclosure_violations", toi_enclosure_violations}, {"uncertain", uncertain},
            {"uncertain_exact_yes", uncertain_exact_yes}, {"uncertain_exact_no", uncertain_exact_no},
            {"exact_yes", exact_yes}, {"seconds_exact", seconds_exact},
            {"microseconds_per_exact_query", checked ? 1e6 * seconds_exact / double(checked) : 0.0}};
  }
};

/// Filters every candidate, then checks the chosen ones exactly (in parallel).
/// `points(c)` gives the 8 positions of candidate c; `first_index` is c's
/// index in the whole scene's candidate sequence.
template <typename Candidate, typename Points, typename Filter, typename Exact>
void tally_accuracy(const std::vector<Candidate>& candidates, std::size_t first_index, std::size_t stride,
                    Points points, Filter filter, Exact exact, AccuracyTally& tally) {
  std::vector<CcdResult> answers(candidates.size());
  tbb::parallel_for(std::size_t{0}, candidates.size(), [&](std::size_t i) { answers[i] = filter(points(candidates[i])); });
  std::vector<std::size_t> chosen;
  std::vector<unsigned char> in_sample(candidates.size(), 0);
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    in_sample[i] = (first_index + i) % stride == 0;
    if (in_sample[i] || answers[i].answer != CcdAnswer::kNo) chosen.push_back(i);
  }
  std::vector<validate::ExactCcdResult> exact_answers(chosen.size());
  const auto start = Clock::now();
  tbb::parallel_for(std::size_t{0}, chosen.size(), [&](std::size_t k) {
    exact_answers[k] = exact(points(candidates[chosen[k]]));
  });
  tally.seconds_exact += seconds_since(start);
  tally.candidates += candidates.size();
  tally.checked += chosen.size();
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    const std::size_t i = chosen[k];
    const CcdResult& fast = answers[i];
    const validate::ExactCcdResult& truth = exact_answers[k];
    tally.exact_yes += truth.collides;
    if (in_sample[i]) {
      ++tally.sampled;
      if (fast.answer == CcdAnswer::kNo) {
        ++tally.sampled_filter_no;
        tally.false_negatives += truth.collides;
      }
    }
    if (fast.answer == CcdAnswer::kYes) {
      ++tally.filter_yes;
      if (!truth.collides)
        ++tally.false_positives;
      else if (truth.toi_hi < fast.toi_lo || truth.toi_lo > fast.toi_hi)
        ++tally.toi_enclosure_violations;
    }
    if (fast.answer == CcdAnswer::kUncertain) {
      ++tally.uncertain;
      (truth.collides ? tally.uncertain_exact_yes : tally.uncertain_exact_no) += 1;
    }
  }
}

}  // namespace

json measure_broad_phase(const BenchScene& bench, BroadPhaseMethod method, bool ccd, const MeasureSettings& settings) {
  auto phase = make_broad_phase(method);
  phase->build(bench.scene, broad_settings(settings, ccd));
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  std::vector<TrianglePair> pairs;
  const std::function<PipelineStats()> pass = [&] {
    PipelineStats total;
    const std::size_t count = ccd ? bench.steps() : bench.frames.size();
    for (std::size_t i = 0; i < count; ++i) {
      PipelineStats one;
      if (ccd) {
        phase->detect_ccd(bench.frames[i], bench.frames[i + 1], vf, ee);
        one.steps = 1;
        one.ccd_broad = phase->stats();
      } else {
        phase->detect_static(bench.frames[i], pairs);
        one.frames = 1;
        one.static_broad = phase->stats();
      }
      total.add(one);
    }
    return total;
  };
  const std::vector<PipelineStats> passes = timed_passes(settings, pass);
  auto stage = [&](double BroadPhaseStats::*field) {
    std::vector<double> values;
    for (const PipelineStats& p : passes) values.push_back((ccd ? p.ccd_broad : p.static_broad).*field);
    return median(values);
  };
  const BroadPhaseStats& counts = ccd ? passes.back().ccd_broad : passes.back().static_broad;
  return {{"mode", ccd ? "ccd" : "static"},
          {"method", broad_phase_method_name(method)},
          {"passes", passes.size()},
          {"seconds",
           {{"bounds", stage(&BroadPhaseStats::seconds_bounds)},
            {"subdivision", stage(&BroadPhaseStats::seconds_subdivision)},
            {"registration", stage(&BroadPhaseStats::seconds_registration)},
            {"pairs", stage(&BroadPhaseStats::seconds_pairs)},
            {"features", stage(&BroadPhaseStats::seconds_features)},
            {"total", stage(&BroadPhaseStats::seconds_total)}}},
          {"counts", broad_counts(counts)}};
}

json measure_narrow_phase(const BenchScene& bench, const MeasureSettings& settings) {
  const std::unique_ptr<Certifier> certifier = validate::make_exact_certifier();
  json out;
  for (const bool certified : {false, true}) {
    auto backend = make_cpu_backend();
    backend->bind(bench.scene, backend_settings(settings, certified ? certifier.get() : nullptr));
    struct Pass {
      double wall = 0;
      PipelineStats stats;
      std::size_t events = 0, uncertain_events = 0;
    };
    std::vector<Event> events;
    const std::function<Pass()> pass = [&] {
      Pass p;
      const auto start = Clock::now();
      for (std::size_t s = 0; s < bench.steps(); ++s) {
        events.clear();
        backend->collisions(bench.frames[s], bench.frames[s + 1], events);
        p.stats.add(backend->stats());
        p.events += events.size();
        for (const Event& e : events) p.uncertain_events += e.certainty == Certainty::kUncertain;
      }
      p.wall = seconds_since(start);
      return p;
    };
    const std::vector<Pass> passes = timed_passes(settings, pass);
    auto med = [&](const std::function<double(const Pass&)>& get) {
      std::vector<double> values;
      for (const Pass& p : passes) values.push_back(get(p));
      return median(values);
    };
    const Pass& last = passes.back();
    const NarrowPhaseStats& n = last.stats.narrow;
    const std::size_t tests = n.vf_tests + n.ee_tests;
    out[certified ? "certified" : "fast"] = {
        {"passes", passes.size()},
        {"seconds",
         {{"pass", med([](const Pass& p) { return p.wall; })},
          {"broad_phase", med([](const Pass& p) { return p.stats.ccd_broad.seconds_total; })},
          {"ccd_filter", med([](const Pass& p) { return p.stats.narrow.seconds_ccd; })},
          {"certify", med([](const Pass& p) { return p.stats.narrow.seconds_certify; })}}},
        {"answers", narrow_counts(n)},
        {"escalated_fraction", tests ? double(n.vf_uncertain + n.ee_uncertain) / double(tests) : 0.0},
        {"events", last.events},
        {"uncertain_events", last.uncertain_events}};
  }
  const double fast = out["fast"]["seconds"]["pass"].get<double>();
  const double fast_narrow = out["fast"]["seconds"]["ccd_filter"].get<double>();
  const double certified = out["certified"]["seconds"]["pass"].get<double>();
  const double certified_narrow = out["certified"]["seconds"]["ccd_filter"].get<double>() +
                                  out["certified"]["seconds"]["certify"].get<double>();
  out["certified_over_fast"] = fast > 0 ? certified / fast : 0.0;
  out["certified_over_fast_narrow_phase"] = fast_narrow > 0 ? certified_narrow / fast_narrow : 0.0;
  return out;
}

json measure_ccd_accuracy(const BenchScene& bench, const MeasureSettings& settings, std::size_t total_candidates) {
  auto phase = make_broad_phase(BroadPhaseMethod::kVirtualSubdivisionGrid);
  phase->build(bench.scene, broad_settings(settings, true));
  const std::size_t sample = std::max<std::size_t>(settings.accuracy_sample, 1);
  const std::size_t stride = std::max<std::size_t>(1, (total_candidates + sample - 1) / sample);
  CcdSettings ccd;
  ccd.thickness = settings.thickness;
  const double thickness = settings.thickness;
  const auto& triangles = bench.scene.triangles();
  const auto& edges = bench.scene.edges();
  AccuracyTally vf_tally, ee_tally;
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  std::size_t index = 0;
  for (std::size_t s = 0; s < bench.steps(); ++s) {
    const std::vector<Vec3>& x_t0 = bench.frames[s];
    const std::vector<Vec3>& x_t1 = bench.frames[s + 1];
    phase->detect_ccd(x_t0, x_t1, vf, ee);
    auto vf_points = [&](const VertexFaceCandidate& c) {
      const Triangle& f = triangles[c.face];
      return std::array<Vec3, 8>{x_t0[c.vertex], x_t0[f[0]], x_t0[f[1]], x_t0[f[2]],
                                 x_t1[c.vertex], x_t1[f[0]], x_t1[f[1]], x_t1[f[2]]};
    };
    auto ee_points = [&](const EdgeEdgeCandidate& c) {
      const Edge& a = edges[c.edge_a];
      const Edge& b = edges[c.edge_b];
      return std::array<Vec3, 8>{x_t0[a[0]], x_t0[a[1]], x_t0[b[0]], x_t0[b[1]],
                                 x_t1[a[0]], x_t1[a[1]], x_t1[b[0]], x_t1[b[1]]};
    };
    auto vf_filter = [&](const std::array<Vec3, 8>& p) {
      return vertex_face_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], ccd);
    };
    auto ee_filter = [&](const std::array<Vec3, 8>& p) {
      return edge_edge_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], ccd);
    };
    auto vf_exact = [&](const std::array<Vec3, 8>& p) { return validate::exact_vertex_face_ccd(p, thickness); };
    auto ee_exact = [&](const std::array<Vec3, 8>& p) { return validate::exact_edge_edge_ccd(p, thickness); };
    tally_accuracy(vf, index, stride, vf_points, vf_filter, vf_exact, vf_tally);
    index += vf.size();
    tally_accuracy(ee, index, stride, ee_points, ee_filter, ee_exact, ee_tally);
    index += ee.size();
  }
  return {{"stride", stride}, {"vf", vf_tally.to_json()}, {"ee", ee_tally.to_json()}};
}

json measure_static_vs_cgal(const BenchScene& bench, const MeasureSettings& settings) {
  // snag with its box grid (the default), and with sweep and prune instead,
  // side by side.
  auto backend = make_cpu_backend();
  backend->bind(bench.scene, backend_settings(settings, nullptr));
  CpuBackendOptions sweep_options;
  sweep_options.broad_phase = BroadPhaseMethod::kSweepAndPrune;
  auto sweep_backend = make_cpu_backend(sweep_options);
  sweep_backend->bind(bench.scene, backend_settings(settings, nullptr));
  std::vector<std::vector<TrianglePair>> snag_pairs(bench.frames.size()), sweep_pairs(bench.frames.size());
  std::vector<Event> events;
  PipelineStats stages;  // of the last pass
  // A pass of `detector`: every frame, its wall and CPU seconds.
  using PassSeconds = std::pair<double, double>;
  const auto snag_pass = [&](Backend& detector, std::vector<std::vector<TrianglePair>>& found, bool keep_stages) {
    const double cpu_start = process_cpu_seconds();
    const auto start = Clock::now();
    if (keep_stages) stages = PipelineStats{};
    for (std::size_t f = 0; f < bench.frames.size(); ++f) {
      events.clear();
      detector.intersections(bench.frames[f], events);
      if (keep_stages) stages.add(detector.stats());
      found[f].clear();
      for (const Event& e : events) found[f].push_back({std::min(e.a, e.b), std::max(e.a, e.b)});
    }
    return PassSeconds{seconds_since(start), process_cpu_seconds() - cpu_start};
  };

  CgalSelfIntersectionRunner cgal(bench.scene);
  std::vector<CgalSelfIntersections> cgal_found(bench.frames.size());
  const std::function<PassSeconds()> cgal_pass = [&] {
    PassSeconds total{0, 0};
    for (std::size_t f = 0; f < bench.frames.size(); ++f) {
      double seconds = 0, cpu_seconds = 0;
      cgal_found[f] = cgal.run(bench.frames[f], seconds, cpu_seconds);
      total.first += seconds;
      total.second += cpu_seconds;
    }
    return total;
  };
  // The passes alternate (snag, CGAL, snag, ...), so that other work on the
  // machine slows both alike.
  std::vector<double> snag_passes, cgal_passes, snag_cpu, cgal_cpu, sweep_passes;
  struct Passes {
    PassSeconds snag, sweep, cgal;
  };
  const std::function<Passes()> all = [&] {
    Passes passes;
    passes.snag = snag_pass(*backend, snag_pairs, true);
    passes.sweep = snag_pass(*sweep_backend, sweep_pairs, false);
    passes.cgal = cgal_pass();
    return passes;
  };
  for (const Passes& passes : timed_passes(settings, all)) {
    snag_passes.push_back(passes.snag.first);
    snag_cpu.push_back(passes.snag.second);
    sweep_passes.push_back(passes.sweep.first);
    cgal_passes.push_back(passes.cgal.first);
    cgal_cpu.push_back(passes.cgal.second);
  }
  const double sweep_seconds = median(sweep_passes);
  std::size_t sweep_differs = 0;  // frames where sweep and prune's pairs are not the box grid's
  for (std::size_t f = 0; f < bench.frames.size(); ++f) {
    std::sort(sweep_pairs[f].begin(), sweep_pairs[f].end());
    std::vector<TrianglePair> ours = snag_pairs[f];
    std::sort(ours.begin(), ours.end());
    sweep_differs += ours != sweep_pairs[f];
  }
  const double snag_seconds = median(snag_passes);
  const double cgal_seconds = median(cgal_passes);
  const double snag_cpu_seconds = median(snag_cpu);
  const double cgal_cpu_seconds = median(cgal_cpu);
  const double snag_fastest = *std::min_element(snag_passes.begin(), snag_passes.end());
  const double cgal_fastest = *std::min_element(cgal_passes.begin(), cgal_passes.end());

  std::size_t snag_total = 0, cgal_total = 0, degenerate = 0, only_snag = 0, only_cgal = 0;
  json differences = json::array();
  for (std::size_t f = 0; f < bench.frames.size(); ++f) {
    std::vector<TrianglePair> ours = snag_pairs[f];
    std::sort(ours.begin(), ours.end());
    const std::vector<TrianglePair>& theirs = cgal_found[f].pairs;
    snag_total += ours.size();
    cgal_total += theirs.size();
    degenerate += cgal_found[f].degenerate_faces.size();
    std::vector<TrianglePair> ours_only, theirs_only;
    std::set_difference(ours.begin(), ours.end(), theirs.begin(), theirs.end(), std::back_inserter(ours_only));
    std::set_difference(theirs.begin(), theirs.end(), ours.begin(), ours.end(), std::back_inserter(theirs_only));
    only_snag += ours_only.size();
    only_cgal += theirs_only.size();
    for (const TrianglePair& p : ours_only)
      if (differences.size() < 20) differences.push_back({{"frame", f}, {"a", p.a}, {"b", p.b}, {"only", "snag"}});
    for (const TrianglePair& p : theirs_only)
      if (differences.size() < 20) differences.push_back({{"frame", f}, {"a", p.a}, {"b", p.b}, {"only", "cgal"}});
  }
  const NarrowPhaseStats& narrow = stages.narrow;
  const double tests_seconds = narrow.seconds_static - narrow.seconds_static_events;
  return {{"frames", bench.frames.size()},
          {"snag_stages",
           {{"broad_phase_seconds", stages.static_broad.seconds_total},
            {"broad_phase", stage_seconds(stages.static_broad)},
            {"triangle_tests_seconds", tests_seconds},
            {"events_seconds", narrow.seconds_static_events},
            {"box_tests", stages.static_broad.tests},
            {"left_out_apart", stages.static_broad.left_out_apart},
            {"triangle_tests", narrow.triangle_tests},
            {"predicate_calls", narrow.predicate_calls},
            {"predicate_exact", narrow.predicate_exact},
            {"filter", static_filter_counts(bench)}}},
          {"snag_passes", snag_passes.size()},
          {"cgal_passes", cgal_passes.size()},
          {"snag_seconds", snag_seconds},
          {"cgal_seconds", cgal_seconds},
          {"speedup", snag_seconds > 0 ? cgal_seconds / snag_seconds : 0.0},
          {"sweep_and_prune_seconds", sweep_seconds},
          {"sweep_and_prune_speedup", sweep_seconds > 0 ? cgal_seconds / sweep_seconds : 0.0},
          {"sweep_and_prune_frames_differing", sweep_differs},
          {"snag_fastest_seconds", snag_fastest},
          {"cgal_fastest_seconds", cgal_fastest},
          {"speedup_fastest", snag_fastest > 0 ? cgal_fastest / snag_fastest : 0.0},
          {"snag_cpu_seconds", snag_cpu_seconds},
          {"cgal_cpu_seconds", cgal_cpu_seconds},
          {"speedup_cpu", snag_cpu_seconds > 0 ? cgal_cpu_seconds / snag_cpu_seconds : 0.0},
          {"cgal_parallel", CgalSelfIntersectionRunner::parallel()},
          {"cgal_mesh_repaired", cgal.repaired()},
          {"snag_pairs", snag_total},
          {"cgal_pairs", cgal_total},
          {"cgal_degenerate_faces", degenerate},
          {"only_snag", only_snag},
          {"only_cgal", only_cgal},
          {"identical", only_snag == 0 && only_cgal == 0},
          {"first_differences", differences}};
}

}  // namespace snag::bench
