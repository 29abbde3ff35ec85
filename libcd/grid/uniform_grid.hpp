// The uniform grid: cubic cells of one size over the scene's box, cell
// coordinates, linear cell ids and cell types.
//
// Cell type (Grand 2007): the parity of the cell's coordinates, x | y<<1 | z<<2.
// The at most 2×2×2 cells a small object overlaps all have different types.
//
// Floating-point: a coordinate maps to floor((v - origin) / size), clamped to
// [0, dims-1]. Subtraction, division, floor and clamping are all monotone, so
// two intervals that share a point share a cell: registration needs no padding.
#pragma once

#include <cmath>
#include <cstdint>

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/vec3.hpp"

namespace snag {

struct CellCoord {
  std::int32_t x = 0, y = 0, z = 0;
};

SNAG_HD_INLINE bool operator==(CellCoord a, CellCoord b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

struct GridSpec {
  Vec3 origin;             ///< low corner of cell (0,0,0)
  double cell_size = 1;    ///< edge length of a cell, scene units, > 0
  std::int32_t dims[3] = {1, 1, 1};  ///< cells per axis
};

/// Cell index along one axis, clamped to the grid.
SNAG_HD_INLINE std::int32_t grid_axis_cell(const GridSpec& grid, double v, int axis) {
  const double q = std::floor((v - grid.origin[axis]) / grid.cell_size);
  const double top = static_cast<double>(grid.dims[axis] - 1);
  return static_cast<std::int32_t>(q < 0 ? 0 : (q > top ? top : q));
}

SNAG_HD_INLINE CellCoord grid_cell_of(const GridSpec& grid, Vec3 p) {
  return {grid_axis_cell(grid, p.x, 0), grid_axis_cell(grid, p.y, 1), grid_axis_cell(grid, p.z, 2)};
}

/// Linear cell id, x fastest. Ids order cells by (z, y, x).
SNAG_HD_INLINE std::uint64_t grid_cell_id(const GridSpec& grid, CellCoord c) {
  return (static_cast<std::uint64_t>(c.z) * static_cast<std::uint64_t>(grid.dims[1]) + static_cast<std::uint64_t>(c.y)) *
             static_cast<std::uint64_t>(grid.dims[0]) +
         static_cast<std::uint64_t>(c.x);
}

/// The cell of a linear id (grid_cell_id's inverse).
SNAG_HD_INLINE CellCoord grid_cell_coord(const GridSpec& grid, std::uint64_t id) {
  const auto nx = static_cast<std::uint64_t>(grid.dims[0]), ny = static_cast<std::uint64_t>(grid.dims[1]);
  return {static_cast<std::int32_t>(id % nx), static_cast<std::int32_t>((id / nx) % ny),
          static_cast<std::int32_t>(id / (nx * ny))};
}

/// grid_cell_id(grid, a) < grid_cell_id(grid, b) for two cells of a grid
/// (coordinates in [0, dims)), without the grid: ids order cells by (z, y, x).
SNAG_HD_INLINE bool cell_precedes(CellCoord a, CellCoord b) {
  if (a.z != b.z) return a.z < b.z;
  if (a.y != b.y) return a.y < b.y;
  return a.x < b.x;
}

/// Cell type: parity bits x | y<<1 | z<<2, in 0..7.
SNAG_HD_INLINE unsigned cell_type(CellCoord c) {
  return static_cast<unsigned>((c.x & 1) | ((c.y & 1) << 1) | ((c.z & 1) << 2));
}

/// A box of cells [lo, hi] (inclusive).
struct CellBlock {
  CellCoord lo, hi;
};

SNAG_HD_INLINE bool block_contains(const CellBlock& b, CellCoord c) {
  return c.x >= b.lo.x && c.x <= b.hi.x && c.y >= b.lo.y && c.y <= b.hi.y && c.z >= b.lo.z && c.z <= b.hi.z;
}

SNAG_HD_INLINE std::uint64_t block_cell_count(const CellBlock& b) {
  return static_cast<std::uint64_t>(b.hi.x - b.lo.x + 1) * static_cast<std::uint64_t>(b.hi.y - b.lo.y + 1) *
         static_cast<std::uint64_t>(b.hi.z - b.lo.z + 1);
}

/// The k-th cell of a block, x fastest (k < block_cell_count).
SNAG_HD_INLINE CellCoord block_cell(const CellBlock& b, std::uint64_t k) {
  const std::uint64_t nx = static_cast<std::uint64_t>(b.hi.x - b.lo.x + 1);
  const std::uint64_t ny = static_cast<std::uint64_t>(b.hi.y - b.lo.y + 1);
  CellCoord c;
  c.x = b.lo.x + static_cast<std::int32_t>(k % nx);
  c.y = b.lo.y + static_cast<std::int32_t>((k / nx) % ny);
  c.z = b.lo.z + static_cast<std::int32_t>(k / (nx * ny));
  return c;
}

/// Cells overlapped by the box [lo, hi].
SNAG_HD_INLINE CellBlock grid_block_of(const GridSpec& grid, Vec3 lo, Vec3 hi) {
  return {grid_cell_of(grid, lo), grid_cell_of(grid, hi)};
}

}  // namespace snag
