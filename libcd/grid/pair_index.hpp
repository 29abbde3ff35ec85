// One candidate test per work item: per-cell pair counts are prefix-summed;
// work item w finds its cell by binary search over the sums and its pair
// (i, j), i < j, within the cell by inverting the triangular numbering.
//
// Pabst, Koch, Straßer, "Fast and scalable CPU/GPU collision detection for
// rigid and deformable surfaces", CGF 29(5), 2010; Fan, Wang, Dong, Sun,
// "Efficient GPU-based collision detection for deformable models", 2011
// (one thread per test, a prefix sum instead of a tree).
#pragma once

#include <cmath>
#include <cstdint>

#include "libcd/core/host_device.hpp"

namespace snag {

/// Number of unordered pairs of n items.
SNAG_HD_INLINE std::uint64_t pair_count(std::uint64_t n) { return n < 2 ? 0 : n * (n - 1) / 2; }

/// The cell c in [lo, hi) with first[c] <= w < first[c+1], given
/// first[lo] <= w and first[hi] > w (or hi = cells): a binary search.
SNAG_HD_INLINE std::uint64_t cell_of_work_item_between(const std::uint64_t* first, std::uint64_t lo, std::uint64_t hi,
                                                       std::uint64_t w) {
  while (hi - lo > 1) {
    const std::uint64_t mid = lo + (hi - lo) / 2;
    if (first[mid] <= w) lo = mid; else hi = mid;
  }
  return lo;
}

/// The cell c with first[c] <= w < first[c+1], for first[0..cells] ascending
/// (first[0] = 0, first[cells] = total work).
SNAG_HD_INLINE std::uint64_t cell_of_work_item(const std::uint64_t* first, std::uint64_t cells, std::uint64_t w) {
  return cell_of_work_item_between(first, 0, cells, w);
}

/// cell_of_work_item(first, cells, w) found from a cell `from` with
/// first[from] <= w (the cell of an earlier work item: cells ascend with the
/// work items): a galloping search forward from it, one read when w lies in
/// the same cell, about 2·log2(d) when it lies d cells further.
SNAG_HD_INLINE std::uint64_t cell_of_work_item_from(const std::uint64_t* first, std::uint64_t cells,
                                                    std::uint64_t from, std::uint64_t w) {
  std::uint64_t lo = from, hi = from + 1, step = 1;  // first[lo] <= w
  while (hi < cells && first[hi] <= w) {
    lo = hi;
    step *= 2;
    hi = cells - lo > step ? lo + step : cells;
  }
  return cell_of_work_item_between(first, lo, hi, w);
}

/// Pair k (0 <= k < pair_count(n)) of n items, numbered row by row:
/// (0,1), (0,2), ..., (0,n-1), (1,2), ... Returns i < j.
SNAG_HD_INLINE void pair_from_index(std::uint64_t n, std::uint64_t k, std::uint64_t& i, std::uint64_t& j) {
  // Rows before row i hold S(i) = i·(2n - i - 1)/2 pairs; find the largest i with S(i) <= k.
  const double nd = static_cast<double>(n);
  const double disc = (2 * nd - 1) * (2 * nd - 1) - 8.0 * static_cast<double>(k);
  double guess = std::floor(((2 * nd - 1) - std::sqrt(disc > 0 ? disc : 0)) / 2);
  std::uint64_t row = guess < 0 ? 0 : static_cast<std::uint64_t>(guess);
  if (row > n - 2) row = n - 2;
  auto rows_before = [n](std::uint64_t r) { return r * (2 * n - r - 1) / 2; };
  while (row > 0 && rows_before(row) > k) --row;        // correct rounding of the guess
  while (row + 1 <= n - 2 && rows_before(row + 1) <= k) ++row;
  i = row;
  j = k - rows_before(row) + row + 1;
}

}  // namespace snag
