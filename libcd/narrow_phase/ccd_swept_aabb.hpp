// Swept axis-aligned bounding boxes: the cheap filter run before the CCD
// kernels, usable from host and device code.
//
// Under linear motion each point stays in the box of its two positions, so a
// primitive stays in the box of all its _t0 and _t1 vertices over the step.
// When the two primitives' boxes are further apart than the thickness along
// some axis, no contact is possible. Minimum, maximum and comparisons are
// exact; the one rounded sum (upper bound + thickness) is stepped up with
// nextafter, so the filter never rejects a pair in contact.
#pragma once

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/narrow_phase/interval.hpp"

namespace snag {

/// An axis-aligned box [lo, hi] (scene units).
struct SweptBox {
  Vec3 lo, hi;
};

/// The box of the first `count` points of `points` (count >= 1).
SNAG_HD_INLINE SweptBox swept_box(const Vec3* points, int count) {
  SweptBox box{points[0], points[0]};
  for (int i = 1; i < count; ++i) {
    box.lo = min(box.lo, points[i]);
    box.hi = max(box.hi, points[i]);
  }
  return box;
}

/// True unless the boxes are provably more than `thickness` (>= 0) apart
/// along some axis. NaN coordinates count as overlapping.
SNAG_HD_INLINE bool swept_boxes_overlap(const SweptBox& a, const SweptBox& b, double thickness) {
  for (int k = 0; k < 3; ++k) {
    if (a.lo[k] > round_up(b.hi[k] + thickness) || b.lo[k] > round_up(a.hi[k] + thickness)) return false;
  }
  return true;
}

/// Swept-box filter of a vertex-face pair (arguments as in vertex_face_ccd).
SNAG_HD_INLINE bool vertex_face_swept_overlap(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                                              const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                                              double thickness) {
  const Vec3 vertex[2] = {p_t0, p_t1};
  const Vec3 face[6] = {a_t0, b_t0, c_t0, a_t1, b_t1, c_t1};
  return swept_boxes_overlap(swept_box(vertex, 2), swept_box(face, 6), thickness);
}

/// Swept-box filter of an edge-edge pair (arguments as in edge_edge_ccd).
SNAG_HD_INLINE bool edge_edge_swept_overlap(const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0,
                                            const Vec3& eb1_t0, const Vec3& ea0_t1, const Vec3& ea1_t1,
                                            const Vec3& eb0_t1, const Vec3& eb1_t1, double thickness) {
  const Vec3 edge_a[4] = {ea0_t0, ea1_t0, ea0_t1, ea1_t1};
  const Vec3 edge_b[4] = {eb0_t0, eb1_t0, eb0_t1, eb1_t1};
  return swept_boxes_overlap(swept_box(edge_a, 4), swept_box(edge_b, 4), thickness);
}

}  // namespace snag
