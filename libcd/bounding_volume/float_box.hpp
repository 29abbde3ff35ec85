// A float box around an 18-DOP's three coordinate slabs, rounded outward: a
// cheap first test before the DOPs' own. Where two such boxes are apart, the
// DOPs are apart (each float bound lies outside the double one), so a pair the
// boxes reject is one dop_overlap rejects too; a pair they keep still takes
// dop_overlap. 24 bytes against the DOP's 144: the GPU's pair tests read the
// boxes of a whole large scene from the L2 cache and fetch the DOPs only of
// the few pairs whose boxes meet.
#pragma once

#include <cmath>

#include "libcd/bounding_volume/dop18.hpp"
#include "libcd/core/host_device.hpp"

namespace snag {

/// x, y and z slabs of a DOP in float, each bound rounded outward.
struct alignas(8) FloatBox {  // 24 bytes, read as three 8-byte words
  float lo[3];
  float hi[3];
};

/// The largest float at most d (NaN stays NaN; beyond float's range: ±infinity
/// or ±FLT_MAX, whichever lies on the right side).
SNAG_HD_INLINE float float_at_most(double d) {
  const float f = static_cast<float>(d);  // round to nearest
  return static_cast<double>(f) > d ? nextafterf(f, -INFINITY) : f;
}

/// The smallest float at least d (NaN stays NaN).
SNAG_HD_INLINE float float_at_least(double d) {
  const float f = static_cast<float>(d);
  return static_cast<double>(f) < d ? nextafterf(f, INFINITY) : f;
}

/// The float box around the DOP's coordinate slabs (axes 0, 1, 2 of
/// dop_project: x, y, z), containing them.
SNAG_HD_INLINE FloatBox float_box_of(const Dop18& dop) {
  FloatBox box;
  for (int k = 0; k < 3; ++k) {
    box.lo[k] = float_at_most(dop.lo[k]);
    box.hi[k] = float_at_least(dop.hi[k]);
  }
  return box;
}

/// False only when the boxes are apart along an axis; then the DOPs they were
/// made from are apart too (dop_overlap is false). NaN bounds never make it
/// false: the DOPs' own test decides. The six comparisons are joined
/// bitwise, without short circuits, so that a GPU warp runs them all without
/// branching.
SNAG_HD_INLINE bool float_boxes_may_overlap(const FloatBox& a, const FloatBox& b) {
  bool apart = false;
  for (int k = 0; k < 3; ++k) apart = apart | (a.lo[k] > b.hi[k]) | (b.lo[k] > a.hi[k]);
  return !apart;
}

/// The lower and upper y of a box as a sweep along y orders and bounds it (the
/// grids' cells, broad_phase/virtual_subdivision_grid.cpp): a NaN bound, which
/// float_boxes_may_overlap finds apart from no other, as -inf and +inf. Where
/// sweep_low(b) > sweep_high(a), float_boxes_may_overlap(a, b) is false.
SNAG_HD_INLINE float sweep_low(const FloatBox& box) { return box.lo[1] != box.lo[1] ? -INFINITY : box.lo[1]; }
SNAG_HD_INLINE float sweep_high(const FloatBox& box) { return box.hi[1] != box.hi[1] ? INFINITY : box.hi[1]; }

}  // namespace snag
