// Complete candidate sets for exhaustive verification: every vertex–face and
// edge–edge pair of a step, and every triangle pair of a frame, that is not
// ruled out by an axis-aligned box test — a brute-force oracle independent of
// the pipeline's broad phase (no grid, no subdivision, no representative
// triangles, no DOP culling), made fast enough by sweep and prune
// (D. Baraff, "Dynamic Simulation of Non-Penetrating Rigid Bodies", PhD
// thesis, Cornell 1992, section 6.3: sort the boxes on one axis and sweep).
//
// Why nothing that touches is left out. Under linear motion every point of a
// primitive at any t in [0, 1] is a convex combination of its corners at that
// time, and each corner lies on the segment from its _t0 to its _t1 position;
// so the primitive lies, at every t, inside the axis-aligned box of all its
// corners' _t0 and _t1 positions (the swept box). Two points within distance
// d are within d on every axis. Hence if, on some axis, the gap between the
// two swept boxes exceeds d, the primitives never come within d: dropping
// such a pair loses no contact. The gap lo_b - hi_a is computed in floating
// point with rounding to nearest, which is monotone: fl(lo_b - hi_a) > d (d a
// double) implies lo_b - hi_a > d exactly, so a pair is dropped only when the
// exact gap exceeds d. Static pairs are the same with t0 = t1 and d = 0.
#pragma once

#include <vector>

#include "libcd/broad_phase/candidates.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/scene.hpp"

namespace snag::validate {

/// Every vertex–face and edge–edge pair of the step x_t0 -> x_t1 whose swept
/// boxes are within `thickness` on every axis, sorted and unique. Pairs that
/// share a vertex id are never included. Vertices used by no triangle are
/// never included (nothing can be reported for them).
/// scene: topology (global ids); x_t0, x_t1: #V global positions each, scene
/// units; thickness: contact distance d >= 0, scene units.
/// Throws snag::UsageError when the position counts differ from the scene's.
void complete_ccd_candidates(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                             double thickness, std::vector<VertexFaceCandidate>& vf,
                             std::vector<EdgeEdgeCandidate>& ee);

/// Every triangle pair (a < b) of one frame whose closed boxes overlap,
/// sorted and unique; pairs sharing vertices are included (the exact test
/// decides them). x: #V global positions. Throws like complete_ccd_candidates.
std::vector<TrianglePair> complete_triangle_candidates(const Scene& scene, const std::vector<Vec3>& x);

}  // namespace snag::validate
