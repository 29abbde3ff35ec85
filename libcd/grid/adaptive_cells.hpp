// Adaptive subdivision of crowded cells: a hierarchical grid over the
// uniform grid of the virtual subdivision scheme, for uneven triangle
// distributions (many small leaves crowding few cells).
//
// Wong, Leach, Zambetta's virtual subdivision chapter leaves uneven
// distributions to its next chapter, a hierarchical grid whose cell size
// adapts to the local density (two-level grids: Fan et al. 2011; multi-level:
// Eitz and Lixu 2007). This is an equivalent adaptive subdivision of crowded
// cells, a region octree over each crowded cell of the uniform grid (Samet,
// "Foundations of multidimensional and metric data structures", 2006): a cell holding more than
// `cell_limit` registrations is split into its 2×2×2 children, recursively, to
// at most `max_depth` levels below the uniform grid. A leaf goes down into
// the children only while its box spans at most two children per axis (so it
// is registered in at most 8 cells per level); a larger leaf stays in the
// crowded cell ("stuck") and is tested there against every leaf of the cell.
//
// Coordinates. Every leaf's box (the axis slabs of its DOP) is mapped once to
// cells of the finest level, size cell_size/2^depth, as floor((v - origin) /
// cell_size · 2^depth) clamped to the grid; a cell of level l holds the fine
// cells whose coordinates shifted right by depth - l equal its own. The
// mapping is monotone, so two boxes that share a point share a fine cell, and
// the levels nest exactly (a shift, no second rounding).
//
// Ownership (each pair tested in one cell). Let p be the fine cell at the low
// corner of the intersection of two leaves' fine blocks (per axis the larger
// low coordinate). Both leaves hold p, so both are registered in the level-0
// cell over p, and at every crowded cell over p each either goes down into
// the child over p or is stuck. The pair is tested in the first cell over p
// where the cell is final (not split) or one of the two is stuck: the cell
// that holds p and lists the pair among its tests (a final cell tests all its
// pairs, a crowded one the pairs with a stuck leaf). Before that cell both
// went down, so no coarser cell over p tests the pair; after it, no finer
// cell lists the pair. Exactly one cell tests each pair of leaves whose fine
// blocks meet; a pair whose blocks do not meet is tested nowhere (its DOPs
// are disjoint).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "libcd/bounding_volume/dop18.hpp"
#include "libcd/core/host_device.hpp"
#include "libcd/grid/uniform_grid.hpp"
#include "libcd/subdivision/virtual_subdivision.hpp"

namespace snag {

/// The deepest subdivision accepted: 2^8 fine cells per grid cell and axis
/// keep fine coordinates below 2^29 for the largest grid (2^21 cells per axis).
constexpr int kMaxAdaptiveDepth = 8;

/// A leaf's box in cells of the finest level (inclusive).
using FineBlock = CellBlock;

/// A cell whose pairs are tested: `count` members from `first` in
/// AdaptiveCells::members; the pairs (i, j), i < j, with i < `stuck` are
/// tested (stuck == count for a final cell: all pairs).
struct TestCell {
  std::uint64_t first = 0;
  std::uint32_t count = 0;
  std::uint32_t stuck = 0;
  CellCoord coord;      ///< at its level
  std::int32_t level = 0;  ///< 0 = the uniform grid
};

/// The hierarchy, as the pair tests read it.
struct AdaptiveCells {
  int depth = 0;                        ///< levels the fine coordinates resolve
  std::vector<FineBlock> blocks;        ///< #leaves fine blocks
  std::vector<TestCell> cells;          ///< cells with at least one test, level by level, by key
  std::vector<std::uint32_t> members;   ///< leaf ids, cell by cell: stuck ones first, each part by leaf id
  std::size_t registrations = 0;        ///< (cell, leaf) registrations, all levels
  std::size_t cells_subdivided = 0;     ///< crowded cells split into children
  std::size_t stuck_registrations = 0;  ///< registrations kept in a crowded cell
  int deepest_level = 0;                ///< deepest level with a registration
};

/// The fine cell of coordinate v along `axis`, clamped to the grid.
SNAG_HD_INLINE std::int32_t fine_axis_cell(const GridSpec& grid, int depth, double v, int axis) {
  const double q = std::floor(std::ldexp((v - grid.origin[axis]) / grid.cell_size, depth));
  const double top = std::ldexp(static_cast<double>(grid.dims[axis]), depth) - 1;
  return static_cast<std::int32_t>(q < 0 ? 0 : (q > top ? top : q));
}

/// The fine block of a DOP's axis slabs.
SNAG_HD_INLINE FineBlock fine_block_of(const GridSpec& grid, int depth, const Dop18& dop) {
  FineBlock b;
  b.lo = {fine_axis_cell(grid, depth, dop.lo[0], 0), fine_axis_cell(grid, depth, dop.lo[1], 1),
          fine_axis_cell(grid, depth, dop.lo[2], 2)};
  b.hi = {fine_axis_cell(grid, depth, dop.hi[0], 0), fine_axis_cell(grid, depth, dop.hi[1], 1),
          fine_axis_cell(grid, depth, dop.hi[2], 2)};
  return b;
}

/// The block at level `level` (coordinates shifted right by depth - level).
SNAG_HD_INLINE CellBlock block_at_level(const FineBlock& b, int depth, int level) {
  const int s = depth - level;
  return {{b.lo.x >> s, b.lo.y >> s, b.lo.z >> s}, {b.hi.x >> s, b.hi.y >> s, b.hi.z >> s}};
}

/// True when the block spans at most two cells on every axis: a leaf whose
/// block at the children's level fits so goes down into them.
SNAG_HD_INLINE bool fits_two_per_axis(const CellBlock& b) {
  return b.hi.x - b.lo.x <= 1 && b.hi.y - b.lo.y <= 1 && b.hi.z - b.lo.z <= 1;
}

/// Child `octant` (0..7: x in bit 0, y in bit 1, z in bit 2) of a cell, at the next level.
SNAG_HD_INLINE CellCoord child_cell(CellCoord parent, unsigned octant) {
  return {2 * parent.x + static_cast<std::int32_t>(octant & 1), 2 * parent.y + static_cast<std::int32_t>((octant >> 1) & 1),
          2 * parent.z + static_cast<std::int32_t>((octant >> 2) & 1)};
}

/// True when the pair of leaves with fine blocks a and b, both listed in the
/// test cell at `level` and `coord`, is tested there (the ownership rule
/// above): their blocks meet and the low corner of the meeting lies in the cell.
SNAG_HD_INLINE bool adaptive_cell_owns_pair(const FineBlock& a, const FineBlock& b, int depth, int level,
                                            CellCoord coord) {
  const CellCoord corner{a.lo.x > b.lo.x ? a.lo.x : b.lo.x, a.lo.y > b.lo.y ? a.lo.y : b.lo.y,
                         a.lo.z > b.lo.z ? a.lo.z : b.lo.z};
  if (corner.x > (a.hi.x < b.hi.x ? a.hi.x : b.hi.x) || corner.y > (a.hi.y < b.hi.y ? a.hi.y : b.hi.y) ||
      corner.z > (a.hi.z < b.hi.z ? a.hi.z : b.hi.z))
    return false;
  const int s = depth - level;
  return (corner.x >> s) == coord.x && (corner.y >> s) == coord.y && (corner.z >> s) == coord.z;
}

/// Builds the hierarchy over `grid` for the leaves' DOPs.
/// @param max_depth   levels below the grid, in [0, kMaxAdaptiveDepth].
/// @param cell_limit  a cell with more registrations than this is split (≥ 1).
AdaptiveCells build_adaptive_cells(const std::vector<Leaf>& leaves, const GridSpec& grid, int max_depth,
                                   std::size_t cell_limit);

}  // namespace snag
