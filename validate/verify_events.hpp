// Exact verification of a scan's events against the cache they came from:
// each reported collision is re-decided with the exact CCD of exact_ccd.hpp
// on the two frames' positions, each reported intersection with
// exact_triangles_intersect; optionally every pair of the complete candidate
// sets of verify_candidates.hpp is decided exactly too, to find what the
// scan missed.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "libcd/pipeline/event.hpp"
#include "libcd/scene/frame_source.hpp"

namespace snag::validate {

struct VerifySettings {
  double thickness = 0;       ///< contact distance of the scan, scene units (>= 0)
  /// Contact thickness per object, #objects, scene units (>= 0); empty:
  /// `thickness` for every pair. A pair's thickness is the mean of its two
  /// objects' (as snag-scan's rules define it), for collisions reported and
  /// searched alike.
  std::vector<double> object_thickness;
  bool collisions = true;     ///< the scan looked for collisions (CCD): check them exhaustively
  bool intersections = true;  ///< the scan looked for intersections (DCD): check them exhaustively
  bool exhaustive = false;    ///< also search the complete candidate sets for missed events
  /// A reported collision's [toi_lo, toi_hi] (step units) must come within
  /// this distance of the exact earliest-time-of-impact interval; it absorbs
  /// the rounding of frame + t to a double in reports (frame units).
  double toi_tolerance = 1e-9;
  double toi_width = 1e-9;    ///< width to which the exact earliest time of impact is isolated
};

/// What the exact check says about one reported event.
enum class Verdict {
  kConfirmed,    ///< the event exists (and, for collisions, the reported time of impact agrees)
  kFalse,        ///< no such event: the pair does not touch, or is not a valid pair
  kToiMismatch,  ///< the collision exists but its reported time of impact is off
};

struct EventCheck {
  Verdict verdict = Verdict::kConfirmed;
  std::string reason;                   ///< why, for kFalse and kToiMismatch
  double exact_toi_lo = 1, exact_toi_hi = 1;  ///< collisions that exist: the exact interval, step units
};

struct VerifyResult {
  std::vector<EventCheck> checks;  ///< one per reported event, in the order given
  /// Events found exactly in the complete candidate sets but not reported,
  /// in event_order (global ids; collisions carry the exact toi interval).
  std::vector<Event> missed;
  std::size_t vf_tested = 0, ee_tested = 0, triangle_pairs_tested = 0;  ///< exhaustive candidates decided
  /// Of vf_tested / ee_tested, those decided by verify_exclusion.hpp's
  /// certified exclusion; the rest ran the exact CCD.
  std::size_t vf_excluded = 0, ee_excluded = 0;
  std::size_t frames_read = 0;
  double seconds_reported = 0, seconds_exhaustive = 0;
};

/// Verifies `reported` (global ids as in snag::Event: VF a = vertex, b = face;
/// EE a, b = edges, any order; triangles a, b; frame = the step or frame
/// index in `source`; toi_lo/toi_hi in step units relative to the frame).
/// Precondition: every id is in range for source.scene() and every frame is
/// < source.frame_count() (collisions: < frame_count() - 1); the caller
/// checks and throws (the report reader does).
/// A reported event listed twice is kFalse the second time.
/// Throws what the source throws (InputError) while reading frames.
VerifyResult verify_events(const FrameSource& source, const std::vector<Event>& reported,
                           const VerifySettings& settings);

}  // namespace snag::validate
