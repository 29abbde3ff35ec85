// Tests for grid/: cell mapping, cell types, pair numbering, control bits and
// the cell pair rule, registration with home priority.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "libcd/grid/cell_size.hpp"
#include "libcd/grid/control_bits.hpp"
#include "libcd/grid/pair_index.hpp"
#include "libcd/grid/uniform_grid.hpp"

namespace snag {
namespace {

TEST(UniformGrid, CellOfPointIsMonotoneAndClamped) {
  const GridSpec grid = make_grid({-1, -1, -1}, {1, 1, 1}, 0.3);
  EXPECT_EQ(grid.dims[0], 7);
  std::int32_t previous = -1;
  for (double x = -2; x <= 2; x += 0.001) {
    const std::int32_t c = grid_axis_cell(grid, x, 0);
    EXPECT_GE(c, previous);
    EXPECT_GE(c, 0);
    EXPECT_LT(c, grid.dims[0]);
    previous = c;
  }
  EXPECT_EQ(grid_axis_cell(grid, -1.0, 0), 0);
  EXPECT_EQ(grid_axis_cell(grid, -0.7, 0), 1);  // -1 + 0.3 = -0.7 starts cell 1
}

TEST(UniformGrid, TinyCellSizeIsRaisedSoIdsFit) {
  const GridSpec grid = make_grid({0, 0, 0}, {1e6, 1, 1}, 1e-9);
  EXPECT_LE(grid.dims[0], (1 << 20) + 1);
  const GridSpec flat = make_grid({0, 0, 0}, {0, 0, 0}, 0);
  EXPECT_EQ(flat.cell_size, 1.0);
}

TEST(CellType, CellsOfATwoByTwoByTwoBlockHaveDistinctTypes) {
  for (int x = -3; x < 3; ++x) {
    const CellBlock block{{x, x + 5, 2 * x}, {x + 1, x + 6, 2 * x + 1}};
    unsigned seen = 0;
    for (std::uint64_t k = 0; k < block_cell_count(block); ++k) seen |= 1u << cell_type(block_cell(block, k));
    EXPECT_EQ(seen, 0xffu);
    EXPECT_EQ(overlap_mask(block), 0xffu);
  }
  const CellBlock line{{4, 2, 2}, {5, 2, 2}};
  EXPECT_EQ(overlap_mask(line), (1u << 0) | (1u << 1));
}

TEST(PairIndex, InvertsTheRowByRowNumbering) {
  const std::uint64_t ns[] = {2, 3, 7, 50};
  for (std::uint64_t n : ns) {
    std::uint64_t k = 0;
    for (std::uint64_t i = 0; i < n; ++i)
      for (std::uint64_t j = i + 1; j < n; ++j, ++k) {
        std::uint64_t gi, gj;
        pair_from_index(n, k, gi, gj);
        ASSERT_EQ(gi, i);
        ASSERT_EQ(gj, j);
      }
    EXPECT_EQ(k, pair_count(n));
  }
  const std::uint64_t big = 3000000;  // rounding of the closed form is corrected
  const std::uint64_t ks[] = {0, 1, big - 2, big - 1, pair_count(big) - 2, pair_count(big) - 1};
  for (std::uint64_t k : ks) {
    std::uint64_t i, j;
    pair_from_index(big, k, i, j);
    EXPECT_LT(i, j);
    EXPECT_LT(j, big);
    EXPECT_EQ(i * (2 * big - i - 1) / 2 + (j - i - 1), k);
  }
}

TEST(PairIndex, WorkItemFindsItsCellAcrossEmptyCells) {
  const std::uint64_t first[] = {0, 0, 3, 3, 3, 4, 10};
  const std::uint64_t expected[] = {1, 1, 1, 4, 5, 5, 5, 5, 5, 5};
  for (std::uint64_t w = 0; w < 10; ++w) EXPECT_EQ(cell_of_work_item(first, 6, w), expected[w]) << w;
}

TEST(PairIndex, GallopingFromAnEarlierCellFindsTheCellOfTheBinarySearch) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    // Runs of empty cells between cells of 1 to a few thousand items.
    const std::uint64_t cells = 1 + rng() % 3000;
    std::vector<std::uint64_t> first(cells + 1, 0);
    for (std::uint64_t c = 0; c < cells; ++c)
      first[c + 1] = first[c] + (rng() % 3 == 0 ? 0 : 1 + rng() % (1u << (rng() % 12)));
    const std::uint64_t total = first[cells];
    if (total == 0) continue;
    // Ascending work items, as one thread strides over them.
    const std::uint64_t stride = 1 + rng() % (trial % 2 ? 64 : total);
    std::uint64_t c = 0;
    for (std::uint64_t w = rng() % std::min<std::uint64_t>(stride, total); w < total; w += stride) {
      c = cell_of_work_item_from(first.data(), cells, c, w);
      ASSERT_EQ(c, cell_of_work_item(first.data(), cells, w)) << "trial " << trial << " w " << w;
    }
  }
}

TEST(PairIndex, TilesHoldEachTestOfTheirRowsOnce) {
  // Every row range of cells from 0 to a few tiles wide, edges on and off the
  // tile side: the tiles' pairs i < j are exactly those with i in [i0, i1).
  const std::uint64_t side = kPairTileSide;
  const std::uint64_t ns[] = {0, 1, 2, 3, side - 1, side, side + 1, 2 * side, 3 * side + 5, 7 * side - 1};
  std::mt19937 rng(5);
  for (std::uint64_t n : ns) {
    std::vector<std::pair<std::uint64_t, std::uint64_t>> ranges = {{0, n}, {n, n}};
    for (int r = 0; r < 40 && n > 0; ++r) {
      const std::uint64_t a = rng() % (n + 1), b = rng() % (n + 1);
      ranges.push_back({std::min(a, b), std::max(a, b)});
    }
    if (n > side) ranges.push_back({side - 1, side + 1});
    for (const auto& [i0, i1] : ranges) {
      std::vector<int> seen(n * n, 0);
      const std::uint64_t tiles = pair_tile_count(n, i0, i1);
      for (std::uint64_t t = 0; t < tiles; ++t) {
        const PairTile tile = pair_tile(n, i0, i1, t);
        ASSERT_LE(tile.row_end - tile.row_begin, side);
        ASSERT_LE(tile.column_end - tile.column_begin, side);
        ASSERT_LT(tile.row_begin, tile.row_end);
        ASSERT_LE(tile.row_begin, tile.column_begin + side - 1) << "no column of the tile lies right of a row";
        for (std::uint64_t i = tile.row_begin; i < tile.row_end; ++i)
          for (std::uint64_t j = std::max(tile.column_begin, i + 1); j < tile.column_end; ++j) ++seen[i * n + j];
      }
      for (std::uint64_t i = 0; i < n; ++i)
        for (std::uint64_t j = 0; j < n; ++j)
          ASSERT_EQ(seen[i * n + j], i0 <= i && i < i1 && i < j ? 1 : 0)
              << "n " << n << " rows [" << i0 << ", " << i1 << ") pair " << i << ", " << j;
    }
  }
  // A cell of 200M items: the closed form's rounding is corrected at its last tile.
  const std::uint64_t big = 200000000, tiles = pair_tile_count(big, 0, big);
  const PairTile last = pair_tile(big, 0, big, tiles - 1);
  EXPECT_EQ(last.column_end, big);
  EXPECT_EQ(last.row_begin, (big - 2) / side * side);
}

LeafCells random_leaf(std::mt19937& rng) {
  std::uniform_int_distribution<int> pos(0, 4), ext(0, 1);
  LeafCells leaf;
  leaf.block.lo = {pos(rng), pos(rng), pos(rng)};
  leaf.block.hi = {leaf.block.lo.x + ext(rng), leaf.block.lo.y + ext(rng), leaf.block.lo.z + ext(rng)};
  leaf.home = block_cell(leaf.block, std::uniform_int_distribution<std::uint64_t>(0, block_cell_count(leaf.block) - 1)(rng));
  leaf.control_bits = make_control_bits(leaf);
  return leaf;
}

TEST(UniformGrid, CellOrderAndCoordinatesFollowTheIds) {
  const GridSpec grid = make_grid({0, 0, 0}, {7, 3, 5}, 1.0);  // about 7 x 3 x 5 cells
  std::vector<CellCoord> cells;
  for (std::int32_t z = 0; z < grid.dims[2]; ++z)
    for (std::int32_t y = 0; y < grid.dims[1]; ++y)
      for (std::int32_t x = 0; x < grid.dims[0]; ++x) cells.push_back({x, y, z});
  for (const CellCoord& a : cells) {
    EXPECT_EQ(grid_cell_coord(grid, grid_cell_id(grid, a)), a);
    for (const CellCoord& b : cells) ASSERT_EQ(cell_precedes(a, b), grid_cell_id(grid, a) < grid_cell_id(grid, b));
  }
}

/// The test rule of control_bits.hpp written out over cell ids: R's cells,
/// the smallest, and whose home it is.
CellPairVerdict verdict_by_ids(const GridSpec& grid, const LeafCells& a, const LeafCells& b, CellCoord cell) {
  std::map<std::uint64_t, bool> r;  // cell id of R -> some leaf's own home
  auto add = [&](const LeafCells& self, const LeafCells& other) {
    if (block_contains(other.block, self.home)) r[grid_cell_id(grid, self.home)] = true;
    for (std::uint32_t k = 0; k < self.sibling_count; ++k)
      if (block_contains(other.block, self.sibling_home[k]))
        r.emplace(grid_cell_id(grid, self.sibling_home[k]), false);
  };
  add(a, b);
  add(b, a);
  if (r.empty()) {
    const CellCoord corner{std::max(a.block.lo.x, b.block.lo.x), std::max(a.block.lo.y, b.block.lo.y),
                           std::max(a.block.lo.z, b.block.lo.z)};
    return corner == cell ? CellPairVerdict::kTestFallback : CellPairVerdict::kSkipControlBits;
  }
  if (r.begin()->first == grid_cell_id(grid, cell)) return CellPairVerdict::kTest;
  return r.begin()->second ? CellPairVerdict::kSkipControlBits : CellPairVerdict::kSkipExtendedBits;
}

TEST(ControlBits, VerdictIsTheRuleOverCellIds) {
  // Leaves with 0 to 3 siblings at home anywhere in a 6 x 6 x 6 grid, in
  // every cell the two share: the verdict (cells ordered without the grid,
  // the three sibling slots read with the count as a condition) is the rule's.
  const GridSpec grid = make_grid({0, 0, 0}, {6, 6, 6}, 1.0);
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> anywhere(0, 5), siblings(0, 3);
  std::map<CellPairVerdict, int> seen;
  for (int trial = 0; trial < 20000; ++trial) {
    LeafCells leaf[2] = {random_leaf(rng), random_leaf(rng)};
    for (LeafCells& l : leaf) {
      l.sibling_count = static_cast<std::uint32_t>(siblings(rng));
      for (std::uint32_t k = 0; k < l.sibling_count; ++k) {
        // Half of them next to the leaf's block, so that they often lie in the other's.
        l.sibling_home[k] = rng() % 2 ? CellCoord{anywhere(rng), anywhere(rng), anywhere(rng)}
                                      : CellCoord{std::min(l.block.hi.x + 1, 5), l.block.lo.y, l.block.lo.z};
      }
      l.control_bits = make_control_bits(l);
    }
    for (std::uint64_t k = 0; k < block_cell_count(leaf[0].block); ++k) {
      const CellCoord c = block_cell(leaf[0].block, k);
      if (!block_contains(leaf[1].block, c)) continue;
      const CellPairVerdict v = cell_pair_verdict(leaf[0], leaf[1], c);
      ASSERT_EQ(v, verdict_by_ids(grid, leaf[0], leaf[1], c)) << "trial " << trial;
      ++seen[v];
    }
  }
  for (CellPairVerdict v : {CellPairVerdict::kTest, CellPairVerdict::kTestFallback, CellPairVerdict::kSkipControlBits,
                            CellPairVerdict::kSkipExtendedBits})
    EXPECT_GT(seen[v], 100) << static_cast<int>(v);
}

TEST(ControlBits, LocalMasksGiveTheVerdictAroundEveryCell) {
  // Two leaves of one to three cells per axis, the second near the first,
  // with 0 to 3 siblings near or anywhere in an 8 x 8 x 8 grid; around every
  // cell within one of the first leaf's block: where neither block reaches
  // beyond one cell of the cell (not wide), the masks' verdict is
  // cell_pair_verdict's, in the cells the two share and elsewhere.
  std::mt19937 rng(21);
  std::uniform_int_distribution<int> pos(2, 4), near(-2, 2), next(-1, 1), ext(0, 1), anywhere(0, 7), siblings(0, 3),
      wide(0, 9);
  std::map<CellPairVerdict, int> seen_shared;
  int compared = 0, wide_seen = 0;
  for (int trial = 0; trial < 100000; ++trial) {
    LeafCells leaf[2];
    for (int k = 0; k < 2; ++k) {
      LeafCells& l = leaf[k];
      l.block.lo = k == 0 ? CellCoord{pos(rng), pos(rng), pos(rng)}
                          : CellCoord{leaf[0].block.lo.x + near(rng), leaf[0].block.lo.y + near(rng),
                                      leaf[0].block.lo.z + near(rng)};
      l.block.hi = {l.block.lo.x + ext(rng), l.block.lo.y + ext(rng), l.block.lo.z + ext(rng)};
      if (wide(rng) == 0) l.block.hi.y = l.block.lo.y + 2;  // an oversized leaf
      l.home = block_cell(l.block, std::uniform_int_distribution<std::uint64_t>(0, block_cell_count(l.block) - 1)(rng));
      l.sibling_count = static_cast<std::uint32_t>(siblings(rng));
      for (std::uint32_t s = 0; s < l.sibling_count; ++s)
        l.sibling_home[s] =
            rng() % 2 ? CellCoord{anywhere(rng), anywhere(rng), anywhere(rng)}
                      : CellCoord{l.block.lo.x + next(rng), l.block.lo.y + next(rng), l.block.lo.z + next(rng)};
      l.control_bits = make_control_bits(l);
    }
    const CellBlock& around = leaf[0].block;
    for (int z = around.lo.z - 1; z <= around.hi.z + 1; ++z)
      for (int y = around.lo.y - 1; y <= around.hi.y + 1; ++y)
        for (int x = around.lo.x - 1; x <= around.hi.x + 1; ++x) {
          const CellCoord c{x, y, z};
          const LocalCells a = local_cells(leaf[0], c), b = local_cells(leaf[1], c);
          for (int k = 0; k < 2; ++k) {
            const CellBlock& block = leaf[k].block;
            const bool reaches = block.lo.x < x - 1 || block.hi.x > x + 1 || block.lo.y < y - 1 || block.hi.y > y + 1 ||
                                 block.lo.z < z - 1 || block.hi.z > z + 1;
            ASSERT_EQ((k == 0 ? a : b).wide(), reaches);
          }
          if (a.wide() || b.wide()) {
            ++wide_seen;
            continue;
          }
          const CellPairVerdict v = cell_pair_verdict(leaf[0], leaf[1], c);
          ASSERT_EQ(cell_pair_verdict(a, b), v) << "trial " << trial << " cell " << x << "," << y << "," << z;
          ASSERT_EQ(cell_pair_verdict(b, a), cell_pair_verdict(leaf[1], leaf[0], c));
          ++compared;
          if (block_contains(leaf[0].block, c) && block_contains(leaf[1].block, c)) ++seen_shared[v];
        }
  }
  EXPECT_GT(compared, 100000);
  EXPECT_GT(wide_seen, 10000);
  for (CellPairVerdict v : {CellPairVerdict::kTest, CellPairVerdict::kTestFallback, CellPairVerdict::kSkipControlBits,
                            CellPairVerdict::kSkipExtendedBits})
    EXPECT_GT(seen_shared[v], 500) << static_cast<int>(v);
}

TEST(ControlBits, EncodeTypesOfHomeBlockAndSiblings) {
  LeafCells leaf;
  leaf.block = {{2, 3, 4}, {3, 3, 5}};
  leaf.home = {3, 3, 4};
  leaf.sibling_count = 2;
  leaf.sibling_home[0] = {2, 3, 5};
  leaf.sibling_home[1] = {7, 8, 9};
  const std::uint32_t bits = make_control_bits(leaf);
  EXPECT_EQ(control_bits_home_type(bits), cell_type(leaf.home));
  EXPECT_EQ(control_bits_sibling_count(bits), 2u);
  EXPECT_EQ(control_bits_sibling_type(bits, 0), cell_type(leaf.sibling_home[0]));
  EXPECT_EQ(control_bits_sibling_type(bits, 1), cell_type(leaf.sibling_home[1]));
  leaf.control_bits = bits;
  EXPECT_TRUE(leaf_overlaps_cell(leaf, {2, 3, 5}));
  EXPECT_FALSE(leaf_overlaps_cell(leaf, {4, 3, 5}));  // same type as (2,3,5), outside the block
}

TEST(ControlBits, SingleLeavesSharingCellsAreTestedInExactlyOneCell) {
  std::mt19937 rng(5);
  int pairs_sharing = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const LeafCells a = random_leaf(rng), b = random_leaf(rng);
    int tested = 0, shared = 0;
    for (std::uint64_t k = 0; k < block_cell_count(a.block); ++k) {
      const CellCoord c = block_cell(a.block, k);
      if (!block_contains(b.block, c)) continue;
      ++shared;
      const CellPairVerdict v = cell_pair_verdict(a, b, c);
      tested += v == CellPairVerdict::kTest || v == CellPairVerdict::kTestFallback;
      EXPECT_EQ(v, cell_pair_verdict(b, a, c));  // symmetric
    }
    if (shared > 0) {
      ++pairs_sharing;
      EXPECT_EQ(tested, 1);
    }
  }
  EXPECT_GT(pairs_sharing, 500);
}

TEST(ControlBits, SiblingHomeRedirectsTheTestToASmallerCell) {
  LeafCells a;  // a child at home in (2,0,0), its sibling at home in (1,0,0)
  a.block = {{2, 0, 0}, {2, 0, 0}};
  a.home = {2, 0, 0};
  a.sibling_count = 1;
  a.sibling_home[0] = {1, 0, 0};
  a.control_bits = make_control_bits(a);
  LeafCells b;  // spans (1,0,0)-(2,0,0), home in (1,0,0)... at (2,0,0): phantom
  b.block = {{1, 0, 0}, {2, 0, 0}};
  b.home = {2, 0, 0};
  b.control_bits = make_control_bits(b);
  // In (2,0,0) both are home; the sibling's home (1,0,0) lies in b's block and
  // has a smaller id: the extended bits move the test there.
  EXPECT_EQ(cell_pair_verdict(a, b, {2, 0, 0}), CellPairVerdict::kSkipExtendedBits);
  a.sibling_count = 0;
  a.control_bits = make_control_bits(a);
  EXPECT_EQ(cell_pair_verdict(a, b, {2, 0, 0}), CellPairVerdict::kTest);
}

}  // namespace
}  // namespace snag
