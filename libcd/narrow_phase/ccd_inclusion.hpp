// The conservative inclusion-based CCD search shared by vertex_face_ccd and
// edge_edge_ccd, usable from host and device code (no recursion, no
// containers, no exceptions: a fixed-size min-heap of boxes).
//
// Method after B. Wang, Z. Ferguson, T. Schneider, X. Jiang, M. Attene and
// D. Panozzo, "A Large Scale Benchmark and an Inclusion-Based Algorithm for
// Continuous Collision Detection", ACM Transactions on Graphics 40(5), 2021
// (Tight Inclusion), with a proven a-priori rounding bound in place of the
// paper's filters and a floating-point certificate for "yes".
//
// The contact function F(t, u, v) (see the two kernels) is affine in each of
// t, u and v separately, so on a box of (t, u, v) each coordinate of F takes
// its extremes at the 8 corners: the axis-aligned box of the corner values
// encloses F over the box exactly in real arithmetic.
//
// Rounding bound of a corner value (u = 2^-53 the unit roundoff,
// gamma_n = n u / (1 - n u), Higham, "Accuracy and Stability of Numerical
// Algorithms", 2nd ed., ch. 3). Bisection keeps t, u, v dyadic with at most 31
// fraction bits, so t, 1 - t, 1 - u, 1 - v and 1 - u - v are exact doubles.
// Let M_k be the largest |coordinate k| over the 8 input points.
//  1. A position x(t) = (1 - t) x_t0 + t x_t1 takes two products and one sum:
//     |fl(x(t)) - x(t)| <= gamma_2 ((1 - t)|x_t0| + t |x_t1|) <= gamma_2 M_k,
//     and |fl(x(t))| <= (1 + gamma_2) M_k.
//  2. A corner value is a 4-term sum sum_i c_i y_i of such positions with
//     coefficients (1, -(1-u-v), -u, -v) (vertex-face) or (1-u, u, -(1-v), -v)
//     (edge-edge); sum_i |c_i| <= 4 for u, v in [0, 1]. Recursive summation of
//     products errs by at most gamma_4 sum_i |c_i| |fl(y_i)|, and the position
//     errors add sum_i |c_i| gamma_2 M_k. In total
//     |fl(F_k) - F_k| <= 4 M_k (gamma_4 (1 + gamma_2) + gamma_2)
//                     <= 4 gamma_6 M_k < 2.6646e-15 M_k.
//  3. Underflow adds at most 2^-1075 per operation (about 10 per value); the
//     bound used is E_k = fl(2.7e-15 M_k) + 1e-300, which covers both (the
//     product fl(2.7e-15 M_k) is at least (1 - u) 2.7e-15 M_k).
//  4. A box is excluded when some coordinate k has all corner values above
//     T_k or all below -T_k, where T_k = nextafter(fl(d + E_k), +inf) >= d + E_k
//     (d the thickness). Then |F_k| > d over the whole box, and since
//     |F_k| <= |F|_2 the Euclidean distance exceeds d: no contact in the box.
//     For d > 0 a box is also excluded when the corner box enlarged by E_k
//     lies further than d from the origin (a lower bound of its squared
//     distance, rounded down, above d^2 rounded up): the ball of radius d is
//     rounder than the cube [-d, d]^3, which matters near grazing contacts.
// Inputs are required finite with M_k <= 1e60 (else kUncertain) so that no
// intermediate value of the kernels' certificates can overflow.
//
// Search: boxes are examined in increasing order of their start time t_lo
// (a min-heap), so when a box cannot be excluded every contact lies in it or
// in a later box: its t_lo bounds the earliest contact from below. A box that
// can be neither excluded nor refined usefully (its parameter widths are at
// the tolerance, or its corner values vary less than the rounding bound) is
// set aside as "stuck" and the search goes on: a later proven contact still
// answers kYes, with the earliest time bounded below by the first stuck box.
//
// Certificates of a contact (kYes), all in outward-rounded interval
// arithmetic (interval.hpp):
//  - crossing: once a box's time interval is at the time tolerance, the
//    kernel's certify_crossing(ta, tb) proves, by a sign change of the
//    coplanarity cubic and strict inside conditions over [ta, tb], that the
//    primitives touch at some time in [ta, tb] (intermediate value theorem);
//  - thickness d > 0: a corner of a box whose value, enlarged by E_k, lies in
//    the ball of radius d is a configuration within distance d. Found on a
//    box wider in time than the tolerance, it bounds the earliest time from
//    above, and the search goes on until the boxes left start after it.
#pragma once

#include <math.h>
#include <stdint.h>

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/narrow_phase/ccd_result.hpp"
#include "libcd/narrow_phase/interval.hpp"

namespace snag {
namespace ccd_detail {

/// Capacity of the box heap; a search that would need more answers kUncertain.
constexpr int kMaxBoxes = 1024;
/// Finest bisection level of t, u and v (widths of 2^-31).
constexpr int kMaxLevel = 31;
/// Bounds 4 gamma_6 from above (see the file comment, step 2).
constexpr double kCornerErrorFactor = 2.7e-15;
/// Covers underflow (see the file comment, step 3).
constexpr double kUnderflowSlack = 1e-300;
/// Weight of the time parameter when choosing which parameter to split.
constexpr double kTimeSplitBias = 4;
/// Largest input coordinate magnitude the kernels accept.
constexpr double kMaxMagnitude = 1e60;

/// A box of (t, u, v): each parameter spans [num / 2^level, (num + 1) / 2^level].
struct Box {
  uint32_t t_num, u_num, v_num;
  uint8_t t_level, u_level, v_level;
};

SNAG_HD_INLINE uint64_t start_key(const Box& box) {
  return static_cast<uint64_t>(box.t_num) << (kMaxLevel - box.t_level);
}
/// 2^-level, exactly, for level in [0, kMaxLevel] (ldexp is a library call).
SNAG_HD_INLINE double inverse_power_of_two(uint8_t level) {
  return static_cast<double>(1.0f / static_cast<float>(1u << level));
}
SNAG_HD_INLINE double lower(uint32_t num, uint8_t level) {
  return static_cast<double>(num) * inverse_power_of_two(level);
}
SNAG_HD_INLINE double upper(uint32_t num, uint8_t level) {
  return (static_cast<double>(num) + 1.0) * inverse_power_of_two(level);
}

/// A min-heap of boxes keyed by start time, in a fixed array.
struct BoxHeap {
  Box boxes[kMaxBoxes];
  int size = 0;

  SNAG_HD_INLINE bool push(const Box& box) {
    if (size == kMaxBoxes) return false;
    int child = size++;
    const uint64_t key = start_key(box);
    while (child > 0) {
      const int parent = (child - 1) / 2;
      if (start_key(boxes[parent]) <= key) break;
      boxes[child] = boxes[parent];
      child = parent;
    }
    boxes[child] = box;
    return true;
  }
  SNAG_HD_INLINE Box pop() {
    const Box top = boxes[0];
    const Box last = boxes[--size];
    const uint64_t key = start_key(last);
    int parent = 0;
    while (true) {
      int child = 2 * parent + 1;
      if (child >= size) break;
      if (child + 1 < size && start_key(boxes[child + 1]) < start_key(boxes[child])) ++child;
      if (key <= start_key(boxes[child])) break;
      boxes[parent] = boxes[child];
      parent = child;
    }
    if (size > 0) boxes[parent] = last;
    return top;
  }
};

SNAG_HD_INLINE double abs_max3(Vec3 a) {
  const double x = fabs(a.x), y = fabs(a.y), z = fabs(a.z);
  const double xy = x > y ? x : y;
  return xy > z ? xy : z;
}

/// True when the corner value f, enlarged by the rounding bound, provably lies
/// within Euclidean distance d of the origin (d2_lo <= d * d).
SNAG_HD_INLINE bool corner_within(Vec3 f, const double error[3], double d2_lo) {
  double sum = 0;
  for (int k = 0; k < 3; ++k) {
    const double magnitude = round_up(fabs(f[k]) + error[k]);
    sum = round_up(sum + round_up(magnitude * magnitude));
  }
  return sum <= d2_lo;
}

SNAG_HD_INLINE CcdResult make_result(CcdAnswer answer, double toi_lo, double toi_hi) {
  CcdResult result;
  result.answer = answer;
  result.toi_lo = toi_lo;
  result.toi_hi = toi_hi;
  return result;
}

/// True when all 8 points are finite with |coordinate| <= kMaxMagnitude and
/// the thickness d satisfies 0 <= d <= kMaxMagnitude: the range in which the
/// kernels' rounding bounds hold. NaN fails every comparison and is out.
SNAG_HD_INLINE bool inputs_in_range(const Vec3 points[8], double d) {
  for (int i = 0; i < 8; ++i) {
    for (int k = 0; k < 3; ++k) {
      if (!(fabs(points[i][k]) <= kMaxMagnitude)) return false;
    }
  }
  return d >= 0 && d <= kMaxMagnitude;
}

/// The range check that comes first in the CCD early exits: true with
/// *result kUncertain over [0, 1] when the inputs are out of range
/// (inputs_in_range), else false.
SNAG_HD_INLINE bool range_exit(const Vec3 points[8], double d, CcdResult* result) {
  if (inputs_in_range(points, d)) return false;
  *result = make_result(CcdAnswer::kUncertain, 0, 1);
  return true;
}

/// The rounding bound E_k of a corner value of the contact function over
/// these 8 points (see the file comment, steps 1 to 3). The points must
/// satisfy inputs_in_range.
SNAG_HD_INLINE void corner_error_bounds(const Vec3 points[8], double error[3]) {
  for (int k = 0; k < 3; ++k) {
    double largest = 0;
    for (int i = 0; i < 8; ++i) {
      const double c = fabs(points[i][k]);
      largest = c > largest ? c : largest;
    }
    error[k] = kCornerErrorFactor * largest + kUnderflowSlack;
  }
}

/// The search. Contact provides: `Vec3 points[8]` (the inputs),
/// `corner_values(t, u, v, f)` (f[4 ti + 2 ui + vi] = F(t[ti], u[ui], v[vi])),
/// `outside_domain(u_lo, v_lo)`, `corner_in_domain(u, v)` and
/// `certify_crossing(ta, tb)`.
template <class Contact>
SNAG_HD CcdResult inclusion_ccd(const Contact& contact, const CcdSettings& settings) {
  const double d = settings.thickness;
  if (!inputs_in_range(contact.points, d)) return make_result(CcdAnswer::kUncertain, 0, 1);
  double error[3], threshold[3];
  corner_error_bounds(contact.points, error);
  double largest_error = 0;
  for (int k = 0; k < 3; ++k) {
    threshold[k] = round_up(d + error[k]);
    largest_error = error[k] > largest_error ? error[k] : largest_error;
  }
  const double d2_lo = round_down(d * d), d2_hi = round_up(d * d);

  BoxHeap heap;
  heap.push(Box{0, 0, 0, 0, 0, 0});
  double stuck_lo = 2, stuck_hi = -1;
  double certified_t_lo = -1, certified_t_hi = -1;  // last time interval tried
  // A contact proven at time proven_hi (> 1: none yet) while the search goes
  // on to narrow the earliest time from below.
  double proven_hi = 2;
  const auto proven = [&proven_hi](double lo, double hi) {
    return make_result(CcdAnswer::kYes, lo < proven_hi ? lo : proven_hi, hi);
  };
  for (int iteration = 0; heap.size > 0; ++iteration) {
    if (iteration >= settings.max_iterations) {
      const double next = lower(heap.boxes[0].t_num, heap.boxes[0].t_level);
      if (proven_hi <= 1) return proven(stuck_lo < next ? stuck_lo : next, proven_hi);
      return make_result(CcdAnswer::kUncertain, stuck_lo < next ? stuck_lo : next, 1);
    }
    const Box box = heap.pop();
    const double t[2] = {lower(box.t_num, box.t_level), upper(box.t_num, box.t_level)};
    if (t[0] >= proven_hi) return proven(stuck_lo < t[0] ? stuck_lo : t[0], proven_hi);
    const double u[2] = {lower(box.u_num, box.u_level), upper(box.u_num, box.u_level)};
    const double v[2] = {lower(box.v_num, box.v_level), upper(box.v_num, box.v_level)};
    if (contact.outside_domain(u[0], v[0])) continue;

    Vec3 f[8];
    contact.corner_values(t, u, v, f);
    bool excluded = false;
    double gap_squared = 0;  // lower bound of the squared distance of the enlarged box to the origin
    for (int k = 0; k < 3 && !excluded; ++k) {
      double lo = f[0][k], hi = f[0][k];
      for (int i = 1; i < 8; ++i) {
        lo = f[i][k] < lo ? f[i][k] : lo;
        hi = f[i][k] > hi ? f[i][k] : hi;
      }
      excluded = lo > threshold[k] || hi < -threshold[k];
      const double gap = lo > 0 ? round_down(lo - error[k]) : round_down(-hi - error[k]);
      if (gap > 0) gap_squared = round_down(gap_squared + round_down(gap * gap));
    }
    if (excluded || (d > 0 && gap_squared > d2_hi)) continue;

    const double earliest = stuck_lo < t[0] ? stuck_lo : t[0];
    const double t_width = t[1] - t[0];
    const bool t_narrow = t_width <= settings.time_tolerance || box.t_level >= kMaxLevel;
    if (d > 0) {
      // Corners at t[0] come first, so the first one found is the earliest.
      for (int i = 0; i < 8; ++i) {
        if (contact.corner_in_domain(u[(i >> 1) & 1], v[i & 1]) && corner_within(f[i], error, d2_lo)) {
          if (t_narrow) return proven(earliest, t[i >> 2] < proven_hi ? t[i >> 2] : proven_hi);
          proven_hi = t[i >> 2] < proven_hi ? t[i >> 2] : proven_hi;
          break;
        }
      }
    }
    if (t_narrow && !(t[0] == certified_t_lo && t[1] == certified_t_hi)) {
      certified_t_lo = t[0];
      certified_t_hi = t[1];
      if (contact.certify_crossing(t[0], t[1])) return proven(earliest, t[1] < proven_hi ? t[1] : proven_hi);
      // The crossing may sit too close to an end of the interval for its sign
      // to be resolved there; a wider interval still bounds the time.
      const double ta = t[0] - t_width > 0 ? t[0] - t_width : 0;
      const double tb = t[1] + t_width < 1 ? t[1] + t_width : 1;
      if (contact.certify_crossing(ta, tb)) return proven(earliest, tb < proven_hi ? tb : proven_hi);
    }

    // Split the parameter whose change moves F the most.
    double spread_t = 0, spread_u = 0, spread_v = 0;
    for (int j = 0; j < 4; ++j) {
      const double dt = abs_max3(f[4 + j] - f[j]);
      const double du = abs_max3(f[((j >> 1) << 2) + 2 + (j & 1)] - f[((j >> 1) << 2) + (j & 1)]);
      const double dv = abs_max3(f[2 * j + 1] - f[2 * j]);
      spread_t = dt > spread_t ? dt : spread_t;
      spread_u = du > spread_u ? du : spread_u;
      spread_v = dv > spread_v ? dv : spread_v;
    }
    // Time is favoured: narrowing it is what bounds the earliest contact.
    spread_t *= kTimeSplitBias;
    if (t_narrow) spread_t = -1;
    if (u[1] - u[0] <= settings.time_tolerance || box.u_level >= kMaxLevel) spread_u = -1;
    if (v[1] - v[0] <= settings.time_tolerance || box.v_level >= kMaxLevel) spread_v = -1;
    const double spread = spread_t > spread_u ? (spread_t > spread_v ? spread_t : spread_v)
                                              : (spread_u > spread_v ? spread_u : spread_v);
    if (!(spread > largest_error)) {
      stuck_lo = t[0] < stuck_lo ? t[0] : stuck_lo;
      stuck_hi = t[1] > stuck_hi ? t[1] : stuck_hi;
      continue;
    }
    Box first = box, second = box;
    if (spread == spread_t) {
      first.t_num = 2 * box.t_num;
      second.t_num = 2 * box.t_num + 1;
      first.t_level = second.t_level = static_cast<uint8_t>(box.t_level + 1);
    } else if (spread == spread_u) {
      first.u_num = 2 * box.u_num;
      second.u_num = 2 * box.u_num + 1;
      first.u_level = second.u_level = static_cast<uint8_t>(box.u_level + 1);
    } else {
      first.v_num = 2 * box.v_num;
      second.v_num = 2 * box.v_num + 1;
      first.v_level = second.v_level = static_cast<uint8_t>(box.v_level + 1);
    }
    if (!heap.push(first) || !heap.push(second)) {
      if (proven_hi <= 1) return proven(earliest, proven_hi);
      return make_result(CcdAnswer::kUncertain, earliest, 1);
    }
  }
  if (proven_hi <= 1) return proven(stuck_lo, proven_hi);
  if (stuck_hi >= 0) return make_result(CcdAnswer::kUncertain, stuck_lo, stuck_hi);
  return make_result(CcdAnswer::kNo, 1, 1);
}

}  // namespace ccd_detail
}  // namespace snag
