// Cell size and extent of the grid.
//
// Wong, Leach, Zambetta, virtual subdivision for uniform-grid collision
// detection (eq. 5.1): size = 3·λ·r_avg, r_avg the mean bounding-sphere radius
// of the triangles in the current frame; λ > 1 (the chapter uses 1.2, snag
// kDefaultLambda).
// Grand, "Broad-phase collision detection with CUDA", GPU Gems 3 ch. 32 (2007):
// a cell that fits the largest object, the baseline.
//
// Radii are those of primitive_bounds: for CCD the sphere of the triangle's
// corners at t0 and t1 (the swept sphere) plus the thickness, for static
// detection the sphere at t0 plus the thickness. The swept radius is used for
// CCD because the grid registers swept volumes: a cell sized from t0 shapes
// alone would force time halving on every moving triangle.
#pragma once

#include <vector>

#include "libcd/grid/uniform_grid.hpp"

namespace snag {

/// λ of the cell size unless the caller sets it. The chapter uses 1.2 with
/// the frame's radii; with the swept radii (above), 1.5 took less device time
/// a step on every scene measured (CUDA back end, -m ccd, 11 steps, H100:
/// cloth_ball 3.17 -> 3.03 ms, ×4 10.46 -> 9.89, ×16 66.6 -> 62.3; 2.0 gave
/// 2.97, 10.39, 67.9; 3.0 gave 3.08, 11.61, 83.8): the tests of larger cells
/// cost less than the subdivision and registrations of smaller ones save.
/// Measured again on the faster kernels (CUPTI, -m all, 11 steps, H100), 1.5
/// still took the least on ×16 and ×4: λ 1.5, 1.65, 1.75, 1.9, 2.0, 2.25 gave
/// ×16 52.5, 52.7, 53.3, 54.3, 55.9, 59.6 ms; ×4 9.48, 9.49, 9.55, 9.91, 9.73,
/// 9.90; cloth_ball 3.69, 3.35, 3.44, 3.53, 3.37, 3.56 (within its noise).
constexpr double kDefaultLambda = 1.5;

/// 3·λ·mean(radii), the mean from the exact order-independent sum of
/// radius_sum.hpp (so the GPU back end finds the same size); 0 when radii is empty.
double virtual_subdivision_cell_size(const std::vector<double>& radii, double lambda);

/// 3·max(radii)·(1 + 1e-9): every triangle meets the "radius ≤ size/3" rule,
/// so none is subdivided (the largest-triangle grid).
double largest_triangle_cell_size(const std::vector<double>& radii);

/// A grid of the given cell size over [lo, hi]. A cell size that is zero or
/// not finite becomes the largest extent (one cell; 1 for an empty box); one
/// so small that an axis would need more than 2^20 cells is raised to
/// (largest extent)/2^20, so cell ids fit 64 bits.
GridSpec make_grid(Vec3 lo, Vec3 hi, double cell_size);

}  // namespace snag
