#include "libcd/broad_phase/virtual_subdivision_grid.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "libcd/bounding_volume/float_box.hpp"
#include "libcd/broad_phase/broad_phase_support.hpp"
#include "libcd/broad_phase/feature_stage.hpp"
#include "libcd/core/error.hpp"
#include "libcd/grid/adaptive_cells.hpp"
#include "libcd/grid/cell_registration.hpp"
#include "libcd/grid/cell_size.hpp"
#include "libcd/grid/control_bits.hpp"
#include "libcd/grid/pair_index.hpp"

namespace snag {

namespace {

using namespace broad_phase_support;

/// Counters of one chunk of work items.
struct PairCounts {
  std::size_t boxes_apart = 0, same_root = 0, time_slots = 0, control_bits = 0, extended = 0, fallback = 0,
              passed = 0, culled = 0;
};

/// The two rules every cell applies before its own: leaves of one root are
/// never tested, nor leaves whose time slots do not nest. Counts which one
/// rejected the pair. LeafLike: VirtualTriangle or RegisteredLeaf.
template <class LeafLike>
bool leaves_may_meet(const LeafLike& a, const LeafLike& b, PairCounts& counts) {
  if (a.root == b.root) {
    ++counts.same_root;
    return false;
  }
  if (!slots_nested(a, b)) {
    ++counts.time_slots;
    return false;
  }
  return true;
}

/// Counts one test of roots ra, rb that passed the cell's rule: kept when the
/// DOPs overlap, else culled (its key kept only to count culled duplicates).
void record_dop_test(bool overlap, Index ra, Index rb, bool count_culled, PairCounts& counts,
                     std::vector<std::uint64_t>& kept, std::vector<std::uint64_t>& culled) {
  ++counts.passed;
  if (overlap) {
    kept.push_back(pack_pair(ra, rb));
    return;
  }
  ++counts.culled;
  if (count_culled) culled.push_back(pack_pair(ra, rb));
}

}  // namespace

/// What the pair tests leave for step 6: per chunk of work items, the keys of
/// the root pairs kept and (when counted) culled, and the counters.
struct VirtualSubdivisionGrid::PairTests {
  std::vector<std::vector<std::uint64_t>> kept, culled;
  std::vector<PairCounts> counts;
  std::size_t memory_bytes = 0;  ///< of the cell lists the tests read
  double seconds = 0;            ///< of step 5
  std::uint64_t apart_in_y = 0;  ///< tests whose root boxes are apart in y, counted without running them
};

namespace {

/// Splits `tests` work items into chunks, one list of keys kept and culled
/// and one PairCounts each, and runs run_chunk(chunk, begin, end) on each
/// chunk's items [begin, end), in parallel.
template <class RunChunk>
void for_each_chunk(std::uint64_t tests, std::vector<std::vector<std::uint64_t>>& chunk_kept,
                    std::vector<std::vector<std::uint64_t>>& chunk_culled, std::vector<PairCounts>& chunk_counts,
                    RunChunk run_chunk) {
  constexpr std::uint64_t kChunk = 1 << 16;
  const std::size_t chunks = static_cast<std::size_t>((tests + kChunk - 1) / kChunk);
  chunk_kept.assign(chunks, {});
  chunk_culled.assign(chunks, {});
  chunk_counts.assign(chunks, {});
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t chunk) {
    run_chunk(chunk, chunk * kChunk, std::min<std::uint64_t>(tests, (chunk + 1) * kChunk));
  });
}

/// Runs one test per work item, chunk by chunk in parallel. first_test
/// (#cells+1) is the prefix sum of the tests of each cell; cell c's tests are
/// its pairs (i, j), i < j < members(c), numbered row by row, in rows
/// i < rows(c) (grid/pair_index.hpp). test(c, i, j, counts, kept, culled)
/// runs one; the chunks' keys come back in work-item order.
template <class Members, class Rows, class Test>
void run_work_items(const std::vector<std::uint64_t>& first_test, Members members, Rows rows, Test test,
                    std::vector<std::vector<std::uint64_t>>& chunk_kept,
                    std::vector<std::vector<std::uint64_t>>& chunk_culled, std::vector<PairCounts>& chunk_counts) {
  const std::size_t cells = first_test.size() - 1;
  auto run_chunk = [&](std::size_t chunk, std::uint64_t begin, std::uint64_t end) {
    // Work item w -> (cell, i, j): the binary search and inversion of
    // grid/pair_index.hpp for the chunk's first item, then stepping, which
    // gives the same mapping item by item.
    std::uint64_t c = cell_of_work_item(first_test.data(), cells, begin), i = 0, j = 0;
    std::uint64_t n = members(c), last_row = rows(c);
    pair_from_index(n, begin - first_test[c], i, j);
    for (std::uint64_t w = begin; w < end; ++w) {
      test(c, i, j, chunk_counts[chunk], chunk_kept[chunk], chunk_culled[chunk]);
      // Next work item.
      if (++j == n) {
        ++i;
        j = i + 1;
        if (i >= last_row || j >= n) {
          do { ++c; } while (c < cells && first_test[c + 1] == first_test[c]);
          if (c < cells) {
            n = members(c);
            last_row = rows(c);
            i = 0;
            j = 1;
          }
        }
      }
    }
  };
  for_each_chunk(first_test[cells], chunk_kept, chunk_culled, chunk_counts, run_chunk);
}

/// Runs one test per work item, chunk by chunk in parallel, where each
/// registration r of the cells (cell c's are first[c] .. first[c+1]) is
/// tested against the run of those after it, and first_test
/// (#registrations+1) is the prefix sum of the runs' lengths: r's tests are
/// the pairs (r, s) for s in (r, r + 1 + first_test[r+1] - first_test[r]).
/// test(c, r, s, counts, kept, culled) runs one; the chunks' keys come back
/// in work-item order.
template <class Test>
void run_runs(const std::vector<std::uint64_t>& first_test, const std::vector<std::uint64_t>& first, Test test,
              std::vector<std::vector<std::uint64_t>>& chunk_kept,
              std::vector<std::vector<std::uint64_t>>& chunk_culled, std::vector<PairCounts>& chunk_counts) {
  const std::uint64_t registrations = first_test.size() - 1, cells = first.size() - 1;
  auto run_end = [&](std::uint64_t r) { return r + 1 + first_test[r + 1] - first_test[r]; };
  auto run_chunk = [&](std::size_t chunk, std::uint64_t begin, std::uint64_t end) {
    // Work item w -> (r, s): the registration whose run holds the chunk's
    // first item, and its cell, by binary search; then stepping.
    std::uint64_t r = cell_of_work_item(first_test.data(), registrations, begin);
    std::uint64_t s = r + 1 + (begin - first_test[r]);
    std::uint64_t c = cell_of_work_item(first.data(), cells, r);
    for (std::uint64_t w = begin; w < end; ++w) {
      test(c, r, s, chunk_counts[chunk], chunk_kept[chunk], chunk_culled[chunk]);
      if (++s < run_end(r) || w + 1 == end) continue;
      do { ++r; } while (first_test[r + 1] == first_test[r]);  // the next run that holds a test: item w + 1
      s = r + 1;
      while (first[c + 1] <= r) ++c;
    }
  };
  for_each_chunk(first_test.back(), chunk_kept, chunk_culled, chunk_counts, run_chunk);
}

}  // namespace

void VirtualSubdivisionGrid::build(const Scene& scene, const BroadPhaseSettings& settings) {
  if (!(settings.lambda > 1.0)) throw UsageError("broad phase: lambda must be greater than 1");
  if (!(settings.thickness >= 0.0)) throw UsageError("broad phase: thickness must be >= 0");
  if (settings.max_subdivision_levels < 0 || settings.max_subdivision_levels > 30 || settings.max_time_halvings < 0 ||
      settings.max_time_halvings > 30)
    throw UsageError("broad phase: safety limits must lie in [0, 30]");
  if (cells_ == Cells::kAdaptive &&
      (settings.adaptive_cell_limit < 2 || settings.adaptive_max_depth < 0 ||
       settings.adaptive_max_depth > kMaxAdaptiveDepth))
    throw UsageError("broad phase: the adaptive grid needs a cell limit >= 2 and a depth in [0, 8]");
  scene_ = &scene;
  settings_ = settings;
  tbb::task_arena arena(arena_threads(settings.threads));
  arena.execute([&] { reps_ = assign_representative_triangles(scene); });
}

VirtualSubdivisionGrid::PairTests VirtualSubdivisionGrid::uniform_pair_tests() {
  // 4. Registration, one sort, one scan.
  auto t = Clock::now();
  RegistrationCounts reg;
  const CellLists lists = register_leaves(leaves_, grid_, reg);
  stats_.registrations = reg.registrations;
  stats_.home_registrations = reg.home;
  stats_.phantom_registrations = reg.phantom;
  stats_.duplicate_registrations_removed = reg.duplicates_removed;
  stats_.cells_used = lists.cell_ids.size();
  stats_.seconds_registration = seconds_since(t);

  // 5. The tests of each cell are its pairs; stats_.tests counts them all.
  t = Clock::now();
  const std::size_t cells = lists.cell_ids.size();
  for (std::size_t c = 0; c < cells; ++c) stats_.tests += pair_count(lists.first[c + 1] - lists.first[c]);

  // The leaves as the tests read them, cell by cell (RegisteredLeaf), each
  // cell's ordered by the lower y of their root's box: a leaf's box can meet
  // in y only those of the leaves after it up to the first whose lower y
  // passes its upper y, so those runs are the pairs tested, and the other
  // pairs of the cell, apart in y, are culled by their boxes untested.
  std::vector<RegisteredLeaf> registered(lists.leaves.size());
  std::vector<float> low_y(registered.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 64), [&](const auto& range) {
    for (std::size_t c = range.begin(); c != range.end(); ++c) {
      const auto begin = registered.begin() + static_cast<std::ptrdiff_t>(lists.first[c]);
      const auto end = registered.begin() + static_cast<std::ptrdiff_t>(lists.first[c + 1]);
      for (auto r = begin; r != end; ++r) *r = registered_leaf(leaves_[lists.leaves[r - registered.begin()]]);
      std::sort(begin, end, [&](const RegisteredLeaf& a, const RegisteredLeaf& b) {
        return sweep_low(root_boxes_[a.root]) < sweep_low(root_boxes_[b.root]);
      });
      for (auto r = begin; r != end; ++r) low_y[r - registered.begin()] = sweep_low(root_boxes_[r->root]);
    }
  });
  // first_test[r]: the tests of the registrations before r; r's own are the
  // pairs (r, s) for s from r + 1 up to the first whose lower y passes r's
  // upper y.
  std::vector<std::uint64_t> first_test(registered.size() + 1, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 64), [&](const auto& range) {
    for (std::size_t c = range.begin(); c != range.end(); ++c) {
      const auto cell_end = low_y.begin() + static_cast<std::ptrdiff_t>(lists.first[c + 1]);
      for (std::uint64_t r = lists.first[c]; r < lists.first[c + 1]; ++r) {
        const float high_y = sweep_high(root_boxes_[registered[r].root]);
        const auto next = low_y.begin() + static_cast<std::ptrdiff_t>(r) + 1;
        first_test[r + 1] = static_cast<std::uint64_t>(std::upper_bound(next, cell_end, high_y) - next);
      }
    }
  });
  for (std::size_t r = 0; r < registered.size(); ++r) first_test[r + 1] += first_test[r];

  std::vector<CellCoord> cell_coords(cells);
  for (std::size_t c = 0; c < cells; ++c) cell_coords[c] = grid_cell_coord(grid_, lists.cell_ids[c]);

  const bool count_culled = settings_.count_culled_duplicates;
  auto test = [&](std::uint64_t c, std::uint64_t i, std::uint64_t j, PairCounts& counts,
                  std::vector<std::uint64_t>& kept, std::vector<std::uint64_t>& culled) {
    const RegisteredLeaf& a = registered[i];
    const RegisteredLeaf& b = registered[j];
    if (!float_boxes_may_overlap(root_boxes_[a.root], root_boxes_[b.root])) {
      ++counts.boxes_apart;
      return;
    }
    if (!leaves_may_meet(a, b, counts)) return;
    switch (cell_pair_verdict(a.cells, b.cells, cell_coords[c])) {
      case CellPairVerdict::kSkipControlBits: ++counts.control_bits; return;
      case CellPairVerdict::kSkipExtendedBits: ++counts.extended; return;
      case CellPairVerdict::kTestFallback: ++counts.fallback; break;
      case CellPairVerdict::kTest: break;
    }
    const Index ra = a.root, rb = b.root;
    record_dop_test(dop_overlap(bounds_.triangles[ra], bounds_.triangles[rb]), ra, rb, count_culled, counts, kept,
                    culled);
  };
  PairTests out;
  run_runs(first_test, lists.first, test, out.kept, out.culled, out.counts);
  out.apart_in_y = stats_.tests - first_test.back();
  out.seconds = seconds_since(t);
  out.memory_bytes = reg.registrations * 16 + lists.leaves.capacity() * 4 + lists.cell_ids.capacity() * 8 +
                     lists.first.capacity() * 8 + first_test.capacity() * 8 + low_y.capacity() * 4 +
                     registered.capacity() * sizeof(RegisteredLeaf) + cell_coords.capacity() * sizeof(CellCoord);
  return out;
}

VirtualSubdivisionGrid::PairTests VirtualSubdivisionGrid::adaptive_pair_tests() {
  // 4. Registration in the hierarchy of crowded cells.
  auto t = Clock::now();
  const AdaptiveCells tree =
      build_adaptive_cells(leaves_, grid_, settings_.adaptive_max_depth, settings_.adaptive_cell_limit);
  stats_.registrations = tree.registrations;
  stats_.cells_used = tree.cells.size();
  stats_.cells_subdivided = tree.cells_subdivided;
  stats_.deepest_level = tree.deepest_level;
  stats_.seconds_registration = seconds_since(t);

  // 5. One test per work item; a crowded cell tests the rows of its stuck leaves.
  t = Clock::now();
  const std::size_t cells = tree.cells.size();
  std::vector<std::uint64_t> first_test(cells + 1, 0);
  for (std::size_t c = 0; c < cells; ++c)
    first_test[c + 1] = first_test[c] + pair_count(tree.cells[c].count) - pair_count(tree.cells[c].count - tree.cells[c].stuck);
  stats_.tests = first_test[cells];

  const bool count_culled = settings_.count_culled_duplicates;
  auto members = [&](std::uint64_t c) { return std::uint64_t(tree.cells[c].count); };
  auto rows = [&](std::uint64_t c) { return std::uint64_t(tree.cells[c].stuck); };
  auto test = [&](std::uint64_t c, std::uint64_t i, std::uint64_t j, PairCounts& counts,
                  std::vector<std::uint64_t>& kept, std::vector<std::uint64_t>& culled) {
    const TestCell& cell = tree.cells[c];
    const std::uint32_t la = tree.members[cell.first + i], lb = tree.members[cell.first + j];
    const Leaf& a = leaves_[la];
    const Leaf& b = leaves_[lb];
    if (!float_boxes_may_overlap(root_boxes_[a.triangle.root], root_boxes_[b.triangle.root])) {
      ++counts.boxes_apart;
      return;
    }
    if (!leaves_may_meet(a.triangle, b.triangle, counts)) return;
    if (!adaptive_cell_owns_pair(tree.blocks[la], tree.blocks[lb], tree.depth, cell.level, cell.coord)) {
      ++counts.control_bits;
      return;
    }
    const Index ra = a.triangle.root, rb = b.triangle.root;
    record_dop_test(dop_overlap(a.dop, b.dop) && dop_overlap(bounds_.triangles[ra], bounds_.triangles[rb]), ra, rb,
                    count_culled, counts, kept, culled);
  };
  PairTests out;
  run_work_items(first_test, members, rows, test, out.kept, out.culled, out.counts);
  out.seconds = seconds_since(t);
  out.memory_bytes = tree.blocks.capacity() * sizeof(FineBlock) + tree.cells.capacity() * sizeof(TestCell) +
                     tree.members.capacity() * 4 + first_test.capacity() * 8;
  return out;
}

std::vector<TrianglePair> VirtualSubdivisionGrid::triangle_pairs(const std::vector<Vec3>& x_t0,
                                                                 const std::vector<Vec3>& x_t1) {
  const Scene& scene = *scene_;
  stats_ = BroadPhaseStats{};
  const auto start = Clock::now();

  // 1. Bounding volumes of triangles, edges and vertices.
  auto t = Clock::now();
  compute_primitive_bounds(scene, x_t0, x_t1, settings_.thickness, bounds_);
  root_boxes_.resize(bounds_.triangles.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, root_boxes_.size(), 4096), [&](const auto& range) {
    for (std::size_t f = range.begin(); f != range.end(); ++f) root_boxes_[f] = float_box_of(bounds_.triangles[f]);
  });
  stats_.seconds_bounds = seconds_since(t);

  // 2. Cell size and grid; 3. virtual subdivision.
  t = Clock::now();
  const double size = subdivide_ ? virtual_subdivision_cell_size(bounds_.triangle_radii, settings_.lambda)
                                 : largest_triangle_cell_size(bounds_.triangle_radii);
  grid_ = make_grid(bounds_.scene_lo, bounds_.scene_hi, size);
  stats_.cell_size = grid_.cell_size;
  for (int a = 0; a < 3; ++a) stats_.grid_dims[a] = grid_.dims[a];
  std::vector<SubdivisionLevelCounts> levels;
  leaves_ = subdivide_virtually(scene, x_t0, x_t1, grid_, settings_.thickness,
                                static_cast<std::uint32_t>(subdivide_ ? settings_.max_subdivision_levels : 0),
                                static_cast<std::uint32_t>(subdivide_ ? settings_.max_time_halvings : 0), levels);
  stats_.root_triangles = scene.triangle_count();
  for (const SubdivisionLevelCounts& level : levels) {
    stats_.triangles_per_level.push_back(level.triangles);
    stats_.subdivided_per_level.push_back(level.subdivided);
    stats_.halved_per_level.push_back(level.halved);
    stats_.triangles_subdivided += level.subdivided;
    stats_.time_halvings += level.halved;
    stats_.oversized_leaves += level.oversized;
  }
  stats_.leaf_triangles = leaves_.size();
  stats_.seconds_subdivision = seconds_since(t);

  // 4.-5. Registration and the pair tests.
  PairTests tests = cells_ == Cells::kAdaptive ? adaptive_pair_tests() : uniform_pair_tests();
  t = Clock::now();
  std::size_t key_count = 0;
  for (std::size_t k = 0; k < tests.counts.size(); ++k) {
    const PairCounts& counts = tests.counts[k];
    stats_.culled_by_boxes += counts.boxes_apart;
    stats_.same_root_tests += counts.same_root;
    stats_.removed_by_time_slots += counts.time_slots;
    stats_.removed_by_control_bits += counts.control_bits;
    stats_.removed_by_extended_control_bits += counts.extended;
    stats_.fallback_tests += counts.fallback;
    stats_.tests_after_control_bits += counts.passed;
    stats_.culled_by_dop += counts.culled;
    key_count += tests.kept[k].size();
  }
  stats_.culled_by_boxes += tests.apart_in_y;
  std::vector<std::uint64_t> keys;
  keys.reserve(key_count);
  for (auto& chunk : tests.kept) {
    keys.insert(keys.end(), chunk.begin(), chunk.end());
    std::vector<std::uint64_t>().swap(chunk);
  }

  // 6. Final sort + unique. Duplicate root-pair tests are counted exactly
  // among the tests the DOPs kept and, when asked, among those they culled
  // (the DOP test depends on the root pair only).
  const bool count_culled = settings_.count_culled_duplicates;
  std::vector<std::uint64_t> culled;
  if (count_culled) culled.reserve(stats_.culled_by_dop);
  for (auto& chunk : tests.culled) {
    culled.insert(culled.end(), chunk.begin(), chunk.end());
    std::vector<std::uint64_t>().swap(chunk);
  }
  tbb::parallel_sort(culled.begin(), culled.end());
  const std::size_t culled_tests = culled.size();
  const std::size_t culled_unique = static_cast<std::size_t>(std::unique(culled.begin(), culled.end()) - culled.begin());
  std::vector<std::uint64_t>().swap(culled);
  tbb::parallel_sort(keys.begin(), keys.end());
  const std::size_t kept_tests = keys.size();
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  stats_.seconds_pairs = seconds_since(t) + tests.seconds;
  stats_.triangle_pairs = keys.size();

  stats_.memory_bytes = leaves_.capacity() * sizeof(Leaf) + tests.memory_bytes + (kept_tests + culled_tests) * 8 +
                        (bounds_.triangles.size() + bounds_.edges.size() + bounds_.vertices.size()) * sizeof(Dop18);
  stats_.duplicate_root_pair_tests = kept_tests - keys.size();
  stats_.duplicate_culled_tests = culled_tests - culled_unique;
  std::vector<TrianglePair> pairs(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k) pairs[k] = unpack_pair(keys[k]);
  stats_.seconds_total = seconds_since(start);
  return pairs;
}

void VirtualSubdivisionGrid::detect_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                        std::vector<VertexFaceCandidate>& vf, std::vector<EdgeEdgeCandidate>& ee) {
  check_positions(scene_, x_t0, "x_t0");
  check_positions(scene_, x_t1, "x_t1");
  tbb::task_arena arena(arena_threads(settings_.threads));
  arena.execute([&] {
    const auto start = Clock::now();
    const std::vector<TrianglePair> pairs = triangle_pairs(x_t0, x_t1);
    feature_stage(*scene_, reps_, bounds_, pairs, x_t0, x_t1, settings_, vf, ee, stats_);
    stats_.seconds_total = seconds_since(start);
  });
}

void VirtualSubdivisionGrid::detect_static(const std::vector<Vec3>& x, std::vector<TrianglePair>& pairs) {
  check_positions(scene_, x, "x");
  tbb::task_arena arena(arena_threads(settings_.threads));
  arena.execute([&] {
    pairs = triangle_pairs(x, x);
    stats_.candidates = pairs.size();
  });
}

}  // namespace snag
