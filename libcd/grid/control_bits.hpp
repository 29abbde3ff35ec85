// Home and phantom cells, control bits, and the rule that decides in which
// cell a pair of registered triangles is tested.
//
// Grand, "Broad-phase collision detection with CUDA", GPU Gems 3 ch. 32, 2007:
// an object is registered in every cell it overlaps (at most 2×2×2): its home
// cell holds its centre, the others are phantom cells; per-object control bits
// record the types of the cells it overlaps, and a pair is tested only in a
// cell where one of the two is at home.
// Wong, Leach, Zambetta, virtual subdivision chapter, section 5.3.3 and
// Figure 5.8: control bits extended with the centroid cells of sibling child
// triangles, so that a root pair is tested in one cell only.
//
// Control-bit word (32 bits) of a leaf:
//   bits 0-7   overlap mask: bit T set when the leaf overlaps a cell of type T
//   bits 8-10  type of the home cell
//   bits 11-12 number of accepted siblings (0..3)
//   bits 13-21 their home cell types, 3 bits each
// The types are a necessary test ("cell c can be in this block only if bit
// type(c) is set"); the exact test compares cell coordinates, which a leaf
// also carries (home, block, sibling homes).
//
// The test rule (proved in the file comment of broad_phase/virtual_subdivision_grid.hpp):
// for leaves a and b registered in cell C, let R be the set of cells that are
//   the home of a or of an accepted sibling of a, and lie in b's block, or
//   the home of b or of an accepted sibling of b, and lie in a's block.
// The pair is tested in C iff C is the cell of smallest id in R, or R is
// empty (both phantom wherever they meet: the fallback) and C is the low
// corner of the intersection of the two blocks (its cell of smallest id). In
// every cell of R one of the two roots is registered at home and the other is
// registered; both are registered in the corner cell; so a skipped pair is
// always passed on to a cell of R or to a cell of smaller id, and some cell
// tests it. For two single leaves (no siblings) the pair is tested in exactly
// one of the cells they share.
#pragma once

#include <cstdint>

#include "libcd/core/host_device.hpp"
#include "libcd/grid/uniform_grid.hpp"

namespace snag {

/// Where a leaf is registered: its home cell, its block of cells, its control
/// bits, and the home cells of its accepted siblings.
struct LeafCells {
  CellCoord home;
  CellBlock block;
  std::uint32_t control_bits = 0;
  std::uint32_t sibling_count = 0;
  CellCoord sibling_home[3];
};

/// Overlap mask of a block: bit T set for every cell type T in it.
SNAG_HD_INLINE std::uint32_t overlap_mask(const CellBlock& b) {
  std::uint32_t mask = 0;
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const CellCoord c{b.lo.x + dx, b.lo.y + dy, b.lo.z + dz};
        if (c.x <= b.hi.x && c.y <= b.hi.y && c.z <= b.hi.z) mask |= 1u << cell_type(c);
      }
  return mask;
}

/// Builds the control-bit word of a leaf from its cells (sibling fields included).
SNAG_HD_INLINE std::uint32_t make_control_bits(const LeafCells& cells) {
  std::uint32_t bits = overlap_mask(cells.block) | (cell_type(cells.home) << 8) | (cells.sibling_count << 11);
  for (std::uint32_t s = 0; s < cells.sibling_count; ++s) bits |= cell_type(cells.sibling_home[s]) << (13 + 3 * s);
  return bits;
}

SNAG_HD_INLINE unsigned control_bits_home_type(std::uint32_t bits) { return (bits >> 8) & 7u; }
SNAG_HD_INLINE unsigned control_bits_sibling_count(std::uint32_t bits) { return (bits >> 11) & 3u; }
SNAG_HD_INLINE unsigned control_bits_sibling_type(std::uint32_t bits, unsigned s) { return (bits >> (13 + 3 * s)) & 7u; }

/// True when cell c is one of the cells the leaf is registered in: the
/// control bits reject most cells, the coordinates decide.
SNAG_HD_INLINE bool leaf_overlaps_cell(const LeafCells& leaf, CellCoord c) {
  if (((leaf.control_bits >> cell_type(c)) & 1u) == 0) return false;
  return block_contains(leaf.block, c);
}

/// Why a pair of leaves registered in one cell is or is not tested there.
enum class CellPairVerdict : std::uint8_t {
  kTest,                  ///< C is the smallest cell of R
  kTestFallback,          ///< R is empty (both phantom wherever they meet) and C is the blocks' low corner
  kSkipControlBits,       ///< tested elsewhere: the smallest cell of R is the home of a or b
  kSkipExtendedBits,      ///< tested elsewhere: the smallest cell of R is a sibling's home only
};

/// The test rule above for leaves a and b, both registered in `cell`. Cells
/// are ordered by id (cell_precedes: the grid is not needed); a sibling's home
/// loops over all three slots with the count as a condition, which a GPU warp
/// runs without diverging on the count.
SNAG_HD_INLINE CellPairVerdict cell_pair_verdict(const LeafCells& a, const LeafCells& b, CellCoord cell) {
  bool found = false, best_is_own_home = false;
  CellCoord best;
  auto consider_side = [&](const LeafCells& self, const LeafCells& other) {
    if (leaf_overlaps_cell(other, self.home) &&
        (!found || cell_precedes(self.home, best) || (self.home == best && !best_is_own_home))) {
      best = self.home;
      best_is_own_home = true;
      found = true;
    }
    for (std::uint32_t k = 0; k < 3; ++k) {
      if (k < self.sibling_count && leaf_overlaps_cell(other, self.sibling_home[k]) &&
          (!found || cell_precedes(self.sibling_home[k], best))) {
        best = self.sibling_home[k];
        best_is_own_home = false;
        found = true;
      }
    }
  };
  consider_side(a, b);
  consider_side(b, a);
  if (!found) {
    const CellCoord corner{a.block.lo.x > b.block.lo.x ? a.block.lo.x : b.block.lo.x,
                           a.block.lo.y > b.block.lo.y ? a.block.lo.y : b.block.lo.y,
                           a.block.lo.z > b.block.lo.z ? a.block.lo.z : b.block.lo.z};
    return corner == cell ? CellPairVerdict::kTestFallback : CellPairVerdict::kSkipControlBits;
  }
  if (best == cell) return CellPairVerdict::kTest;
  return best_is_own_home ? CellPairVerdict::kSkipControlBits : CellPairVerdict::kSkipExtendedBits;
}

/// The test rule in one cell C as bit masks: the form the GPU's pair tests
/// evaluate, without branches, on every test of a tile (the leaves' masks are
/// made once per tile, the rule per test is a few integer operations).
///
/// When each leaf's block lies within one cell of C along every axis (the
/// usual case: a leaf registered in C, no larger than a cell, spans at most
/// two cells per axis), every cell of R lies in one of the two blocks, so
/// within those 27 cells. They are numbered (dx + 1) + 3 (dy + 1) + 9 (dz +
/// 1) for the offset (dx, dy, dz) from C, which orders them as
/// cell_precedes does; the smallest cell of R is then its lowest bit. A
/// home or sibling home farther from C lies in neither block and takes no
/// bit. A leaf whose block reaches farther is marked `wide`, and the caller
/// decides its pairs with cell_pair_verdict of the LeafCells.
struct LocalCells {
  std::uint32_t block = 0;     ///< bits: the cells of the leaf's block
  std::uint32_t home = 0;      ///< bit of its home cell
  std::uint32_t siblings = 0;  ///< bits: its accepted siblings' homes
  /// bits 0-2: the block's low corner equals C along x, y, z; bits 3-5: it
  /// lies above C along that axis; bit 6: wide (the masks do not apply).
  std::uint32_t corner = 0;
  SNAG_HD_INLINE bool wide() const { return (corner >> 6) & 1u; }
};

/// Bit of cell c among the 27 cells around `cell` (LocalCells), 0 when farther.
SNAG_HD_INLINE std::uint32_t local_cell_bit(CellCoord c, CellCoord cell) {
  const int dx = c.x - cell.x, dy = c.y - cell.y, dz = c.z - cell.z;
  const bool near = (dx >= -1) & (dx <= 1) & (dy >= -1) & (dy <= 1) & (dz >= -1) & (dz <= 1);
  return near ? 1u << ((dx + 1) + 3 * (dy + 1) + 9 * (dz + 1)) : 0u;
}

/// The leaf's masks around `cell`.
SNAG_HD_INLINE LocalCells local_cells(const LeafCells& leaf, CellCoord cell) {
  LocalCells local;
  const CellBlock& b = leaf.block;
  const bool wide = (b.lo.x < cell.x - 1) | (b.hi.x > cell.x + 1) | (b.lo.y < cell.y - 1) | (b.hi.y > cell.y + 1) |
                    (b.lo.z < cell.z - 1) | (b.hi.z > cell.z + 1);
  if (wide) {
    local.corner = 1u << 6;
    return local;
  }
  for (std::int32_t z = b.lo.z; z <= b.hi.z; ++z)
    for (std::int32_t y = b.lo.y; y <= b.hi.y; ++y)
      for (std::int32_t x = b.lo.x; x <= b.hi.x; ++x) local.block |= local_cell_bit({x, y, z}, cell);
  local.home = local_cell_bit(leaf.home, cell);
  for (std::uint32_t k = 0; k < leaf.sibling_count; ++k) local.siblings |= local_cell_bit(leaf.sibling_home[k], cell);
  local.corner = static_cast<std::uint32_t>(b.lo.x == cell.x) | static_cast<std::uint32_t>(b.lo.y == cell.y) << 1 |
                 static_cast<std::uint32_t>(b.lo.z == cell.z) << 2 | static_cast<std::uint32_t>(b.lo.x > cell.x) << 3 |
                 static_cast<std::uint32_t>(b.lo.y > cell.y) << 4 | static_cast<std::uint32_t>(b.lo.z > cell.z) << 5;
  return local;
}

/// cell_pair_verdict of two leaves in the cell their masks were made
/// around, neither wide. The fallback's corner, the larger of the two low
/// corners, is the cell when along each axis one low corner is at the cell
/// and neither lies above it.
SNAG_HD_INLINE CellPairVerdict cell_pair_verdict(const LocalCells& a, const LocalCells& b) {
  const std::uint32_t own = (a.home & b.block) | (b.home & a.block);
  const std::uint32_t r = own | (a.siblings & b.block) | (b.siblings & a.block);
  if (r == 0)
    return ((a.corner | b.corner) & 63u) == 7u ? CellPairVerdict::kTestFallback : CellPairVerdict::kSkipControlBits;
  const std::uint32_t smallest = r & (~r + 1u);
  if (smallest == local_cell_bit({0, 0, 0}, {0, 0, 0})) return CellPairVerdict::kTest;
  return (smallest & own) != 0 ? CellPairVerdict::kSkipControlBits : CellPairVerdict::kSkipExtendedBits;
}

}  // namespace snag
