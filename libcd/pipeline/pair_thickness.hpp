// Contact thickness per object: the back end runs the step at the largest
// pair thickness, then the collisions of pairs whose own thickness is smaller
// are decided again at that thickness, candidate by candidate, exactly as the
// CPU back end decides them (ccd_test, then the certifier for what floating
// point leaves uncertain, then the event of event_builder.hpp).
//
// This is sound because a contact at a thickness d is a contact at every
// thickness above d: the broad phase and the filter at the larger thickness
// keep every pair that can touch at the smaller one.
#pragma once

#include <cstddef>
#include <vector>

#include "libcd/narrow_phase/ccd_result.hpp"
#include "libcd/pipeline/backend.hpp"
#include "libcd/pipeline/event.hpp"
#include "libcd/scene/scene.hpp"

namespace snag {

/// What redecide_at_pair_thickness did.
struct RedecideCounts {
  std::size_t redecided = 0;  ///< collisions decided again at their pair's thickness
  std::size_t removed = 0;    ///< of those, the ones that do not collide at it
};

/// Decides the collisions in `events` again at their pair's thickness, the
/// mean of the two objects' thicknesses, where that is below run_thickness.
///
/// \param[in] scene             the scene the events' global ids refer to
/// \param[in] x_t0, x_t1        #V global positions at the step's start and end
/// \param[in] object_thickness  #objects contact thicknesses, scene units (>= 0)
/// \param[in] run_thickness     the thickness the back end ran with; pairs at it
///                              are kept untouched. It must be computed as the
///                              pair thicknesses are, 0.5 * (h_a + h_b), so that
///                              equal values compare equal.
/// \param[in] ccd               the filter's tuning (its thickness is ignored)
/// \param[in] certifier         exact decision of uncertain answers; null: they
///                              stay uncertain (fast mode)
/// \param[in,out] events        collisions of the step x_t0 -> x_t1 (any frame
///                              value, kept), in event_order; intersections and
///                              collisions of pairs at or above run_thickness are
///                              left as they are. Collisions that do not occur at
///                              their pair's thickness are removed; the others
///                              get the new toi, position and certainty. The
///                              order stays event_order.
/// Note: pairs thicker than run_thickness cannot be decided from the run's
/// candidates and are left untouched; the caller should not check such pairs.
RedecideCounts redecide_at_pair_thickness(const Scene& scene, const std::vector<Vec3>& x_t0,
                                          const std::vector<Vec3>& x_t1, const std::vector<double>& object_thickness,
                                          double run_thickness, const CcdSettings& ccd, const Certifier* certifier,
                                          std::vector<Event>& events);

}  // namespace snag
