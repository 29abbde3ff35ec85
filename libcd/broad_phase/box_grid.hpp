// A broad phase shaped for CPUs: a uniform grid of triangle boxes, queried
// triangle by triangle, with no subdivision and no global sort.
//
//   1. 18-DOPs of the triangles (static, or swept over the step), whose axis
//      slabs are the boxes, quantised to 16-bit integers once per triangle
//      (a monotone map, so no overlapping pair is lost);
//   2. a uniform grid over the boxes; each triangle is registered in every
//      cell its box overlaps (a stable counting sort by cell, so that each
//      cell lists its triangles in order), with its quantised box and three
//      bits saying whether the cell is the box's lowest along each axis, so
//      that a cell's scan streams 16 bytes per triangle, tests each box with
//      one SSE2 comparison and needs nothing else; for each registration,
//      the part of its cell after it is noted, in triangle order;
//   3. for each triangle a, in parallel over fixed blocks of triangles (in
//      their own order, or, for a large mesh whose order is not spatial, in
//      the order of their box's lowest cell, so that queries one after
//      another read the same cells and DOPs from cache), the
//      cells of its box are scanned from a's own place on (so only triangles
//      b > a are read, half of a cell on average), without branches, for
//      boxes that overlap a's, keeping the pair only in the cell that holds
//      the low corner of the two boxes' intersection (so it is found once,
//      without a sort and unique); with detect_static_leaving_out, those
//      sharing an apart vertex with a are dropped (vertex_fans.hpp: most of
//      a cloth's pairs); then the 18-DOPs of the rest are fetched together
//      (prefetches) and tested;
//   4. a's partners are sorted (a handful) and the blocks concatenated in
//      order (or, in the spatial order, each a's run copied to its place in
//      triangle order), so the output is sorted and the same for every
//      thread count.
// The cell size is twice the mean box extent (kCellPerExtent: registering
// costs more than the box tests it saves), grown until the grid has at
// most 4·#F + 64 cells and at most 16·#F registrations, so memory stays
// linear in the triangle count whatever the sizes (a scene of one huge
// triangle and many small ones ends with coarse cells, not a blow-up).
//
// The set returned is T_root exactly, the set of the brute force broad phase
// (brute_force.hpp): every pair (a < b) whose DOPs overlap. If the DOPs
// overlap, so do their axis slabs, the low corner of the boxes' intersection
// lies in both boxes, and the cell mapping (clamped floor of a scaled offset)
// is monotone, so that corner's cell lies in the cell ranges of both boxes:
// a's query sees b there. The CCD output is then the representative-triangle
// features of T_root, culled by vertex/face and edge/edge swept DOPs
// (feature_stage.hpp), as the other broad phases do.
//
// Ericson, "Real-Time Collision Detection", 2005, §7.1 (uniform grids, the
// low-corner rule for reporting a pair once); Klosowski et al. 1998 (k-DOPs).
#pragma once

#include <tbb/task_arena.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "libcd/bounding_volume/primitive_bounds.hpp"
#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/culling/representative_triangles.hpp"

namespace snag {

class BoxGridBroadPhase : public BroadPhase {
 public:
  void build(const Scene& scene, const BroadPhaseSettings& settings) override;
  void detect_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, std::vector<VertexFaceCandidate>& vf,
                  std::vector<EdgeEdgeCandidate>& ee) override;
  void detect_static(const std::vector<Vec3>& x, std::vector<TrianglePair>& pairs) override;
  /// detect_static without the pairs that share an apart vertex: they are
  /// dropped after the box test, before their DOPs are read. find_apart
  /// runs alongside the grid's registration (on another thread when there is one).
  void detect_static_leaving_out(const std::vector<Vec3>& x, const std::vector<unsigned char>& apart,
                                 std::vector<TrianglePair>& pairs, const std::function<void()>& find_apart) override;
  using BroadPhase::detect_static_leaving_out;
  const BroadPhaseStats& stats() const override { return stats_; }

 private:
  /// Triangle pairs whose DOPs (dops_, #F) overlap, sorted, into `pairs`;
  /// with `apart` (#V flags), none that shares a flagged vertex. The grid
  /// must have been built (build_grid).
  void triangle_pairs(std::vector<TrianglePair>& pairs, const unsigned char* apart = nullptr);
  /// The grid of the boxes of dops_: choose_grid, then register_boxes.
  void build_grid();
  /// detect_static's work, `apart` as in triangle_pairs, filled by
  /// `find_apart` (if any) alongside the registration.
  void static_pairs(const std::vector<Vec3>& x, const std::vector<unsigned char>* apart,
                    const std::function<void()>& find_apart, std::vector<TrianglePair>& pairs);
  /// Chooses the cell size and dimensions for the boxes of dops_.
  void choose_grid();
  /// Registers every triangle in the cells of its box (a stable counting
  /// sort by cell) and notes what each registration's query scans.
  void register_boxes();
  /// Decides whether to query the triangles in a spatial order
  /// (spatial_queries_) and, if so, sorts them into it (query_order_).
  void choose_query_order();
  /// The pairs of the block outputs, found in the spatial query order, into
  /// `pairs` sorted.
  void put_back_in_triangle_order(std::vector<TrianglePair>& pairs);

  const Scene* scene_ = nullptr;
  BroadPhaseSettings settings_;
  RepresentativeTriangles reps_;
  BroadPhaseStats stats_;
  PrimitiveBounds bounds_;  ///< CCD: all primitives' swept DOPs
  std::vector<Dop18> static_dops_;
  std::vector<TrianglePair> pairs_;  ///< CCD: the triangle pairs before the feature stage
  const std::vector<Dop18>* dops_ = nullptr;  ///< the triangle DOPs of this detection
  std::unique_ptr<tbb::task_arena> arena_;    ///< settings.threads workers, made once in build()

  // The grid, kept between detections so that its arrays are reused.
  double origin_[3] = {0, 0, 0};
  double inverse_cell_size_ = 1;
  std::int64_t dims_[3] = {1, 1, 1};
  /// Registrations are counted in 32 bits: choose_grid allows at most
  /// kMaxTriangles triangles, so at most 16·#F + 64 < 2^32 registrations.
  std::vector<std::uint32_t> cell_first_;  ///< #cells + 1, start of each cell's registrations
  /// Per range of triangles registered by one thread, #cells: its counts,
  /// then its cursors in the counting sort.
  std::vector<std::vector<std::uint32_t>> range_cursors_;
  std::vector<std::uint32_t> cell_lo_[3], cell_hi_[3];  ///< #F cell range of each box, per axis
  std::vector<std::uint64_t> first_registration_;       ///< #F + 1, prefix sum of range volumes
  /// A registration, 16 bytes: the triangle's box quantised, and the
  /// triangle with three bits saying whether the cell is the box's lowest
  /// along each axis. Each coordinate v of the box along axis k becomes
  /// floor((v - scene low corner) · kQuantumMax / scene extent), clamped to
  /// [0, kQuantumMax]: a monotone map, so that boxes that overlap keep
  /// overlapping (boxes that touch only after it are culled by the DOP test
  /// that follows). The high corner is stored negated, so that the box test
  /// is six "at most" comparisons (one SSE2 instruction).
  struct alignas(16) Member {
    std::int16_t quantised[6];  ///< low corner x, y, z, then the negated high corner
    std::uint32_t triangle_and_lowest;  ///< triangle | lowest-cell bits << kLowestShift
  };
  static constexpr int kQuantisedLanes = 6;
  static constexpr std::int16_t kQuantumMax = 32767;
  static constexpr int kLowestShift = 29;
  static constexpr std::uint32_t kTriangleMask = (std::uint32_t(1) << kLowestShift) - 1;
  /// The most triangles in one detection: ids fit under kTriangleMask and
  /// 16·#F + 64 registrations in 32 bits.
  static constexpr std::size_t kMaxTriangles = (std::size_t(1) << 28) - 64;
  std::vector<Member> boxes_;  ///< #F, each triangle's quantised box (lowest bits 0)
  std::vector<Member> members_;  ///< registrations in cell order, each cell by triangle
  /// Per registration in triangle order (first_registration_[t] + the
  /// cell's rank in t's box, x fastest): what t's query scans in that cell,
  /// the members after t's own (scan_first_) up to the cell's end
  /// (scan_end_). A query reads them in order, and prefetches the members
  /// of a later query from them, without looking the cells up.
  std::vector<std::uint32_t> scan_first_, scan_end_;
  /// Whether the triangles are queried in query_order_ rather than in their
  /// own order: only when there are many and their order is not spatial.
  bool spatial_queries_ = false;
  /// #F, the triangles in the order they are queried: by the cell of their
  /// box's low corner, so that queries one after another read the same
  /// cells and DOPs from cache in a mesh whose triangle order is not spatial.
  std::vector<Index> query_order_;
  std::vector<std::uint64_t> home_first_;  ///< #cells + 1, the query order's counting sort
  std::vector<std::uint32_t> partner_count_;  ///< #F: a's pairs
  std::vector<std::size_t> run_start_;        ///< #F: where a's pairs start in its block's output
  std::vector<std::uint64_t> first_pair_;   ///< #F + 1: where a's pairs start in the output
  // Output blocks, one per fixed range of the query order.
  std::vector<std::vector<TrianglePair>> block_pairs_;
  std::vector<std::vector<Index>> block_candidates_;  ///< per block: a triangle's boxes that overlap, before the DOPs
  std::vector<std::size_t> block_tests_, block_culled_, block_left_out_;
};

}  // namespace snag
