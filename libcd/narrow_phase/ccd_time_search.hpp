// The CCD search over time alone at thickness 0, usable from host and device
// code: a fast path tried before the (t, u, v) search of ccd_inclusion.hpp.
//
// At thickness 0 a contact at time t needs the four points in one plane,
// g(t) = 0, with g the coplanarity cubic of ccd_coplanarity_filter.hpp; and
// at such a time the kernel's inside conditions (vertex-face: the three edge
// functions; edge-edge: the parameters of the lines' common point, see the
// kernels) decide whether the features touch. So the search needs only t:
//  - an interval of t is excluded when the Bernstein coefficients of g on it
//    all have one strict sign (g has no zero there), or when some inside
//    condition is strictly violated over it (at a zero of g the features are
//    apart);
//  - it is a contact once it is at most the time tolerance wide, g has
//    strictly opposite signs at its ends and every inside condition holds
//    strictly over it (the kernel's certify_crossing);
//  - otherwise it is halved.
// Intervals are visited depth first, earlier half first, so when a contact is
// proven on [ta, tb] every time before ta has been excluded: the earliest
// contact lies in [ta, tb]. When the crossing's sign cannot be resolved at
// the ends of [ta, tb], the kernel tries [ta - w, tb + w] (w = tb - ta) and
// the earliest contact then lies in [ta, tb + w].
//
// The Bernstein coefficients of 3 g on [0, 1] are 3 D000, 3 beta_1, 3 beta_2
// and 3 D111, enclosed from their computed values and rounding bounds; the
// halves' coefficients come from de Casteljau's midpoint subdivision
// (Farouki, "The Bernstein polynomial basis: a centennial retrospective",
// CAGD 29(6), 2012) in outward-rounded interval arithmetic (interval.hpp),
// so every enclosure holds for the exact cubic. g(ta) and g(tb) are the end
// coefficients.
//
// The search gives up, and the caller falls back to the full search, when an
// interval at the tolerance can be neither excluded nor proven (a contact at
// t = 0, a grazing or tangential touch, points coplanar over the whole step)
// or after kMaxTimeIntervals intervals.
#pragma once

#include <stdint.h>

#include "libcd/core/host_device.hpp"
#include "libcd/narrow_phase/ccd_coplanarity_filter.hpp"
#include "libcd/narrow_phase/ccd_inclusion.hpp"
#include "libcd/narrow_phase/ccd_result.hpp"
#include "libcd/narrow_phase/interval.hpp"

namespace snag {
namespace ccd_detail {

/// Deepest halving of the time interval (widths of 2^-31).
constexpr int kMaxTimeLevel = 31;
/// Intervals examined before the time search gives up.
constexpr int kMaxTimeIntervals = 256;

/// Enclosures of the Bernstein coefficients of 3 g on one time interval;
/// `inside`: every inside condition is known to hold strictly over it (see
/// time_search).
struct TimeInterval {
  uint32_t num;
  uint8_t level;
  bool inside;
  Interval b[4];
};

/// A later half the depth-first search has yet to visit, without its last
/// coefficient: the pending halves tile the rest of [0, 1] in order, so that
/// coefficient (g at the half's upper end) is the first one of the pending
/// half below it, or the whole step's last one for the lowest.
struct PendingTimeInterval {
  uint32_t num;
  uint8_t level;
  bool inside;
  Interval b[3];
};

/// Encloses the exact coefficient a computed term approximates, times `scale`.
SNAG_HD_INLINE Interval enclose(const BernsteinTerm& term, double scale) {
  const double bound = round_up(rounding_bound(term));
  const Interval exact{round_down(term.value - bound), round_up(term.value + bound)};
  return point_interval(scale) * exact;
}

SNAG_HD_INLINE Interval midpoint(Interval a, Interval b) { return (a + b) * point_interval(0.5); }

/// True when every coefficient is strictly positive or every one strictly
/// negative: g has no zero on the interval.
SNAG_HD_INLINE bool keeps_sign(const Interval b[4]) {
  bool positive = true, negative = true;
  for (int m = 0; m < 4; ++m) {
    positive = positive && certainly_positive(b[m]);
    negative = negative && certainly_negative(b[m]);
  }
  return positive || negative;
}

/// Where an isolating search (time_search_from with `isolated`) handed its
/// interval over: the node it was about to halve, on which g has strictly
/// opposite signs at the ends and every inside condition holds (`inside` is
/// true), and the count of intervals examined up to and including it.
struct IsolatedTimeInterval {
  TimeInterval node;
  int examined;
};

/// How time_search_from ended.
enum class TimeSearchEnd : uint8_t {
  kDecided,   ///< *result is kNo or kYes with the enclosure of the earliest contact
  kGaveUp,    ///< only the (t, u, v) search can decide
  kIsolated,  ///< *isolated holds the interval to refine (time_search_isolated)
};

/// A time search in progress (time_search_from), advanced one interval at
/// a time by advance_time_search: `node` is the interval it examines next,
/// the `examined`-th; `last` is g's coefficient at the upper end of the
/// whole search; the search's stack (kTimeSearchStack entries, kept apart so
/// that the state can stay in registers) holds the `pending` later halves
/// still to visit. The GPU kernels advance one search per lane and start
/// another search on a lane whose search ended, so that a long search does
/// not hold its warp.
struct TimeSearchState {
  TimeInterval node;
  Interval last;
  int examined;
  int pending;
  bool subtree;
};

/// Entries of a time search's stack: one per level.
constexpr int kTimeSearchStack = kMaxTimeLevel + 1;

/// The state of a search from `node` (see time_search_from).
SNAG_HD_INLINE void start_time_search(TimeInterval node, Interval last, int examined, bool subtree,
                                      TimeSearchState* state) {
  state->node = node;
  state->last = last;
  state->examined = examined;
  state->pending = 0;
  state->subtree = subtree;
}

/// Examines the search's current interval: true with *end (and *result or
/// *isolated, as time_search_from sets them) when the search ends there,
/// else false with `state` moved on to the next interval.
template <class Contact>
SNAG_HD_INLINE bool advance_time_search(const Contact& contact, double time_tolerance, IsolatedTimeInterval* isolated,
                                        TimeSearchState* state, PendingTimeInterval* stack, CcdResult* result,
                                        TimeSearchEnd* end) {
  TimeInterval& node = state->node;
  if (state->examined > kMaxTimeIntervals) {
    *end = TimeSearchEnd::kGaveUp;
    return true;
  }
  bool excluded = keeps_sign(node.b);
  if (!excluded) {
    const double ta = lower(node.num, node.level), tb = upper(node.num, node.level);
    const int inside = node.inside ? 1 : contact.inside_over(ta, tb);
    excluded = inside < 0;
    if (!excluded) {
      const double width = tb - ta;
      if (width <= time_tolerance || node.level >= kMaxTimeLevel) {
        if (inside > 0 && opposite_signs(node.b[0], node.b[3])) {
          *result = make_result(CcdAnswer::kYes, ta, tb);
          *end = TimeSearchEnd::kDecided;
          return true;
        }
        const double wide_a = ta - width > 0 ? ta - width : 0;
        const double wide_b = tb + width < 1 ? tb + width : 1;
        if (contact.certify_crossing(wide_a, wide_b)) {
          *result = make_result(CcdAnswer::kYes, ta, wide_b);
          *end = TimeSearchEnd::kDecided;
          return true;
        }
        *end = TimeSearchEnd::kGaveUp;
        return true;
      }
      if (isolated != nullptr && inside > 0 && opposite_signs(node.b[0], node.b[3])) {
        node.inside = true;
        *isolated = IsolatedTimeInterval{node, state->examined};
        *end = TimeSearchEnd::kIsolated;
        return true;
      }
      // De Casteljau at the midpoint: the earlier half goes on now.
      const Interval* b = node.b;
      const Interval m01 = midpoint(b[0], b[1]), m12 = midpoint(b[1], b[2]), m23 = midpoint(b[2], b[3]);
      const Interval m012 = midpoint(m01, m12), m123 = midpoint(m12, m23);
      const Interval middle = midpoint(m012, m123);
      const uint8_t level = static_cast<uint8_t>(node.level + 1);
      stack[state->pending++] = PendingTimeInterval{2 * node.num + 1, level, inside > 0, {middle, m123, m23}};
      node = TimeInterval{2 * node.num, level, inside > 0, {b[0], m01, m012, middle}};
      ++state->examined;
      return false;
    }
  }
  if (state->pending == 0) {
    if (state->subtree) {
      *end = TimeSearchEnd::kGaveUp;
      return true;
    }
    *result = make_result(CcdAnswer::kNo, 1, 1);
    *end = TimeSearchEnd::kDecided;
    return true;
  }
  const PendingTimeInterval& next = stack[--state->pending];
  node = TimeInterval{
      next.num,
      next.level,
      next.inside,
      {next.b[0], next.b[1], next.b[2], state->pending > 0 ? stack[state->pending - 1].b[0] : state->last}};
  ++state->examined;
  return false;
}

/// Advances a search just started (start_time_search) to its end and
/// returns how it ended.
template <class Contact>
SNAG_HD_INLINE TimeSearchEnd finish_time_search(const Contact& contact, double time_tolerance,
                                                IsolatedTimeInterval* isolated, TimeSearchState* state,
                                                CcdResult* result) {
  PendingTimeInterval stack[kTimeSearchStack];
  TimeSearchEnd end = TimeSearchEnd::kGaveUp;
  while (!advance_time_search(contact, time_tolerance, isolated, state, stack, result, &end)) {
  }
  return end;
}

/// The search from `node` (the whole step, or an isolated interval when
/// `subtree`), having examined `examined - 1` intervals before it; `last` is
/// g's coefficient at the upper end of the node. Contact provides
/// `inside_over(ta, tb)` (+1: every inside condition holds strictly over
/// [ta, tb]; -1: one is strictly violated; 0: undecided) and
/// `certify_crossing(ta, tb)`.
///
/// The halves of an interval over which inside_over gave +1 are not asked
/// again: they inherit +1, which is what inside_over would give them, since
/// it must be inclusion-monotone: evaluated over [ta', tb'] inside [ta, tb]
/// it encloses no more than over [ta, tb]. The kernels' inside_over are
/// outward-rounded interval expressions in the time interval (interval.hpp),
/// and each of their operations is monotone in its operands' bounds
/// (round-to-nearest and next_up/next_down are non-decreasing, and a product's
/// bounds are the least and greatest of its endpoint products), so their lower
/// bounds only grow on a sub-interval.
///
/// With `isolated`, the search stops where it would halve an interval with
/// inside +1 and strictly opposite signs of g at its ends, and hands it over.
/// From there the search never leaves that interval: no descendant is ruled
/// out by the inside conditions (they inherit +1), and its descendants
/// cannot all keep one sign, because consecutive ones share the enclosure of
/// g at their common end (the midpoint coefficient) and the first and last
/// have the interval's own ends, of opposite signs. So the search ends inside
/// it with a contact or by giving up, at the same interval and with the same
/// result whether it goes on at once or later from the handed-over node
/// (time_search_isolated): the refinement of every hit, which takes most of
/// the steps, can run apart from the first levels. A subtree search that
/// nevertheless ran out of intervals gives up rather than answer kNo.
template <class Contact>
SNAG_HD TimeSearchEnd time_search_from(const Contact& contact, TimeInterval node, Interval last, int examined,
                                       bool subtree, double time_tolerance, IsolatedTimeInterval* isolated,
                                       CcdResult* result) {
  TimeSearchState state;
  start_time_search(node, last, examined, subtree, &state);
  return finish_time_search(contact, time_tolerance, isolated, &state, result);
}

/// The whole step's interval of `cubic`: its Bernstein coefficients of 3 g.
SNAG_HD_INLINE TimeInterval whole_step(const CoplanarityCubic& cubic) {
  const Interval b[4] = {enclose(cubic.term[0], 3), enclose(cubic.term[1], 1), enclose(cubic.term[2], 1),
                         enclose(cubic.term[3], 3)};
  return TimeInterval{0, 0, false, {b[0], b[1], b[2], b[3]}};
}

/// Starts the search over the whole step of `cubic` (see time_search_from).
SNAG_HD_INLINE void start_whole_step_search(const CoplanarityCubic& cubic, TimeSearchState* state) {
  const TimeInterval node = whole_step(cubic);
  start_time_search(node, node.b[3], 1, false, state);
}

/// The search over the whole step. Returns false when it gives up; else
/// *result is kNo or kYes with the enclosure of the earliest contact.
template <class Contact>
SNAG_HD bool time_search(const Contact& contact, const CoplanarityCubic& cubic, double time_tolerance,
                         CcdResult* result) {
  TimeSearchState state;
  start_whole_step_search(cubic, &state);
  return finish_time_search(contact, time_tolerance, nullptr, &state, result) == TimeSearchEnd::kDecided;
}

/// The rest of a search that handed over its isolated interval: true with
/// *result as time_search would have set it, false where it gives up.
template <class Contact>
SNAG_HD bool time_search_isolated(const Contact& contact, const IsolatedTimeInterval& isolated, double time_tolerance,
                                  CcdResult* result) {
  return time_search_from(contact, isolated.node, isolated.node.b[3], isolated.examined, true, time_tolerance, nullptr,
                          result) == TimeSearchEnd::kDecided;
}

}  // namespace ccd_detail
}  // namespace snag
