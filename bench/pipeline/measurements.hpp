// The pipeline benchmark's measurements, each returning JSON so that it can
// run in a forked child (child_process.hpp). Every timed quantity is the
// median of `repeat` passes after one warm-up pass (or the warm-up alone when
// it took longer than slow_pass_seconds); a pass covers every step (CCD) or
// every frame (static) of the scene.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>

#include "bench/pipeline/bench_scene.hpp"
#include "libcd/broad_phase/broad_phase.hpp"

namespace snag::bench {

struct MeasureSettings {
  double lambda = 1.2;                  ///< cell size = 3·λ·r_avg
  double thickness = 0;                 ///< contact distance, scene units
  unsigned threads = 0;                 ///< worker threads, 0 = all cores
  int repeat = 3;                       ///< timed passes (median), after one warm-up
  double slow_pass_seconds = 20;        ///< a warm-up longer than this is the only pass timed
  std::size_t accuracy_sample = 2000;   ///< CCD candidates checked exactly besides the filter's yes/uncertain
};


/// One broad phase on every step (`ccd` true) or every frame: median stage
/// times in seconds ("seconds": bounds, subdivision, registration, pairs,
/// features, total), and the counts of one pass summed over steps or frames
/// ("counts", BroadPhaseStats's names; memory_bytes is the largest of any
/// step). Throws what the broad phase throws.
nlohmann::json measure_broad_phase(const BenchScene& scene, BroadPhaseMethod method, bool ccd,
                                   const MeasureSettings& settings);

/// The CPU back end's collisions() on every step, fast (no certifier) and
/// certified (validate's exact certifier): median wall time of a pass, median
/// filter and certification times, and the narrow-phase answers per kind.
nlohmann::json measure_narrow_phase(const BenchScene& scene, const MeasureSettings& settings);

/// The floating-point CCD filter against exact CCD on the VSS candidates:
/// every candidate the filter answered yes or uncertain, plus a deterministic
/// sample (every k-th candidate of the whole scene, k = ceil(total /
/// accuracy_sample)) of the rest. Counts false negatives (filter no, exact
/// collides: sample only) and false positives (filter yes, exact no: all),
/// how the uncertain ones resolve, and time-of-impact enclosure violations.
/// `total_candidates`: VF + EE candidates of the whole scene (for k).
nlohmann::json measure_ccd_accuracy(const BenchScene& scene, const MeasureSettings& settings,
                                    std::size_t total_candidates);

/// Static detection: the CPU back end's intersections() against CGAL's
/// self_intersections (parallel) on every frame: median times of a pass,
/// the speed ratio, and whether the intersecting pair sets are identical
/// (the differences otherwise). CGAL's (f, f) degenerate-face reports are
/// counted apart: snag's intersections() does not report degenerate faces.
/// "snag_stages": snag's seconds per stage in the last pass (broad phase and
/// its stages, triangle tests, events), its predicate counts, and "filter":
/// on the box grid's pairs of every frame, how many the 2D exact-sign filter
/// decided and how often a predicate of the filter or of the test that
/// followed needed its exact stage.
nlohmann::json measure_static_vs_cgal(const BenchScene& scene, const MeasureSettings& settings);

}  // namespace snag::bench
