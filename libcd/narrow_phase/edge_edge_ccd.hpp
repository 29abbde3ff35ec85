// Conservative continuous collision detection of two edges, usable from host
// and device code.
//
// Method: three proven early exits; the decisions by structure of
// ccd_structure.hpp (a contact at t = 0, a pair that moves as one); at
// thickness 0 the search over time alone
// of ccd_time_search.hpp, which decides nearly every plain crossing; then, for
// what is left, the inclusion-based search of ccd_inclusion.hpp (after Wang et al.,
// "A Large Scale Benchmark and an Inclusion-Based Algorithm for Continuous
// Collision Detection", ACM TOG 2021) on the contact function
//   F(t, u, v) = [(1 - u) ea0(t) + u ea1(t)] - [(1 - v) eb0(t) + v eb1(t)],
//   t, u, v in [0, 1],
// where every end moves linearly, x(t) = (1 - t) x_t0 + t x_t1. The edges
// are in contact at time t when |F(t, u, v)| <= thickness for some (u, v).
//
// Early exits, each proving kNo (most candidates of a real scene end here):
//  1. the swept boxes of the two edges are more than the thickness apart
//     along some axis (ccd_swept_aabb.hpp);
//  2. at thickness 0, the coplanarity cubic g(t) below keeps one strict sign
//     over [0, 1] (ccd_coplanarity_filter.hpp): the four ends are never
//     coplanar, which touching edges must be; parallel or zero-length edges
//     never pass this test.
//  3. a fixed direction separates the two swept features over the whole
//     step (ccd_separating_direction.hpp): most pairs whose planes cross but
//     whose features pass beside each other.
// Inputs out of range (see inclusion_ccd) answer kUncertain before any.
//
// Certificate of a crossing on [ta, tb], in outward-rounded interval
// arithmetic, with da = ea1 - ea0, db = eb1 - eb0, w = eb0 - ea0,
// n = da x db:
//   g(t) = w . n has strictly opposite signs at ta and at tb, so the four ends
//   are coplanar at some t* in [ta, tb]; and for every t in [ta, tb]
//   0 < U < |n|^2 and 0 < V < |n|^2 with U = (w x db) . n, V = (w x da) . n.
//   U / |n|^2 and V / |n|^2 are the parameters of the closest points of the
//   two lines (n != 0 follows); when the lines are coplanar these points
//   coincide, so at t* the segments share a point inside both. Parallel edges,
//   edges that only graze each other or stay coplanar can never be certified
//   this way and end kUncertain unless excluded.
#pragma once

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/narrow_phase/ccd_coplanarity_filter.hpp"
#include "libcd/narrow_phase/ccd_inclusion.hpp"
#include "libcd/narrow_phase/ccd_result.hpp"
#include "libcd/narrow_phase/ccd_separating_direction.hpp"
#include "libcd/narrow_phase/ccd_structure.hpp"
#include "libcd/narrow_phase/ccd_swept_aabb.hpp"
#include "libcd/narrow_phase/ccd_time_search.hpp"
#include "libcd/narrow_phase/interval.hpp"

namespace snag {
namespace ccd_detail {

/// The edge-edge contact function for inclusion_ccd; points are
/// ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1.
struct EdgeEdgeContact {
  Vec3 points[8];

  SNAG_HD_INLINE void corner_values(const double t[2], const double u[2], const double v[2], Vec3 f[8]) const {
    for (int ti = 0; ti < 2; ++ti) {
      const double s = 1.0 - t[ti];
      const Vec3 ea0 = s * points[0] + t[ti] * points[4];
      const Vec3 ea1 = s * points[1] + t[ti] * points[5];
      const Vec3 eb0 = s * points[2] + t[ti] * points[6];
      const Vec3 eb1 = s * points[3] + t[ti] * points[7];
      for (int ui = 0; ui < 2; ++ui) {
        for (int vi = 0; vi < 2; ++vi) {
          f[4 * ti + 2 * ui + vi] = (1.0 - u[ui]) * ea0 + u[ui] * ea1 - (1.0 - v[vi]) * eb0 - v[vi] * eb1;
        }
      }
    }
  }
  SNAG_HD_INLINE bool outside_domain(double, double) const { return false; }
  SNAG_HD_INLINE bool corner_in_domain(double, double) const { return true; }

  /// Encloses g(t) = (eb0 - ea0) . ((ea1 - ea0) x (eb1 - eb0)) for t in `time`.
  SNAG_HD_INLINE Interval coplanarity(Interval time) const {
    const IntervalVec3 ea0 = position_over(points[0], points[4], time);
    const IntervalVec3 ea1 = position_over(points[1], points[5], time);
    const IntervalVec3 eb0 = position_over(points[2], points[6], time);
    const IntervalVec3 eb1 = position_over(points[3], points[7], time);
    return dot(eb0 - ea0, cross(ea1 - ea0, eb1 - eb0));
  }

  /// +1 when, at every t in [ta, tb] at which the four ends are coplanar,
  /// the lines' common point provably lies strictly inside both edges, -1
  /// when it provably lies outside one of them at every such t, else 0: the
  /// signs of U, |n|^2 - U, V and |n|^2 - V (one strictly negative makes
  /// n != 0 too).
  SNAG_HD_INLINE int inside_over(double ta, double tb) const {
    const Interval time{ta, tb};
    const IntervalVec3 ea0 = position_over(points[0], points[4], time);
    const IntervalVec3 ea1 = position_over(points[1], points[5], time);
    const IntervalVec3 eb0 = position_over(points[2], points[6], time);
    const IntervalVec3 eb1 = position_over(points[3], points[7], time);
    const IntervalVec3 da = ea1 - ea0, db = eb1 - eb0, w = eb0 - ea0;
    const IntervalVec3 n = cross(da, db);
    const Interval n2 = dot(n, n);
    const Interval along_a = dot(cross(w, db), n);
    const Interval along_b = dot(cross(w, da), n);
    const Interval conditions[4] = {along_a, n2 - along_a, along_b, n2 - along_b};
    return all_positive(conditions, 4);
  }

  SNAG_HD_INLINE bool certify_crossing(double ta, double tb) const {
    return opposite_signs(coplanarity(point_interval(ta)), coplanarity(point_interval(tb))) &&
           inside_over(ta, tb) > 0;
  }
};

}  // namespace ccd_detail

/// The range check and the early exits of edge_edge_ccd: true with *result
/// set when they decide the query, else false. Never throws.
SNAG_HD_INLINE bool edge_edge_early_exit(const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0,
                                         const Vec3& eb1_t0, const Vec3& ea0_t1, const Vec3& ea1_t1,
                                         const Vec3& eb0_t1, const Vec3& eb1_t1, const CcdSettings& settings,
                                         CcdResult* result) {
  const Vec3 points[8] = {ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1};
  if (ccd_detail::range_exit(points, settings.thickness, result)) return true;
  if (!edge_edge_swept_overlap(ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1, settings.thickness) ||
      (settings.thickness == 0 && coplanarity_keeps_sign(ea0_t0, eb0_t0, ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1,
                                                         eb0_t1, ea0_t1, ea1_t1, eb0_t1, eb1_t1)) ||
      edge_edge_separated(ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1, settings.thickness)) {
    *result = ccd_detail::make_result(CcdAnswer::kNo, 1, 1);
    return true;
  }
  return false;
}

/// The decisions by structure (ccd_structure.hpp), for inputs that passed
/// the range check: true with *result set when they decide the query: kYes
/// with toi [0, 0] when the edges provably touch at t = 0 (at thickness d:
/// are provably within d), kNo when at thickness 0 the four ends move by one
/// displacement and the edges do not touch at t = 0. Never throws.
SNAG_HD_INLINE bool edge_edge_structure(const ccd_detail::EdgeEdgeContact& contact, const CcdSettings& settings,
                                        CcdResult* result) {
  using namespace ccd_detail;
  const Vec3 *x = contact.points, &ea0 = x[0], &ea1 = x[1], &eb0 = x[2], &eb1 = x[3];
  const bool exact = in_exact_range(ea0, ea1, eb0, eb1);
  if (exact && segments_meet(ea0, ea1, eb0, eb1)) {
    *result = make_result(CcdAnswer::kYes, 0, 0);
    return true;
  }
  if (settings.thickness > 0) {
    double u, v;
    closest_on_segments(ea0, ea1, eb0, eb1, &u, &v);
    if (within_at_start(contact, dyadic_parameter(u), dyadic_parameter(v), settings.thickness)) {
      *result = make_result(CcdAnswer::kYes, 0, 0);
      return true;
    }
  } else if (exact && moves_together(x)) {
    *result = make_result(CcdAnswer::kNo, 1, 1);
    return true;
  }
  return false;
}

/// The start of edge_edge_quick_isolating, on a query the early exits left
/// undecided: false with *end and *result set when the decisions by
/// structure decide it (kDecided) or, at a thickness, only the (t, u, v)
/// search can (kGaveUp); else true with *search at the start of the time
/// search over the whole step, which ccd_detail::advance_time_search
/// carries on. Never throws.
SNAG_HD_INLINE bool edge_edge_quick_start(const ccd_detail::EdgeEdgeContact& contact, const CcdSettings& settings,
                                          ccd_detail::TimeSearchState* search, ccd_detail::TimeSearchEnd* end,
                                          CcdResult* result) {
  if (edge_edge_structure(contact, settings, result)) {
    *end = ccd_detail::TimeSearchEnd::kDecided;
    return false;
  }
  if (settings.thickness != 0) {
    *end = ccd_detail::TimeSearchEnd::kGaveUp;
    return false;
  }
  const Vec3* x = contact.points;
  const Vec3 p[2] = {x[2] - x[0], x[6] - x[4]}, b[2] = {x[1] - x[0], x[5] - x[4]}, c[2] = {x[3] - x[2], x[7] - x[6]};
  ccd_detail::start_whole_step_search(ccd_detail::coplanarity_cubic(p, b, c), search);
  return true;
}

/// The decisions by structure and, at thickness 0, the time search, for a
/// query the early exits left undecided (edge_edge_early_exit returned
/// false): kDecided with *result set (the answer edge_edge_ccd gives) when
/// they decide it, kGaveUp when only the (t, u, v) search can. With
/// `isolated`, kIsolated where the time search isolates the earliest
/// contact's interval (ccd_detail::time_search_from); edge_edge_quick_refine
/// finishes it. Never throws.
SNAG_HD_INLINE ccd_detail::TimeSearchEnd edge_edge_quick_isolating(
    const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0, const Vec3& eb1_t0, const Vec3& ea0_t1,
    const Vec3& ea1_t1, const Vec3& eb0_t1, const Vec3& eb1_t1, const CcdSettings& settings,
    ccd_detail::IsolatedTimeInterval* isolated, CcdResult* result) {
  const ccd_detail::EdgeEdgeContact contact{{ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1}};
  ccd_detail::TimeSearchState search;
  ccd_detail::TimeSearchEnd end;
  if (!edge_edge_quick_start(contact, settings, &search, &end, result)) return end;
  return ccd_detail::finish_time_search(contact, settings.time_tolerance, isolated, &search, result);
}

/// The decisions by structure and, at thickness 0, the time search, for a
/// query the early exits left undecided (edge_edge_early_exit returned
/// false): true with *result set (the answer edge_edge_ccd gives) when they
/// decide it, false when only the (t, u, v) search can. Never throws.
SNAG_HD_INLINE bool edge_edge_quick_search(const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0,
                                           const Vec3& eb1_t0, const Vec3& ea0_t1, const Vec3& ea1_t1,
                                           const Vec3& eb0_t1, const Vec3& eb1_t1, const CcdSettings& settings,
                                           CcdResult* result) {
  return edge_edge_quick_isolating(ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1, settings, nullptr,
                                   result) == ccd_detail::TimeSearchEnd::kDecided;
}

/// The rest of edge_edge_quick_isolating's search from the interval it
/// isolated: true with *result set as edge_edge_quick_search sets it, false
/// where only the (t, u, v) search can decide. Never throws.
SNAG_HD_INLINE bool edge_edge_quick_refine(const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0,
                                           const Vec3& eb1_t0, const Vec3& ea0_t1, const Vec3& ea1_t1,
                                           const Vec3& eb0_t1, const Vec3& eb1_t1,
                                           const ccd_detail::IsolatedTimeInterval& isolated,
                                           const CcdSettings& settings, CcdResult* result) {
  const ccd_detail::EdgeEdgeContact contact{{ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1}};
  return ccd_detail::time_search_isolated(contact, isolated, settings.time_tolerance, result);
}

/// The early exits, then edge_edge_quick_search: true with *result set (the
/// answer edge_edge_ccd gives) when they decide the query, false when only
/// the (t, u, v) search can. Never throws.
SNAG_HD_INLINE bool edge_edge_quick_ccd(const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0,
                                        const Vec3& eb1_t0, const Vec3& ea0_t1, const Vec3& ea1_t1,
                                        const Vec3& eb0_t1, const Vec3& eb1_t1, const CcdSettings& settings,
                                        CcdResult* result) {
  return edge_edge_early_exit(ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1, settings, result) ||
         edge_edge_quick_search(ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1, settings, result);
}

/// Continuous collision of edge (ea0, ea1) against edge (eb0, eb1), every end
/// moving linearly from its _t0 to its _t1 position over t in [0, 1].
/// Positions in scene units (|coordinates| <= 1e60, else kUncertain).
/// Returns kNo only when no contact (distance <= settings.thickness) exists,
/// kYes only when one provably exists, else kUncertain; for kYes and
/// kUncertain [toi_lo, toi_hi] encloses the earliest time of contact (see
/// CcdResult). Never throws.
SNAG_HD_INLINE CcdResult edge_edge_ccd(const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0,
                                       const Vec3& eb1_t0, const Vec3& ea0_t1, const Vec3& ea1_t1,
                                       const Vec3& eb0_t1, const Vec3& eb1_t1, const CcdSettings& settings) {
  CcdResult result;
  if (edge_edge_quick_ccd(ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1, settings, &result)) {
    return result;
  }
  const ccd_detail::EdgeEdgeContact contact{{ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1}};
  return ccd_detail::inclusion_ccd(contact, settings);
}

}  // namespace snag
