// Virtual triangles: a root (input) triangle, a sub-triangle of it given by
// exact dyadic barycentric coordinates, and a time slot. The mesh is never
// changed; positions are interpolated from the root's corners on demand.
//
// Loop, "Smooth subdivision surfaces based on triangles", MS thesis, 1987:
// the 1-to-4 split at edge midpoints (positions interpolated linearly, not
// smoothed: the children tile the parent exactly).
// Wong, Leach, Zambetta, virtual subdivision chapter, section 5.3.2 and
// Figure 5.3: time-step halving when the swept volume stays too large.
//
// Barycentrics: corner i of a virtual triangle at depth d is
//   (u·P0 + v·P1 + (2^d - u - v)·P2) / 2^d
// with integer numerators (u, v); midpoints add numerators at depth d+1, so
// every child corner is exact. Time slot k at slot depth e is [k/2^e, (k+1)/2^e].
#pragma once

#include <cmath>
#include <cstdint>

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag {

struct VirtualTriangle {
  Index root = 0;                 ///< global id of the input triangle
  std::uint32_t depth = 0;        ///< spatial subdivision level; barycentric denominator 2^depth
  std::uint32_t bary[3][2] = {{1, 0}, {0, 1}, {0, 0}};  ///< (u, v) numerators of each corner
  std::uint32_t slot_depth = 0;   ///< number of time halvings
  std::uint32_t slot_index = 0;   ///< slot [k/2^e, (k+1)/2^e]
};

/// The root triangle itself over the whole step.
SNAG_HD_INLINE VirtualTriangle virtual_root(Index root) {
  VirtualTriangle t;
  t.root = root;
  return t;
}

/// Start and end time of the slot, in [0, 1] (exact).
SNAG_HD_INLINE double slot_start(const VirtualTriangle& t) {
  return std::ldexp(static_cast<double>(t.slot_index), -static_cast<int>(t.slot_depth));
}
SNAG_HD_INLINE double slot_end(const VirtualTriangle& t) {
  return std::ldexp(static_cast<double>(t.slot_index + 1), -static_cast<int>(t.slot_depth));
}

/// True when two dyadic slots share an interval of positive length (one holds
/// the other). Every time in [0,1] lies in such a pair of slots of any two
/// slot partitions, so pairs of non-nested slots need no test.
/// Slots are given as (depth, index): [index/2^depth, (index+1)/2^depth].
SNAG_HD_INLINE bool slots_nested(std::uint32_t depth_a, std::uint32_t index_a, std::uint32_t depth_b,
                                 std::uint32_t index_b) {
  if (depth_a <= depth_b) return (index_b >> (depth_b - depth_a)) == index_a;
  return (index_a >> (depth_a - depth_b)) == index_b;
}
SNAG_HD_INLINE bool slots_nested(const VirtualTriangle& a, const VirtualTriangle& b) {
  return slots_nested(a.slot_depth, a.slot_index, b.slot_depth, b.slot_index);
}

/// Position of corner i of t at root corner positions p[3].
SNAG_HD_INLINE Vec3 virtual_corner(const VirtualTriangle& t, int i, const Vec3 p[3]) {
  const double scale = std::ldexp(1.0, -static_cast<int>(t.depth));
  const double u = static_cast<double>(t.bary[i][0]) * scale;
  const double v = static_cast<double>(t.bary[i][1]) * scale;
  const double full = std::ldexp(1.0, static_cast<int>(t.depth));
  const double w = (full - static_cast<double>(t.bary[i][0]) - static_cast<double>(t.bary[i][1])) * scale;
  return u * p[0] + v * p[1] + w * p[2];
}

/// The six points whose hull holds t over its slot: corners at slot start
/// (out[0..2]) and slot end (out[3..5]); root corners p_t0 at time 0, p_t1 at 1.
SNAG_HD_INLINE void virtual_swept_points(const VirtualTriangle& t, const Vec3 p_t0[3], const Vec3 p_t1[3],
                                         Vec3 out[6]) {
  const double s0 = slot_start(t), s1 = slot_end(t);
  for (int i = 0; i < 3; ++i) {
    const Vec3 a = virtual_corner(t, i, p_t0);
    const Vec3 b = virtual_corner(t, i, p_t1);
    out[i] = s0 == 0 ? a : lerp(a, b, s0);
    out[3 + i] = s1 == 1 ? b : lerp(a, b, s1);
  }
}

/// Loop 1-to-4 split: children 0..2 at the corners, child 3 in the middle.
SNAG_HD_INLINE void loop_children(const VirtualTriangle& parent, VirtualTriangle child[4]) {
  std::uint32_t c[3][2], m[3][2];  // corners and midpoints m[i] of edge (i, i+1), at depth+1
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    for (int k = 0; k < 2; ++k) {
      c[i][k] = 2 * parent.bary[i][k];
      m[i][k] = parent.bary[i][k] + parent.bary[j][k];
    }
  }
  const std::uint32_t* corners[4][3] = {{c[0], m[0], m[2]}, {m[0], c[1], m[1]}, {m[2], m[1], c[2]}, {m[1], m[2], m[0]}};
  for (int q = 0; q < 4; ++q) {
    child[q] = parent;
    child[q].depth = parent.depth + 1;
    for (int i = 0; i < 3; ++i) {
      child[q].bary[i][0] = corners[q][i][0];
      child[q].bary[i][1] = corners[q][i][1];
    }
  }
}

/// Splits the time slot in two halves (first, second); the shape is unchanged.
SNAG_HD_INLINE void halve_time(const VirtualTriangle& parent, VirtualTriangle child[2]) {
  for (int h = 0; h < 2; ++h) {
    child[h] = parent;
    child[h].slot_depth = parent.slot_depth + 1;
    child[h].slot_index = 2 * parent.slot_index + static_cast<std::uint32_t>(h);
  }
}

/// What the subdivision pass does with one virtual triangle.
enum class SplitDecision : std::uint8_t { kAccept, kSubdivide, kHalveTime, kAcceptOversized };

/// Decides from the six swept points (virtual_swept_points) whether t is small
/// enough for the grid: accepted when its bounding-sphere radius plus the
/// thickness is at most cell_size/3 (so it overlaps at most 2×2×2 cells).
/// Otherwise the time slot is halved when the corners' motion over the slot
/// exceeds the static radius (halving then shrinks the volume most), else the
/// triangle is Loop-subdivided. At a safety limit the other split is used;
/// at both limits it is accepted oversized (it then overlaps more cells; the
/// result stays exact, only slower).
SNAG_HD_INLINE SplitDecision decide_split(const VirtualTriangle& t, const Vec3 points[6], double swept_radius,
                                          double thickness, double cell_size, std::uint32_t max_levels,
                                          std::uint32_t max_halvings) {
  if (swept_radius + thickness <= cell_size / 3.0) return SplitDecision::kAccept;
  double motion2 = 0;
  for (int i = 0; i < 3; ++i) {
    const double d2 = squared_norm(points[3 + i] - points[i]);
    motion2 = d2 > motion2 ? d2 : motion2;
  }
  double static_r2 = 0;  // squared radius of the slot-start / slot-end shapes about their centroids
  for (int h = 0; h < 2; ++h) {
    const Vec3 centroid = (points[3 * h] + points[3 * h + 1] + points[3 * h + 2]) / 3.0;
    for (int i = 0; i < 3; ++i) {
      const double d2 = squared_norm(points[3 * h + i] - centroid);
      static_r2 = d2 > static_r2 ? d2 : static_r2;
    }
  }
  const bool can_halve = t.slot_depth < max_halvings;
  const bool can_subdivide = t.depth < max_levels;
  if (motion2 > static_r2 && can_halve) return SplitDecision::kHalveTime;
  if (can_subdivide) return SplitDecision::kSubdivide;
  if (can_halve) return SplitDecision::kHalveTime;
  return SplitDecision::kAcceptOversized;
}

}  // namespace snag
