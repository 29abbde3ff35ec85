// A certified exclusion for CCD pairs, so that exhaustive verification runs
// the full exact test only on pairs that might touch. The step [0, 1] is cut
// into kExclusionSlices equal slices; a pair is excluded when on every slice
//   (a) the slice's boxes of the two primitives are farther apart than the
//       thickness on some axis, or
//   (b) at thickness 0, the four points provably never become coplanar.
//
// Why it is sound. (a) Under linear motion a corner's position over a slice
// [ta, tb] lies between its positions at ta and tb, and the primitive lies in
// the box of its corners; two points within d are within d on every axis.
// (b) At thickness 0 a vertex touching a face (or an edge an edge) at time t
// puts the four points on one plane, so the coplanarity cubic
// g(t) = det(b - a, c - a, p - a) (VF) or det(ea1 - ea0, eb1 - eb0, eb0 - ea0)
// (EE) vanishes at t (exact_ccd.cpp uses the same fact). On a slice the three
// vectors are linear, X(s) = (1 - s) X(ta) + s X(tb), so g is trilinear in them
// and its Bernstein coefficients on the slice are
// c_m = sum_{i+j+k=m} det(X_i, Y_j, Z_k) / C(3, m); g is a convex combination
// of them, so if all are certainly positive, or all certainly negative, g has
// no root on the slice. Every quantity, positions at slice ends included, is
// enclosed with CGAL::Interval_nt (outward-rounded interval arithmetic), so
// each decision holds for the exact values.
#pragma once

#include <array>

#include "libcd/geometry/vec3.hpp"

namespace snag::validate {

/// Number of time slices of the exclusion test.
constexpr int kExclusionSlices = 16;

/// True only when the pair provably never comes within `thickness` over the
/// step; false means nothing (the exact test must decide).
/// points: the 8 rows of exact_ccd.hpp (VF: v, f0, f1, f2 at t0 then t1;
/// EE: ea0, ea1, eb0, eb1 at t0 then t1), scene units; thickness >= 0.
/// Never throws.
bool certainly_apart(const std::array<Vec3, 8>& points, bool edge_edge, double thickness);

}  // namespace snag::validate
