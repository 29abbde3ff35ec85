// Virtual subdivision of the scene's triangles, level by level, into leaf
// triangles small enough for the grid, with their DOPs and cells.
//
// Wong, Leach, Zambetta, virtual subdivision chapter, Algorithm 1 and section
// 5.3.2 (Figure 5.4): every triangle of the current list is examined in one
// parallel pass; those that are too large are split (Loop 1-to-4, or time
// halving for CCD, Figure 5.3) into the next level's list, the others become
// leaves. Children of one parent are written next to each other, so leaves of
// one root in one level are coherent in the leaf list.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "libcd/bounding_volume/dop18.hpp"
#include "libcd/grid/control_bits.hpp"
#include "libcd/grid/uniform_grid.hpp"
#include "libcd/scene/scene.hpp"
#include "libcd/subdivision/virtual_triangle.hpp"

namespace snag {

/// A virtual triangle accepted for registration: its swept 18-DOP over its
/// slot (rounding pad and thickness included) and its cells. The block is the
/// set of cells overlapped by the DOP's axis slabs; the home cell holds the
/// centre of its bounding sphere.
struct Leaf {
  VirtualTriangle triangle;
  Dop18 dop;
  LeafCells cells;
};

/// What the pair tests read of a leaf: its root, its time slot and its cells
/// (92 bytes; not the corners, which only the leaf's own DOP needed). Both
/// back ends copy the leaves in registration order (cell by cell), so that
/// the leaves of one cell lie side by side and the tests of a cell read them
/// from cache; a cell of n leaves is read about n times over on the CPU, so
/// every byte here is paid for on each of its tests (the GPU's tiles read
/// each leaf once per tile and test it as masks around the cell, LocalCells).
struct RegisteredLeaf {
  Index root = 0;                ///< the leaf's root triangle
  std::uint32_t slot_depth = 0;  ///< its time slot (VirtualTriangle::slot_depth, slot_index)
  std::uint32_t slot_index = 0;
  LeafCells cells;
};
static_assert(sizeof(RegisteredLeaf) == 92, "RegisteredLeaf: the CPU's pair tests read all of it on every test");

SNAG_HD_INLINE RegisteredLeaf registered_leaf(const Leaf& leaf) {
  return RegisteredLeaf{leaf.triangle.root, leaf.triangle.slot_depth, leaf.triangle.slot_index, leaf.cells};
}

/// slots_nested of the two leaves' time slots.
SNAG_HD_INLINE bool slots_nested(const RegisteredLeaf& a, const RegisteredLeaf& b) {
  return slots_nested(a.slot_depth, a.slot_index, b.slot_depth, b.slot_index);
}

/// What one subdivision level did.
struct SubdivisionLevelCounts {
  std::size_t triangles = 0;   ///< virtual triangles examined at this level
  std::size_t accepted = 0;    ///< became leaves (oversized included)
  std::size_t subdivided = 0;  ///< Loop-split into 4
  std::size_t halved = 0;      ///< time slot halved
  std::size_t oversized = 0;   ///< accepted at both safety limits while still too large
};

/// Subdivides every triangle of the scene as needed for the grid.
/// @param x_t0, x_t1   #V global positions at the start/end of the step (the
///                     same array twice for static detection).
/// @param grid         the grid (cell size decides what is too large).
/// @param thickness    ≥ 0, scene units.
/// @param max_levels   safety limit on Loop levels per root.
/// @param max_halvings safety limit on time halvings per root.
/// @param[out] levels  one entry per level examined.
/// @return the leaves, level by level, in list order (deterministic).
std::vector<Leaf> subdivide_virtually(const Scene& scene, const std::vector<Vec3>& x_t0,
                                      const std::vector<Vec3>& x_t1, const GridSpec& grid, double thickness,
                                      std::uint32_t max_levels, std::uint32_t max_halvings,
                                      std::vector<SubdivisionLevelCounts>& levels);

}  // namespace snag
