#include "libcd/broad_phase/box_grid.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "libcd/broad_phase/broad_phase_support.hpp"
#include "libcd/broad_phase/feature_stage.hpp"
#include "libcd/core/error.hpp"

namespace snag {

namespace {

using namespace broad_phase_support;

/// The cell size over the mean of the boxes' largest extents. With the
/// 16-byte registrations and their one-instruction box test, registering
/// costs more than testing: snag-bench-pipeline --static-only, 2 threads,
/// pairs of runs at 1, 1.8, 2, 2.4, 3 and 4 times the mean extent gave
/// cloth 100k 5.2-6.4x CGAL at 1 and 5.5-7.0x from 1.8 on, cloth 10k
/// 4.8-4.9x at 1 and 5.2-7.6x from 1.8 on, the samples 4.3-4.6x at 1 and
/// 3.8-6.0x from 1.8 on, with no clear best above 1.8.
constexpr double kCellPerExtent = 2.0;

/// Triangles per block of the scene-bounds pass: fixed, so that the sum of
/// box extents (and so the grid) does not depend on the thread count.
constexpr std::size_t kBoundsBlock = 4096;

/// Triangles per output block: fixed, so that the blocks (and the output
/// order) do not depend on the thread count.
constexpr std::size_t kBlock = 256;

/// Below this many triangles the grid's arrays stay in cache in any order,
/// and the spatial query order would cost more than it saves (the samples'
/// 2,024 faces: about a tenth slower with it).
constexpr std::size_t kSpatialQueriesFrom = 16384;

/// Runs `work` on `arena`'s threads: on the calling arena when it has as
/// many (a back end calling with its own arena of the same size), for a
/// switch of arenas costs a frame of the samples about a tenth.
template <typename Work>
void run_with_threads(tbb::task_arena& arena, Work&& work) {
  if (tbb::this_task_arena::max_concurrency() == arena.max_concurrency())
    work();
  else
    arena.execute(work);
}

/// Triangles per thread below which the registration stays on one thread.
constexpr std::size_t kRegistrationRange = 16384;
/// At most this many registration ranges: each holds a cursor per cell (8
/// bytes, up to 4 cells per triangle), so that a many-core machine does not
/// spend 32 bytes per triangle and thread on them.
constexpr std::size_t kMaxRegistrationRanges = 8;

/// How many queries ahead the spatial query order prefetches a query's arrays.
constexpr std::size_t kPrefetchQueries = 4;

/// No vertex has this id: it stands for a vertex of a that is not apart.
constexpr Index kNoVertex = ~Index(0);


}  // namespace

void BoxGridBroadPhase::build(const Scene& scene, const BroadPhaseSettings& settings) {
  if (!(settings.thickness >= 0.0)) throw UsageError("broad phase: thickness must be >= 0");
  scene_ = &scene;
  settings_ = settings;
  arena_ = std::make_unique<tbb::task_arena>(arena_threads(settings.threads));
  arena_->execute([&] { reps_ = assign_representative_triangles(scene); });
}

void BoxGridBroadPhase::build_grid() {
  choose_grid();
  register_boxes();
}

void BoxGridBroadPhase::choose_grid() {
  const std::vector<Dop18>& dops = *dops_;
  const std::size_t n = dops.size();
  if (n > kMaxTriangles)
    throw UsageError("box grid: at most " + std::to_string(kMaxTriangles) + " triangles per detection, this one has " +
                     std::to_string(n));
  // The scene's bounds and the sum of the boxes' largest extents, per fixed
  // block in parallel, then added up in block order.
  struct Partial {
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300}, extent_sum = 0;
  };
  std::vector<Partial> partials((n + kBoundsBlock - 1) / kBoundsBlock);
  tbb::parallel_for(std::size_t(0), partials.size(), [&](std::size_t block) {
    Partial& part = partials[block];
    for (std::size_t t = block * kBoundsBlock; t < std::min(n, (block + 1) * kBoundsBlock); ++t) {
      double extent = 0;
      for (int a = 0; a < 3; ++a) {
        part.lo[a] = std::min(part.lo[a], dops[t].lo[a]);
        part.hi[a] = std::max(part.hi[a], dops[t].hi[a]);
        extent = std::max(extent, dops[t].hi[a] - dops[t].lo[a]);
      }
      part.extent_sum += extent;
    }
  });
  Partial scene;
  for (const Partial& part : partials) {
    for (int a = 0; a < 3; ++a) {
      scene.lo[a] = std::min(scene.lo[a], part.lo[a]);
      scene.hi[a] = std::max(scene.hi[a], part.hi[a]);
    }
    scene.extent_sum += part.extent_sum;
  }
  const double* lo = scene.lo;
  const double* hi = scene.hi;
  // The quantisation of the boxes: kQuantumMax steps over the scene along
  // each axis.
  double quantum_scale[3];
  for (int a = 0; a < 3; ++a)
    quantum_scale[a] = hi[a] > lo[a] && std::isfinite(hi[a] - lo[a]) ? double(kQuantumMax) / (hi[a] - lo[a]) : 0.0;
  double span = 0;
  for (int a = 0; a < 3; ++a) span = std::max(span, hi[a] - lo[a]);
  double size = n ? kCellPerExtent * scene.extent_sum / double(n) : 1.0;
  if (!(size > 0) || !std::isfinite(size)) size = span > 0 ? span : 1.0;
  const double max_cells = 4.0 * double(n) + 64.0;
  const double max_registrations = 16.0 * double(n) + 64.0;
  boxes_.resize(n);
  for (int a = 0; a < 3; ++a) {
    cell_lo_[a].resize(n);
    cell_hi_[a].resize(n);
  }
  first_registration_.resize(n + 1);
  bool quantised = false;  // boxes_ (once, on the first grid that is tried)
  for (;;) {
    double cells = 1;
    for (int a = 0; a < 3; ++a) cells *= std::max(1.0, std::ceil((hi[a] - lo[a]) / size));
    if (cells > max_cells) {
      size *= std::cbrt(cells / max_cells) * 1.001;
      continue;
    }
    for (int a = 0; a < 3; ++a) {
      origin_[a] = lo[a];
      dims_[a] = static_cast<std::int64_t>(std::max(1.0, std::ceil((hi[a] - lo[a]) / size)));
    }
    inverse_cell_size_ = 1.0 / size;
    // Each box's cell range and number of cells, and (once) its quantised
    // box. cell() and quantise() are monotone in the coordinate, which is
    // all that the set returned relies on.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& range) {
      for (std::size_t t = range.begin(); t != range.end(); ++t) {
        std::uint64_t volume = 1;
        for (int a = 0; a < 3; ++a) {
          const std::int64_t last = dims_[a] - 1;
          auto cell = [&](double v) {
            const double c = std::floor((v - origin_[a]) * inverse_cell_size_);
            return static_cast<std::uint32_t>(c <= 0 ? 0 : (c >= double(last) ? last : std::int64_t(c)));
          };
          cell_lo_[a][t] = cell(dops[t].lo[a]);
          cell_hi_[a][t] = cell(dops[t].hi[a]);
          volume *= std::uint64_t(cell_hi_[a][t] - cell_lo_[a][t] + 1);
        }
        first_registration_[t + 1] = volume;
        if (!quantised) {
          auto quantise = [&](int a, double v) {
            const double q = (v - lo[a]) * quantum_scale[a];  // NaN only for a NaN coordinate: then 0
            return static_cast<std::int16_t>(q >= kQuantumMax ? kQuantumMax : (q > 0 ? q : 0));
          };
          Member& box = boxes_[t];
          for (int a = 0; a < 3; ++a) {
            box.quantised[a] = quantise(a, dops[t].lo[a]);
            box.quantised[3 + a] = static_cast<std::int16_t>(-quantise(a, dops[t].hi[a]));
          }
          box.triangle_and_lowest = static_cast<std::uint32_t>(t);
        }
      }
    });
    quantised = true;
    first_registration_[0] = 0;
    for (std::size_t t = 0; t < n; ++t) first_registration_[t + 1] += first_registration_[t];
    if (double(first_registration_[n]) <= max_registrations) break;
    size *= 2;  // ends: with one cell, every triangle registers once
  }
  stats_.cell_size = 1.0 / inverse_cell_size_;
  for (int a = 0; a < 3; ++a) stats_.grid_dims[a] = static_cast<int>(dims_[a]);
}

void BoxGridBroadPhase::register_boxes() {
  const std::size_t n = dops_->size();
  const std::size_t cells = static_cast<std::size_t>(dims_[0] * dims_[1] * dims_[2]);
  const std::size_t registrations = first_registration_[n];
  // visit(cell, lowest_along bits) for every cell of triangle t's box. The
  // box's cell range is read into locals first: the writes in visit may
  // alias the arrays as far as the compiler knows.
  const std::size_t dim_x = static_cast<std::size_t>(dims_[0]);
  const std::size_t dim_xy = static_cast<std::size_t>(dims_[0] * dims_[1]);
  auto for_each_cell = [&, dim_x, dim_xy](std::size_t t, auto&& visit) {
    const std::uint32_t lo_x = cell_lo_[0][t], lo_y = cell_lo_[1][t], lo_z = cell_lo_[2][t];
    const std::uint32_t hi_x = cell_hi_[0][t], hi_y = cell_hi_[1][t], hi_z = cell_hi_[2][t];
    for (std::uint32_t z = lo_z; z <= hi_z; ++z)
      for (std::uint32_t y = lo_y; y <= hi_y; ++y)
        for (std::uint32_t x = lo_x; x <= hi_x; ++x)
          visit(std::size_t(x) + dim_x * std::size_t(y) + dim_xy * std::size_t(z),
                std::uint32_t(x == lo_x) | std::uint32_t(y == lo_y) << 1 | std::uint32_t(z == lo_z) << 2);
  };
  // A stable counting sort by cell: the registrations of a cell come out in
  // triangle order, and each one's place is known as it is written. Plain
  // increments cost less than the atomic adds and the per-cell sort that a
  // shared fill needs (cloth 100k, 8 frames, 2 threads: 0.24 -> 0.14 s), so
  // each thread counts and fills its own consecutive range of triangles,
  // with cursors that start where the ranges before it end in each cell:
  // the same arrays for any number of ranges.
  const std::size_t ranges = std::max<std::size_t>(
      1, std::min<std::size_t>({std::size_t(tbb::this_task_arena::max_concurrency()), n / kRegistrationRange,
                                kMaxRegistrationRanges}));
  range_cursors_.resize(ranges);
  auto range_begin = [&](std::size_t r) { return n * r / ranges; };
  tbb::parallel_for(std::size_t(0), ranges, [&](std::size_t r) {
    range_cursors_[r].assign(cells, 0);
    std::uint32_t* __restrict__ count = range_cursors_[r].data();
    for (std::size_t t = range_begin(r); t < range_begin(r + 1); ++t)
      for_each_cell(t, [count](std::size_t c, std::uint32_t) { ++count[c]; });
  });
  cell_first_.resize(cells + 1);
  cell_first_[0] = 0;
  std::size_t used = 0;
  for (std::size_t c = 0; c < cells; ++c) {
    std::uint32_t next = cell_first_[c];
    for (std::size_t r = 0; r < ranges; ++r) {
      const std::uint32_t count = range_cursors_[r][c];
      range_cursors_[r][c] = next;
      next += count;
    }
    used += next != cell_first_[c];
    cell_first_[c + 1] = next;
  }
  members_.resize(registrations);
  scan_first_.resize(registrations);
  scan_end_.resize(registrations);
  tbb::parallel_for(std::size_t(0), ranges, [&](std::size_t r) {
    std::uint32_t* __restrict__ next = range_cursors_[r].data();
    Member* __restrict__ members = members_.data();
    const std::uint32_t* __restrict__ cell_end = cell_first_.data() + 1;
    // A range's registrations are consecutive in triangle order.
    std::uint32_t* __restrict__ scan_first = scan_first_.data() + first_registration_[range_begin(r)];
    std::uint32_t* __restrict__ scan_end = scan_end_.data() + first_registration_[range_begin(r)];
    for (std::size_t t = range_begin(r); t < range_begin(r + 1); ++t) {
      Member member = boxes_[t];
      for_each_cell(t, [&](std::size_t c, std::uint32_t lowest_along) {
        member.triangle_and_lowest = static_cast<std::uint32_t>(t) | lowest_along << kLowestShift;
        const std::uint32_t slot = next[c]++;
        members[slot] = member;
        *scan_first++ = slot + 1;
        *scan_end++ = cell_end[c];
      });
    }
  });
  choose_query_order();
  stats_.cells_used = used;
  stats_.registrations = registrations;
  stats_.home_registrations = n;
  stats_.phantom_registrations = registrations - n;
}

void BoxGridBroadPhase::choose_query_order() {
  const std::size_t n = dops_->size();
  const std::size_t cells = static_cast<std::size_t>(dims_[0] * dims_[1] * dims_[2]);
  // Whether the triangle order is spatial already: how many triangles have
  // their box's low corner within one cell of the previous one's, along
  // every axis: 88-99% in the samples and the Blender cloths, where the
  // query order gained nothing, 64% in cloth-ball's, where it saved about a
  // tenth of the pair stage.
  std::size_t near_previous = 0;
  for (std::size_t t = 1; t < n; ++t) {
    bool near = true;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t step = std::int64_t(cell_lo_[a][t]) - std::int64_t(cell_lo_[a][t - 1]);
      near = near && step >= -1 && step <= 1;
    }
    near_previous += near;
  }
  spatial_queries_ = n > kSpatialQueriesFrom && 4 * near_previous < 3 * n;
  if (!spatial_queries_) return;
  // The query order: triangles by home cell (their box's lowest), cells in
  // grid order, again a counting sort.
  home_first_.assign(cells + 1, 0);
  auto home_cell = [&](std::size_t t) {
    return std::size_t(cell_lo_[0][t]) +
           std::size_t(dims_[0]) * (std::size_t(cell_lo_[1][t]) + std::size_t(dims_[1]) * cell_lo_[2][t]);
  };
  for (std::size_t t = 0; t < n; ++t) ++home_first_[home_cell(t) + 1];
  for (std::size_t c = 0; c < cells; ++c) home_first_[c + 1] += home_first_[c];
  query_order_.resize(n);
  for (std::size_t t = 0; t < n; ++t) query_order_[home_first_[home_cell(t)]++] = static_cast<Index>(t);
}

void BoxGridBroadPhase::triangle_pairs(std::vector<TrianglePair>& pairs, const unsigned char* apart) {
  const std::vector<Dop18>& dops = *dops_;
  const std::size_t n = dops.size();
  stats_.root_triangles = n;

  const auto t = Clock::now();
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  block_pairs_.resize(blocks);
  block_candidates_.resize(blocks);
  block_tests_.assign(blocks, 0);
  block_culled_.assign(blocks, 0);
  block_left_out_.assign(blocks, 0);
  const std::vector<Triangle>& triangles = scene_->triangles();
  const Member* members = members_.data();
  const std::uint32_t *cell_lo_x = cell_lo_[0].data(), *cell_lo_y = cell_lo_[1].data(), *cell_lo_z = cell_lo_[2].data();
  const std::uint32_t *cell_hi_x = cell_hi_[0].data(), *cell_hi_y = cell_hi_[1].data(), *cell_hi_z = cell_hi_[2].data();
  const std::uint32_t* scan_first = scan_first_.data();
  const std::uint32_t* scan_end = scan_end_.data();
  const std::uint64_t* first_registration = first_registration_.data();
  const Index* query_order = spatial_queries_ ? query_order_.data() : nullptr;
  if (spatial_queries_) {
    partner_count_.resize(n);
    run_start_.resize(n);
  }
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
    std::vector<TrianglePair>& out = block_pairs_[block];
    out.clear();
    std::vector<Index>& candidates = block_candidates_[block];
    std::size_t tests = 0, culled = 0, left_out = 0;
    const std::size_t end = std::min(n, (block + 1) * kBlock);
    for (std::size_t q = block * kBlock; q < end; ++q) {
      const Index a = query_order ? query_order[q] : static_cast<Index>(q);
      if (query_order && q + 2 * kPrefetchQueries < end) {
        // In the spatial order a query's own arrays are far from the last
        // one's: fetch those of a later query now (cloth-ball: a tenth of
        // this stage waited on a's box).
        const Index later = query_order[q + 2 * kPrefetchQueries];
        __builtin_prefetch(&boxes_[later]);
        __builtin_prefetch(&first_registration[later]);
        for (const std::uint32_t* cells : {cell_lo_x, cell_lo_y, cell_lo_z, cell_hi_x, cell_hi_y, cell_hi_z})
          __builtin_prefetch(cells + later);
        __builtin_prefetch(scan_first + first_registration[later]);
        __builtin_prefetch(scan_end + first_registration[later]);
        __builtin_prefetch(&dops[later]);
        if (apart) __builtin_prefetch(&triangles[later]);
      }
      if (q + kPrefetchQueries < end) {
        // The first members that a later query scans in each of its cells:
        // waiting for them was half of this stage (cloth 100k).
        const Index later = query_order ? query_order[q + kPrefetchQueries] : static_cast<Index>(q + kPrefetchQueries);
        for (std::uint64_t r = first_registration[later]; r < first_registration[later + 1]; ++r)
          __builtin_prefetch(members + scan_first[r]);
      }
      // b's box overlaps a's when each of b's six quantised values is at
      // most a's limit for it: b's low corners at most a's high ones, b's
      // negated high corners at most a's negated low ones.
      std::int16_t limit[kQuantisedLanes];
      for (int k = 0; k < 3; ++k) {
        limit[k] = static_cast<std::int16_t>(-boxes_[a].quantised[3 + k]);
        limit[3 + k] = static_cast<std::int16_t>(-boxes_[a].quantised[k]);
      }
#if defined(__SSE2__)
      // Lanes 6 and 7 hold b's id: a limit of the largest value passes them.
      const __m128i limits = _mm_setr_epi16(limit[0], limit[1], limit[2], limit[3], limit[4], limit[5], INT16_MAX,
                                            INT16_MAX);
#endif
      const std::uint32_t ax = cell_lo_x[a], ay = cell_lo_y[a], az = cell_lo_z[a];
      const std::uint32_t* from = scan_first + first_registration[a];
      const std::uint32_t* to = scan_end + first_registration[a];
      // First every cell's boxes, without branches (a branch would often
      // mispredict), the candidates compacted ...
      std::size_t count = 0;
      for (std::uint32_t z = az; z <= cell_hi_z[a]; ++z) {
        for (std::uint32_t y = ay; y <= cell_hi_y[a]; ++y) {
          for (std::uint32_t x = ax; x <= cell_hi_x[a]; ++x) {
            // The pair is kept only in the cell of the low corner of the
            // boxes' intersection, max(a's lowest cell, b's) along each
            // axis: along an axis where this cell is above a's lowest, it
            // must be b's lowest.
            const std::uint32_t need =
                std::uint32_t(x != ax) | std::uint32_t(y != ay) << 1 | std::uint32_t(z != az) << 2;
            // The cell is sorted by triangle: those after a's own place are b > a.
            const Member* m = members + *from++;
            const Member* m_end = members + *to++;
            tests += static_cast<std::size_t>(m_end - m);
            if (candidates.size() < count + static_cast<std::size_t>(m_end - m))
              candidates.resize(2 * (count + static_cast<std::size_t>(m_end - m)));
            Index* kept = candidates.data();
            for (; m != m_end; ++m) {
              const std::uint32_t id = m->triangle_and_lowest;
#if defined(__SSE2__)
              // All six comparisons in one instruction.
              const __m128i values = _mm_load_si128(reinterpret_cast<const __m128i*>(m));
              const bool outside = _mm_movemask_epi8(_mm_cmpgt_epi16(values, limits)) != 0;
#else
              bool outside = false;
              for (int k = 0; k < kQuantisedLanes; ++k) outside |= m->quantised[k] > limit[k];
#endif
              const bool skip = outside | (((id >> kLowestShift) & need) != need);
              kept[count] = id & kTriangleMask;
              count += !skip;
            }
          }
        }
      }
      // ... without those that share an apart vertex with a (most of a
      // cloth's pairs: its neighbours), ...
      Index* kept = candidates.data();
      if (apart) {
        const Triangle& ta = triangles[a];
        Index shared_if_apart[3];
        bool any_apart = false;
        for (int i = 0; i < 3; ++i) {
          shared_if_apart[i] = apart[ta[i]] ? ta[i] : kNoVertex;
          any_apart = any_apart || apart[ta[i]];
        }
        if (any_apart) {
          // b's vertex ids, all fetched first (far apart in cloth-ball's order).
          for (std::size_t h = 0; h < count; ++h) __builtin_prefetch(&triangles[kept[h]]);
          std::size_t still = 0;
          for (std::size_t h = 0; h < count; ++h) {
            const Triangle& tb = triangles[kept[h]];
            bool shares = false;
            for (int i = 0; i < 3; ++i)
              shares |= (tb[0] == shared_if_apart[i]) | (tb[1] == shared_if_apart[i]) | (tb[2] == shared_if_apart[i]);
            kept[still] = kept[h];
            still += !shares;
          }
          left_out += count - still;
          count = still;
        }
      }
      // ... then their DOPs, fetched all at once first: in a mesh whose
      // triangle order is not spatial (cloth-ball's) each is a cache miss,
      // and waiting for them one by one was a quarter of this stage.
      for (std::size_t h = 0; h < count; ++h) {
        const char* dop = reinterpret_cast<const char*>(&dops[kept[h]]);
        __builtin_prefetch(dop);
        __builtin_prefetch(dop + 64);
        __builtin_prefetch(dop + sizeof(Dop18) - 1);
      }
      const Dop18& da = dops[a];
      const std::size_t first_out = out.size();
      for (std::size_t h = 0; h < count; ++h) {
        if (dop_overlap(da, dops[kept[h]]))
          out.push_back({a, kept[h]});
        else
          ++culled;
      }
      std::sort(out.begin() + static_cast<std::ptrdiff_t>(first_out), out.end());
      if (query_order) {
        run_start_[a] = first_out;
        partner_count_[a] = static_cast<std::uint32_t>(out.size() - first_out);
      }
    }
    block_tests_[block] = tests;
    block_culled_[block] = culled;
    block_left_out_[block] = left_out;
  });
  for (std::size_t b = 0; b < blocks; ++b) {
    stats_.tests += block_tests_[b];
    stats_.culled_by_dop += block_culled_[b];
    stats_.left_out_apart += block_left_out_[b];
  }
  if (!spatial_queries_) {
    // The blocks hold the triangles in order: concatenated, the output is sorted.
    std::size_t total = 0;
    for (const auto& block : block_pairs_) total += block.size();
    pairs.clear();
    pairs.reserve(total);
    for (const auto& block : block_pairs_) pairs.insert(pairs.end(), block.begin(), block.end());
  } else {
    put_back_in_triangle_order(pairs);
  }
  stats_.tests_after_control_bits = stats_.tests;
  stats_.triangle_pairs = pairs.size();
  stats_.leaf_triangles = n;
  stats_.seconds_pairs = seconds_since(t);
  std::size_t cursor_bytes = 0;
  for (const auto& cursors : range_cursors_) cursor_bytes += cursors.capacity() * sizeof(std::uint32_t);
  stats_.memory_bytes = dops.size() * sizeof(Dop18) + cell_first_.capacity() * sizeof(std::uint32_t) + cursor_bytes +
                        n * (6 * sizeof(std::uint32_t) + sizeof(std::uint64_t)) +
                        members_.capacity() * sizeof(Member) +
                        (scan_first_.capacity() + scan_end_.capacity()) * sizeof(std::uint32_t) +
                        boxes_.capacity() * sizeof(Member) +
                        query_order_.capacity() * sizeof(Index) + home_first_.capacity() * sizeof(std::uint64_t) +
                        partner_count_.capacity() * sizeof(std::uint32_t) +
                        run_start_.capacity() * sizeof(std::size_t) +
                        first_pair_.capacity() * sizeof(std::uint64_t) +
                        pairs.capacity() * sizeof(TrianglePair);
}

void BoxGridBroadPhase::put_back_in_triangle_order(std::vector<TrianglePair>& pairs) {
  // Each a's run goes to its place in triangle order: the output is sorted,
  // whatever the query order and the thread count.
  const std::size_t n = query_order_.size();
  first_pair_.resize(n + 1);
  first_pair_[0] = 0;
  for (std::size_t a = 0; a < n; ++a) first_pair_[a + 1] = first_pair_[a] + partner_count_[a];
  pairs.resize(first_pair_[n]);
  tbb::parallel_for(std::size_t(0), block_pairs_.size(), [&](std::size_t block) {
    const TrianglePair* out = block_pairs_[block].data();
    const std::size_t end = std::min(n, (block + 1) * kBlock);
    for (std::size_t q = block * kBlock; q < end; ++q) {
      const Index a = query_order_[q];
      std::copy_n(out + run_start_[a], partner_count_[a], pairs.data() + first_pair_[a]);
    }
  });
}

void BoxGridBroadPhase::detect_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                   std::vector<VertexFaceCandidate>& vf, std::vector<EdgeEdgeCandidate>& ee) {
  check_positions(scene_, x_t0, "x_t0");
  check_positions(scene_, x_t1, "x_t1");
  run_with_threads(*arena_, [&] {
    stats_ = BroadPhaseStats{};
    const auto start = Clock::now();
    compute_primitive_bounds(*scene_, x_t0, x_t1, settings_.thickness, bounds_);
    dops_ = &bounds_.triangles;
    stats_.seconds_bounds = seconds_since(start);
    const auto registration_start = Clock::now();
    build_grid();
    stats_.seconds_registration = seconds_since(registration_start);
    triangle_pairs(pairs_);
    feature_stage(*scene_, reps_, bounds_, pairs_, x_t0, x_t1, settings_, vf, ee, stats_);
    stats_.memory_bytes += (bounds_.edges.size() + bounds_.vertices.size()) * sizeof(Dop18);
    stats_.seconds_total = seconds_since(start);
  });
}

void BoxGridBroadPhase::detect_static(const std::vector<Vec3>& x, std::vector<TrianglePair>& pairs) {
  static_pairs(x, nullptr, {}, pairs);
}

void BoxGridBroadPhase::detect_static_leaving_out(const std::vector<Vec3>& x, const std::vector<unsigned char>& apart,
                                                  std::vector<TrianglePair>& pairs,
                                                  const std::function<void()>& find_apart) {
  // The flags are checked after find_apart has filled them.
  static_pairs(x, &apart, find_apart, pairs);
}

void BoxGridBroadPhase::static_pairs(const std::vector<Vec3>& x, const std::vector<unsigned char>* apart,
                                     const std::function<void()>& find_apart, std::vector<TrianglePair>& pairs) {
  check_positions(scene_, x, "x");
  run_with_threads(*arena_, [&] {
    stats_ = BroadPhaseStats{};
    const auto start = Clock::now();
    compute_static_triangle_dops(*scene_, x, settings_.thickness, static_dops_);
    dops_ = &static_dops_;
    stats_.seconds_bounds = seconds_since(start);
    const auto registration_start = Clock::now();
    if (find_apart) {
      tbb::parallel_invoke([&] { build_grid(); }, [&] { find_apart(); });
    } else {
      build_grid();
    }
    stats_.seconds_registration = seconds_since(registration_start);
    if (apart && apart->size() != x.size()) throw UsageError("broad phase: apart flags must have one per vertex");
    triangle_pairs(pairs, apart ? apart->data() : nullptr);
    stats_.candidates = pairs.size();
    stats_.seconds_total = seconds_since(start);
  });
}

}  // namespace snag
