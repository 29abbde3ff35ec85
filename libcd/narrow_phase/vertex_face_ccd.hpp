// Conservative continuous collision detection of a vertex against a triangle,
// usable from host and device code.
//
// Method: three proven early exits; the decisions by structure of
// ccd_structure.hpp (a contact at t = 0, a pair that moves as one); at
// thickness 0 the search over time alone
// of ccd_time_search.hpp, which decides nearly every plain crossing; then, for
// what is left, the inclusion-based search of ccd_inclusion.hpp (after Wang et al.,
// "A Large Scale Benchmark and an Inclusion-Based Algorithm for Continuous
// Collision Detection", ACM TOG 2021) on the contact function
//   F(t, u, v) = p(t) - [(1 - u - v) a(t) + u b(t) + v c(t)],
//   t, u, v in [0, 1], u + v <= 1,
// where every point moves linearly, x(t) = (1 - t) x_t0 + t x_t1. The pair is
// in contact at time t when |F(t, u, v)| <= thickness for some (u, v).
//
// Early exits, each proving kNo (most candidates of a real scene end here):
//  1. the swept boxes of the vertex and of the face are more than the
//     thickness apart along some axis (ccd_swept_aabb.hpp);
//  2. at thickness 0, the coplanarity cubic g(t) below keeps one strict sign
//     over [0, 1] (ccd_coplanarity_filter.hpp): the vertex never reaches the
//     triangle's plane, and a degenerate triangle never passes this test.
//  3. a fixed direction separates the two swept features over the whole
//     step (ccd_separating_direction.hpp): most pairs whose planes cross but
//     whose features pass beside each other.
// Inputs out of range (see inclusion_ccd) answer kUncertain before any.
//
// Certificate of a crossing on [ta, tb] (thickness 0 or more), in outward-
// rounded interval arithmetic:
//   g(t) = (p - a) . n with n = (b - a) x (c - a) has strictly opposite signs
//   at ta and at tb, so p(t*) is on the triangle's plane at some t* in
//   [ta, tb]; and for every t in [ta, tb]
//   ((b - a) x (p - a)) . n > 0, ((c - b) x (p - b)) . n > 0,
//   ((a - c) x (p - c)) . n > 0,
//   which for a point of the plane says it lies inside the triangle (n != 0
//   follows). So p(t*) is on the closed triangle. A zero-area triangle, a
//   vertex that only grazes the plane, or one that stays on it can never be
//   certified this way and ends kUncertain unless excluded.
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

/// The vertex-face contact function for inclusion_ccd; points are
/// p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1.
struct VertexFaceContact {
  Vec3 points[8];

  SNAG_HD_INLINE void corner_values(const double t[2], const double u[2], const double v[2], Vec3 f[8]) const {
    for (int ti = 0; ti < 2; ++ti) {
      const double s = 1.0 - t[ti];
      const Vec3 p = s * points[0] + t[ti] * points[4];
      const Vec3 a = s * points[1] + t[ti] * points[5];
      const Vec3 b = s * points[2] + t[ti] * points[6];
      const Vec3 c = s * points[3] + t[ti] * points[7];
      for (int ui = 0; ui < 2; ++ui) {
        for (int vi = 0; vi < 2; ++vi) {
          const double w = 1.0 - u[ui] - v[vi];
          f[4 * ti + 2 * ui + vi] = p - w * a - u[ui] * b - v[vi] * c;
        }
      }
    }
  }
  SNAG_HD_INLINE bool outside_domain(double u_lo, double v_lo) const { return u_lo + v_lo > 1; }
  SNAG_HD_INLINE bool corner_in_domain(double u, double v) const { return u + v <= 1; }

  /// Encloses g(t) = (p - a) . ((b - a) x (c - a)) for t in `time`.
  SNAG_HD_INLINE Interval coplanarity(Interval time) const {
    const IntervalVec3 p = position_over(points[0], points[4], time);
    const IntervalVec3 a = position_over(points[1], points[5], time);
    const IntervalVec3 b = position_over(points[2], points[6], time);
    const IntervalVec3 c = position_over(points[3], points[7], time);
    return dot(p - a, cross(b - a, c - a));
  }

  /// +1 when the vertex provably lies strictly inside the triangle at every
  /// t in [ta, tb] at which it is on the triangle's plane, -1 when it
  /// provably lies outside at every such t, else 0: the signs of the edge
  /// functions ((b - a) x (p - a)) . n, ((c - b) x (p - b)) . n and
  /// ((a - c) x (p - c)) . n, n = (b - a) x (c - a) (one strictly negative
  /// makes n != 0 too).
  SNAG_HD_INLINE int inside_over(double ta, double tb) const {
    const Interval time{ta, tb};
    const IntervalVec3 p = position_over(points[0], points[4], time);
    const IntervalVec3 a = position_over(points[1], points[5], time);
    const IntervalVec3 b = position_over(points[2], points[6], time);
    const IntervalVec3 c = position_over(points[3], points[7], time);
    const IntervalVec3 n = cross(b - a, c - a);
    const Interval edge_functions[3] = {dot(cross(b - a, p - a), n), dot(cross(c - b, p - b), n),
                                        dot(cross(a - c, p - c), n)};
    return all_positive(edge_functions, 3);
  }

  SNAG_HD_INLINE bool certify_crossing(double ta, double tb) const {
    return opposite_signs(coplanarity(point_interval(ta)), coplanarity(point_interval(tb))) &&
           inside_over(ta, tb) > 0;
  }
};

}  // namespace ccd_detail

/// The range check and the early exits of vertex_face_ccd: true with *result
/// set when they decide the query, else false. Never throws.
SNAG_HD_INLINE bool vertex_face_early_exit(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                                           const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                                           const CcdSettings& settings, CcdResult* result) {
  const Vec3 points[8] = {p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1};
  if (ccd_detail::range_exit(points, settings.thickness, result)) return true;
  if (!vertex_face_swept_overlap(p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1, settings.thickness) ||
      (settings.thickness == 0 &&
       coplanarity_keeps_sign(a_t0, p_t0, a_t0, b_t0, a_t0, c_t0, a_t1, p_t1, a_t1, b_t1, a_t1, c_t1)) ||
      vertex_face_separated(p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1, settings.thickness)) {
    *result = ccd_detail::make_result(CcdAnswer::kNo, 1, 1);
    return true;
  }
  return false;
}

/// The decisions by structure (ccd_structure.hpp), for inputs that passed
/// the range check: true with *result set when they decide the query: kYes
/// with toi [0, 0] when the vertex provably touches the face at t = 0 (at
/// thickness d: is provably within d of it), kNo when at thickness 0 the
/// four points move by one displacement and do not touch at t = 0. Never
/// throws.
SNAG_HD_INLINE bool vertex_face_structure(const ccd_detail::VertexFaceContact& contact, const CcdSettings& settings,
                                          CcdResult* result) {
  using namespace ccd_detail;
  const Vec3 *x = contact.points, &p = x[0], &a = x[1], &b = x[2], &c = x[3];
  const bool exact = in_exact_range(p, a, b, c);
  if (exact && point_on_triangle(p, a, b, c)) {
    *result = make_result(CcdAnswer::kYes, 0, 0);
    return true;
  }
  if (settings.thickness > 0) {
    double u, v;
    closest_on_triangle(p, a, b, c, &u, &v);
    u = dyadic_parameter(u);
    v = dyadic_parameter(v);
    if (u + v > 1) v = 1 - u;
    if (within_at_start(contact, u, v, settings.thickness)) {
      *result = make_result(CcdAnswer::kYes, 0, 0);
      return true;
    }
  } else if (exact && moves_together(x)) {
    *result = make_result(CcdAnswer::kNo, 1, 1);
    return true;
  }
  return false;
}

/// The start of vertex_face_quick_isolating, on a query the early exits left
/// undecided: false with *end and *result set when the decisions by
/// structure decide it (kDecided) or, at a thickness, only the (t, u, v)
/// search can (kGaveUp); else true with *search at the start of the time
/// search over the whole step, which ccd_detail::advance_time_search
/// carries on. Never throws.
SNAG_HD_INLINE bool vertex_face_quick_start(const ccd_detail::VertexFaceContact& contact, const CcdSettings& settings,
                                            ccd_detail::TimeSearchState* search, ccd_detail::TimeSearchEnd* end,
                                            CcdResult* result) {
  if (vertex_face_structure(contact, settings, result)) {
    *end = ccd_detail::TimeSearchEnd::kDecided;
    return false;
  }
  if (settings.thickness != 0) {
    *end = ccd_detail::TimeSearchEnd::kGaveUp;
    return false;
  }
  const Vec3* x = contact.points;
  const Vec3 p[2] = {x[0] - x[1], x[4] - x[5]}, b[2] = {x[2] - x[1], x[6] - x[5]}, c[2] = {x[3] - x[1], x[7] - x[5]};
  ccd_detail::start_whole_step_search(ccd_detail::coplanarity_cubic(p, b, c), search);
  return true;
}

/// The decisions by structure and, at thickness 0, the time search, for a
/// query the early exits left undecided (vertex_face_early_exit returned
/// false): kDecided with *result set (the answer vertex_face_ccd gives) when
/// they decide it, kGaveUp when only the (t, u, v) search can. With
/// `isolated`, kIsolated where the time search isolates the earliest
/// contact's interval (ccd_detail::time_search_from); vertex_face_quick_refine
/// finishes it. Never throws.
SNAG_HD_INLINE ccd_detail::TimeSearchEnd vertex_face_quick_isolating(
    const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0, const Vec3& p_t1, const Vec3& a_t1,
    const Vec3& b_t1, const Vec3& c_t1, const CcdSettings& settings, ccd_detail::IsolatedTimeInterval* isolated,
    CcdResult* result) {
  const ccd_detail::VertexFaceContact contact{{p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1}};
  ccd_detail::TimeSearchState search;
  ccd_detail::TimeSearchEnd end;
  if (!vertex_face_quick_start(contact, settings, &search, &end, result)) return end;
  return ccd_detail::finish_time_search(contact, settings.time_tolerance, isolated, &search, result);
}

/// The decisions by structure and, at thickness 0, the time search, for a
/// query the early exits left undecided (vertex_face_early_exit returned
/// false): true with *result set (the answer vertex_face_ccd gives) when they
/// decide it, false when only the (t, u, v) search can. Never throws.
SNAG_HD_INLINE bool vertex_face_quick_search(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                                             const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                                             const CcdSettings& settings, CcdResult* result) {
  return vertex_face_quick_isolating(p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1, settings, nullptr, result) ==
         ccd_detail::TimeSearchEnd::kDecided;
}

/// The rest of vertex_face_quick_isolating's search from the interval it
/// isolated: true with *result set as vertex_face_quick_search sets it, false
/// where only the (t, u, v) search can decide. Never throws.
SNAG_HD_INLINE bool vertex_face_quick_refine(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                                             const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                                             const ccd_detail::IsolatedTimeInterval& isolated,
                                             const CcdSettings& settings, CcdResult* result) {
  const ccd_detail::VertexFaceContact contact{{p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1}};
  return ccd_detail::time_search_isolated(contact, isolated, settings.time_tolerance, result);
}

/// The early exits, then vertex_face_quick_search: true with *result set (the
/// answer vertex_face_ccd gives) when they decide the query, false when only
/// the (t, u, v) search can. Never throws.
SNAG_HD_INLINE bool vertex_face_quick_ccd(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                                          const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                                          const CcdSettings& settings, CcdResult* result) {
  return vertex_face_early_exit(p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1, settings, result) ||
         vertex_face_quick_search(p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1, settings, result);
}

/// Continuous collision of vertex p against triangle (a, b, c), every point
/// moving linearly from its _t0 to its _t1 position over t in [0, 1].
/// Positions in scene units (|coordinates| <= 1e60, else kUncertain).
/// Returns kNo only when no contact (distance <= settings.thickness) exists,
/// kYes only when one provably exists, else kUncertain; for kYes and
/// kUncertain [toi_lo, toi_hi] encloses the earliest time of contact (see
/// CcdResult). Never throws.
SNAG_HD_INLINE CcdResult vertex_face_ccd(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                                         const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                                         const CcdSettings& settings) {
  CcdResult result;
  if (vertex_face_quick_ccd(p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1, settings, &result)) return result;
  const ccd_detail::VertexFaceContact contact{{p_t0, a_t0, b_t0, c_t0, p_t1, a_t1, b_t1, c_t1}};
  return ccd_detail::inclusion_ccd(contact, settings);
}

}  // namespace snag
