#include "libcd/grid/adaptive_cells.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>

#include "libcd/grid/cell_registration.hpp"

namespace snag {

namespace {

/// One leaf in one cell of a level; `cell` is the cell's key in that level.
using Registration = CellRegistration;

/// Level 0: every leaf in every uniform-grid cell of its block, keyed by cell id.
std::vector<Registration> register_in_grid(const std::vector<FineBlock>& blocks, const GridSpec& grid, int depth) {
  std::vector<std::size_t> offset(blocks.size() + 1, 0);
  for (std::size_t i = 0; i < blocks.size(); ++i)
    offset[i + 1] = offset[i] + block_cell_count(block_at_level(blocks[i], depth, 0));
  std::vector<Registration> regs(offset.back());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 1024), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const CellBlock b = block_at_level(blocks[i], depth, 0);
      const std::uint64_t k_end = block_cell_count(b);
      for (std::uint64_t k = 0; k < k_end; ++k)
        regs[offset[i] + k] = {grid_cell_id(grid, block_cell(b, k)), static_cast<std::uint32_t>(i)};
    }
  });
  return regs;
}

}  // namespace

AdaptiveCells build_adaptive_cells(const std::vector<Leaf>& leaves, const GridSpec& grid, int max_depth,
                                   std::size_t cell_limit) {
  AdaptiveCells out;
  out.depth = std::clamp(max_depth, 0, kMaxAdaptiveDepth);
  const int depth = out.depth;
  if (cell_limit < 1) cell_limit = 1;
  out.blocks.resize(leaves.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) out.blocks[i] = fine_block_of(grid, depth, leaves[i].dop);
  });

  std::vector<Registration> regs = register_in_grid(out.blocks, grid, depth);
  std::vector<CellCoord> parents;  // coordinates of the crowded cells of the level above
  std::vector<std::uint32_t> stuck, pushed;
  for (int level = 0; !regs.empty(); ++level) {
    out.registrations += regs.size();
    out.deepest_level = level;
    tbb::parallel_sort(regs.begin(), regs.end());
    std::vector<Registration> next;
    std::vector<CellCoord> crowded;
    for (std::size_t begin = 0; begin < regs.size();) {
      std::size_t end = begin + 1;
      while (end < regs.size() && regs[end].cell == regs[begin].cell) ++end;
      const std::uint64_t key = regs[begin].cell;
      CellCoord coord;
      if (level == 0) {
        coord = grid_cell_coord(grid, key);
      } else {
        coord = child_cell(parents[key >> 3], static_cast<unsigned>(key & 7));
      }
      const std::size_t n = end - begin;
      stuck.clear();
      pushed.clear();
      if (n <= cell_limit || level == depth) {
        for (std::size_t r = begin; r < end; ++r) stuck.push_back(regs[r].leaf);  // final: all pairs
      } else {
        // Crowded: the leaves that fit the children go down, the others stay.
        ++out.cells_subdivided;
        const std::uint64_t parent_index = crowded.size();
        crowded.push_back(coord);
        for (std::size_t r = begin; r < end; ++r) {
          const std::uint32_t leaf = regs[r].leaf;
          const CellBlock child_block = block_at_level(out.blocks[leaf], depth, level + 1);
          if (!fits_two_per_axis(child_block)) {
            stuck.push_back(leaf);
            continue;
          }
          pushed.push_back(leaf);
          for (std::uint32_t octant = 0; octant < 8; ++octant) {
            if (block_contains(child_block, child_cell(coord, octant))) next.push_back({parent_index * 8 + octant, leaf});
          }
        }
        out.stuck_registrations += stuck.size();
      }
      if (!stuck.empty() && stuck.size() + pushed.size() >= 2) {
        TestCell cell;
        cell.first = out.members.size();
        cell.count = static_cast<std::uint32_t>(stuck.size() + pushed.size());
        cell.stuck = static_cast<std::uint32_t>(stuck.size());
        cell.coord = coord;
        cell.level = level;
        out.members.insert(out.members.end(), stuck.begin(), stuck.end());
        out.members.insert(out.members.end(), pushed.begin(), pushed.end());
        out.cells.push_back(cell);
      }
      begin = end;
    }
    regs.swap(next);
    parents.swap(crowded);
  }
  return out;
}

}  // namespace snag
