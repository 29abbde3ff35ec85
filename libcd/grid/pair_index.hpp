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

/// Square tiles of a cell's tests, for the GPU's pair tests: the rows
/// [i0, i1) of n items' row-by-row numbering (the pairs i < j with i0 <= i <
/// i1) cut at multiples of kPairTileSide, rows and columns alike. Row tile I
/// meets the column tiles I, I + 1, ..., the last: a block of threads reads a
/// tile's rows and columns once and runs every test between them, instead of
/// reading two items per test.
constexpr std::uint64_t kPairTileSide = 64;

/// The items of one tile: rows [row_begin, row_end), columns [column_begin,
/// column_end); its tests are the pairs (i, j) of the two with i < j.
struct PairTile {
  std::uint64_t row_begin = 0, row_end = 0, column_begin = 0, column_end = 0;
};

/// The row tiles of the rows [i0, i1) of n items (i0 <= i1 <= n): rows from
/// n - 1 on clipped off, the first row tile, and m, the column tiles it meets
/// (row tile first + k meets m - k, so the tiles are numbered as the pairs of
/// m + 1 items).
struct PairTileRows {
  std::uint64_t i1 = 0, first = 0, m = 0;
};
SNAG_HD_INLINE PairTileRows pair_tile_rows(std::uint64_t n, std::uint64_t i0, std::uint64_t i1) {
  const std::uint64_t last_row = n < 2 ? 0 : n - 1;
  PairTileRows rows;
  rows.i1 = i1 < last_row ? i1 : last_row;
  rows.first = i0 / kPairTileSide;
  rows.m = (n + kPairTileSide - 1) / kPairTileSide - rows.first;
  return rows;
}

/// Tiles of the rows [i0, i1) of n items (i0 <= i1 <= n).
SNAG_HD_INLINE std::uint64_t pair_tile_count(std::uint64_t n, std::uint64_t i0, std::uint64_t i1) {
  const PairTileRows rows = pair_tile_rows(n, i0, i1);
  if (i0 >= rows.i1) return 0;
  const std::uint64_t row_tiles = (rows.i1 - 1) / kPairTileSide - rows.first + 1;
  return pair_count(rows.m + 1) - pair_count(rows.m + 1 - row_tiles);
}

/// Tile t (0 <= t < pair_tile_count(n, i0, i1)) of the rows [i0, i1) of n
/// items, row tile by row tile and each row tile's by column tile.
SNAG_HD_INLINE PairTile pair_tile(std::uint64_t n, std::uint64_t i0, std::uint64_t i1, std::uint64_t t) {
  const PairTileRows rows = pair_tile_rows(n, i0, i1);
  std::uint64_t k = 0, j = 0;
  pair_from_index(rows.m + 1, t, k, j);  // row tile first + k, column tile first + j - 1
  const std::uint64_t row_tile = rows.first + k, column_tile = rows.first + j - 1;
  PairTile tile;
  tile.row_begin = row_tile * kPairTileSide > i0 ? row_tile * kPairTileSide : i0;
  tile.row_end = (row_tile + 1) * kPairTileSide < rows.i1 ? (row_tile + 1) * kPairTileSide : rows.i1;
  tile.column_begin = column_tile * kPairTileSide;
  tile.column_end = (column_tile + 1) * kPairTileSide < n ? (column_tile + 1) * kPairTileSide : n;
  return tile;
}

}  // namespace snag
