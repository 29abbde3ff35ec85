#include "libcd/grid/cell_registration.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_scan.h>
#include <tbb/parallel_sort.h>

namespace snag {

namespace {

using Registration = CellRegistration;

std::size_t exclusive_scan(std::vector<std::size_t>& values) {
  const std::size_t n = values.size();
  return tbb::parallel_scan(
      tbb::blocked_range<std::size_t>(0, n, 4096), std::size_t(0),
      [&](const tbb::blocked_range<std::size_t>& r, std::size_t sum, bool final) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          const std::size_t v = values[i];
          if (final) values[i] = sum;
          sum += v;
        }
        return sum;
      },
      [](std::size_t a, std::size_t b) { return a + b; });
}

}  // namespace

CellLists register_leaves(const std::vector<Leaf>& leaves, const GridSpec& grid, RegistrationCounts& counts) {
  counts = RegistrationCounts{};
  // Registration: one (cell, leaf) item per cell of each leaf's block.
  std::vector<std::size_t> offset(leaves.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) offset[i] = block_cell_count(leaves[i].cells.block);
  });
  const std::size_t total = exclusive_scan(offset);
  std::vector<Registration> regs(total);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 1024), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const CellBlock& b = leaves[i].cells.block;
      const std::uint64_t k_end = block_cell_count(b);
      for (std::uint64_t k = 0; k < k_end; ++k)
        regs[offset[i] + k] = {grid_cell_id(grid, block_cell(b, k)), static_cast<std::uint32_t>(i)};
    }
  });
  counts.registrations = total;
  counts.home = leaves.size();  // every leaf's home cell lies in its block
  counts.phantom = total - leaves.size();

  // One sort by cell id.
  tbb::parallel_sort(regs.begin(), regs.end());

  // One scan: in each run of adjacent registrations of one unit in one cell,
  // keep the first home registration, else the first.
  auto is_home = [&](const Registration& g) {
    return grid_cell_id(grid, leaves[g.leaf].cells.home) == g.cell;
  };
  auto same_run = [&](std::size_t i, std::size_t j) {
    return regs[i].cell == regs[j].cell && same_unit(leaves[regs[i].leaf].triangle, leaves[regs[j].leaf].triangle);
  };
  std::vector<std::size_t> keep(total, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, total, 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      if (i > 0 && same_run(i, i - 1)) continue;  // not the head of a run
      std::size_t chosen = i;
      for (std::size_t j = i; j < total && same_run(j, i); ++j) {
        if (is_home(regs[j])) {
          chosen = j;
          break;
        }
      }
      keep[chosen] = 1;
    }
  });
  std::vector<std::size_t> position = keep;
  const std::size_t kept = exclusive_scan(position);
  counts.kept = kept;
  counts.duplicates_removed = total - kept;

  // Compact, and find the cells (runs of equal cell id).
  std::vector<Registration> compact(kept);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, total, 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i)
      if (keep[i]) compact[position[i]] = regs[i];
  });
  regs.clear();
  regs.shrink_to_fit();
  std::vector<std::size_t> cell_start(kept);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kept, 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) cell_start[i] = (i == 0 || compact[i].cell != compact[i - 1].cell);
  });
  std::vector<std::size_t> cell_index = cell_start;
  const std::size_t cells = exclusive_scan(cell_index);
  CellLists lists;
  lists.cell_ids.resize(cells);
  lists.first.resize(cells + 1);
  lists.leaves.resize(kept);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kept, 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      lists.leaves[i] = compact[i].leaf;
      if (cell_start[i]) {
        lists.cell_ids[cell_index[i]] = compact[i].cell;
        lists.first[cell_index[i]] = i;
      }
    }
  });
  lists.first[cells] = kept;
  return lists;
}

}  // namespace snag
