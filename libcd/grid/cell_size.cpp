#include "libcd/grid/cell_size.hpp"

#include <algorithm>
#include <cmath>

#include "libcd/grid/radius_sum.hpp"

namespace snag {

double virtual_subdivision_cell_size(const std::vector<double>& radii, double lambda) {
  if (radii.empty()) return 0;
  // Order-independent exact sum (radius_sum.hpp): identical result for any
  // thread count and on the GPU back end.
  const int shift = radius_sum_shift(*std::max_element(radii.begin(), radii.end()));
  FixedPointSum sum;
  for (double r : radii) sum = sum + quantize_radius(r, shift);
  return 3.0 * lambda * fixed_point_mean(sum, radii.size(), shift);
}

double largest_triangle_cell_size(const std::vector<double>& radii) {
  if (radii.empty()) return 0;
  return 3.0 * *std::max_element(radii.begin(), radii.end()) * (1 + 1e-9);
}

GridSpec make_grid(Vec3 lo, Vec3 hi, double cell_size) {
  GridSpec grid;
  grid.origin = lo;
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 0.0});
  const double smallest = extent > 0 ? extent / double(1 << 20) : 1.0;
  // No size at all (every triangle a point, or no finite radius): one cell
  // over the box, since the DOPs' rounding pads would span 2^20 tiny cells
  // per axis.
  if (!(cell_size > 0) || !std::isfinite(cell_size)) cell_size = extent > 0 ? extent : 1.0;
  if (!(cell_size >= smallest)) cell_size = smallest;
  grid.cell_size = cell_size;
  for (int a = 0; a < 3; ++a) {
    const double n = std::floor(std::max(hi[a] - lo[a], 0.0) / cell_size) + 1;
    grid.dims[a] = static_cast<std::int32_t>(std::min(n, double(1 << 21)));
  }
  return grid;
}

}  // namespace snag
