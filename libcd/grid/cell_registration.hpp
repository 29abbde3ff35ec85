// Registration of leaf triangles in the grid cells they overlap, one sort by
// cell id, and one scan that removes duplicate registrations of a root in a
// cell, keeping a home registration where there is one.
//
// Grand, GPU Gems 3 ch. 32 (2007): cell-object array, radix sort by cell id.
// Wong, Leach, Zambetta, virtual subdivision chapter, section 5.3.3, Figures
// 5.5-5.7: one sort by cell id; since the leaves of one root in one level are
// coherent, the sort puts their registrations of a cell next to each other and
// a scan removes all but one, with home priority. Registrations of one root
// that come from different levels are not adjacent and stay (the chapter's
// T00 / T020 case); the pair rule stays correct with them, they only cause
// duplicate tests, which are counted.
//
// The "root" here is the (root triangle, time slot) unit: leaves of different
// time slots are different units and are never merged.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "libcd/core/host_device.hpp"
#include "libcd/grid/uniform_grid.hpp"
#include "libcd/subdivision/virtual_subdivision.hpp"

namespace snag {

/// The grid after registration: for each used cell, the leaves registered in it.
struct CellLists {
  std::vector<std::uint64_t> cell_ids;  ///< #C used cell ids, ascending
  std::vector<std::uint64_t> first;     ///< #C+1 offsets into leaves
  std::vector<std::uint32_t> leaves;    ///< leaf ids, cell by cell, in leaf-list order
};

struct RegistrationCounts {
  std::size_t registrations = 0;       ///< (cell, leaf) pairs before the scan
  std::size_t home = 0;                ///< of which in the leaf's home cell
  std::size_t phantom = 0;             ///< of which in another cell
  std::size_t duplicates_removed = 0;  ///< removed by the scan
  std::size_t kept = 0;                ///< left after the scan
};

/// One leaf in one cell; sorted by cell, then leaf (a stable sort by cell).
struct CellRegistration {
  std::uint64_t cell;
  std::uint32_t leaf;
  bool operator<(const CellRegistration& o) const { return cell != o.cell ? cell < o.cell : leaf < o.leaf; }
};

/// True when two leaves belong to the same (root, time slot) unit.
SNAG_HD_INLINE bool same_unit(const VirtualTriangle& a, const VirtualTriangle& b) {
  return a.root == b.root && a.slot_depth == b.slot_depth && a.slot_index == b.slot_index;
}

/// Registers every leaf in every cell of its block, sorts by (cell id, leaf id)
/// — the leaf id only breaks ties, as a stable radix sort by cell id would —
/// and removes adjacent duplicate registrations of one unit in one cell,
/// keeping the first home registration of the run, else its first.
CellLists register_leaves(const std::vector<Leaf>& leaves, const GridSpec& grid, RegistrationCounts& counts);

}  // namespace snag
