// 18-DOPs (discrete oriented polytopes with 18 faces): the intersection of 9
// slabs whose normals are the coordinate axes and the six (±1,±1,0)-type
// diagonals x+y, x-y, x+z, x-z, y+z, y-z.
//
// Klosowski, Held, Mitchell, Sowizral, Zikan, "Efficient collision detection
// using bounding volume hierarchies of k-DOPs", IEEE TVCG 4(1), 1998.
//
// Conservative rounding: a slab is [min, max] of the projections of the points
// it bounds. The coordinate projections are exact; a diagonal projection
// (one addition) is off by at most half an ulp of its magnitude. Callers pass
// an absolute `pad` that exceeds every rounding error of the points and of the
// projections (see bounding_volume/primitive_bounds.hpp for the values used);
// the slab is widened by it, so the floating-point DOP contains the exact one.
// Inflation by a thickness h widens the axis slabs by h and the diagonal slabs
// by 1.5·h (> √2·h, the projection of a ball of radius h on an unnormalised
// diagonal), so the DOP contains every point within distance h.
#pragma once

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/vec3.hpp"

namespace snag {

/// Number of slab directions of an 18-DOP.
constexpr int kDopAxes = 9;

struct Dop18 {
  double lo[kDopAxes];
  double hi[kDopAxes];
};

/// Projections of p on the 9 slab directions (x, y, z, x+y, x-y, x+z, x-z, y+z, y-z).
SNAG_HD_INLINE void dop_project(Vec3 p, double d[kDopAxes]) {
  d[0] = p.x;
  d[1] = p.y;
  d[2] = p.z;
  d[3] = p.x + p.y;
  d[4] = p.x - p.y;
  d[5] = p.x + p.z;
  d[6] = p.x - p.z;
  d[7] = p.y + p.z;
  d[8] = p.y - p.z;
}

/// The empty DOP (every slab inverted); grow it with dop_add_point.
SNAG_HD_INLINE Dop18 dop_empty() {
  Dop18 dop;
  for (int k = 0; k < kDopAxes; ++k) {
    dop.lo[k] = 1e300;
    dop.hi[k] = -1e300;
  }
  return dop;
}

SNAG_HD_INLINE void dop_add_point(Dop18& dop, Vec3 p) {
  double d[kDopAxes];
  dop_project(p, d);
  for (int k = 0; k < kDopAxes; ++k) {
    dop.lo[k] = d[k] < dop.lo[k] ? d[k] : dop.lo[k];
    dop.hi[k] = d[k] > dop.hi[k] ? d[k] : dop.hi[k];
  }
}

/// Widens the DOP by a rounding pad (absolute, ≥ 0) plus a thickness h ≥ 0:
/// axis slabs by pad + h, diagonal slabs by 2·pad + 1.5·h.
SNAG_HD_INLINE void dop_inflate(Dop18& dop, double pad, double thickness) {
  for (int k = 0; k < kDopAxes; ++k) {
    const double w = k < 3 ? pad + thickness : 2.0 * pad + 1.5 * thickness;
    dop.lo[k] -= w;
    dop.hi[k] += w;
  }
}

/// The DOP of n points, widened by dop_inflate(pad, thickness).
SNAG_HD_INLINE Dop18 dop_of_points(const Vec3* points, int n, double pad, double thickness) {
  Dop18 dop = dop_empty();
  for (int i = 0; i < n; ++i) dop_add_point(dop, points[i]);
  dop_inflate(dop, pad, thickness);
  return dop;
}

/// True when the two DOPs share a point in every slab (closed slabs). Every
/// slab is compared, without an early exit: the loads of all of them can be
/// in flight at once (on a GPU, one wait for memory instead of one per slab).
SNAG_HD_INLINE bool dop_overlap(const Dop18& a, const Dop18& b) {
  bool apart = false;
  for (int k = 0; k < kDopAxes; ++k) apart |= (a.lo[k] > b.hi[k]) | (b.lo[k] > a.hi[k]);
  return !apart;
}

/// True when p lies in every slab of the DOP.
SNAG_HD_INLINE bool dop_contains(const Dop18& dop, Vec3 p) {
  double d[kDopAxes];
  dop_project(p, d);
  for (int k = 0; k < kDopAxes; ++k) {
    if (d[k] < dop.lo[k] || d[k] > dop.hi[k]) return false;
  }
  return true;
}

/// The axis-aligned box of the DOP (its x, y, z slabs).
SNAG_HD_INLINE void dop_box(const Dop18& dop, Vec3& lo, Vec3& hi) {
  lo = {dop.lo[0], dop.lo[1], dop.lo[2]};
  hi = {dop.hi[0], dop.hi[1], dop.hi[2]};
}

}  // namespace snag
