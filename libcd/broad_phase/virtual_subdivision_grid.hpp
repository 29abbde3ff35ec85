// The virtual subdivision scheme (VSS) uniform grid, and Grand's grid whose
// cell fits the largest triangle (the same pipeline without subdivision).
//
// Wong, Leach, Zambetta, "virtual subdivision for uniform-grid collision
// detection" (the chapter in ../shared/seed/), Algorithm 1:
//   1. swept 18-DOPs of triangles, edges and vertices (bounding_volume/)
//   2. cell size 3·λ·r_avg, grid over both frames (grid/cell_size)
//   3. virtual Loop subdivision and time halving, level by level (subdivision/)
//   4. registration in home and phantom cells with control bits, one sort by
//      cell id, one scan removing duplicate registrations (grid/cell_registration)
//   5. one test per work item (grid/pair_index): the roots' float boxes
//      (bounding_volume/float_box), control bits and extended control bits
//      (grid/control_bits), triangle 18-DOP culling; the rules count among
//      the tests whose boxes meet (culled_by_boxes: the others)
//   6. final sort + unique of root pairs: the duplicate root-pair tests that
//      remain are counted exactly, then removed
//   7. representative triangles and feature-level DOP culling (culling/)
// Grand, GPU Gems 3 ch. 32 (2007); Klosowski et al. 1998 (k-DOPs);
// Curtis, Tamstorf, Manocha 2008 (representative triangles);
// Pabst et al. 2010, Fan et al. 2011 (one test per thread).
//
// Time halving (CCD). A leaf carries a time slot [k/2^e, (k+1)/2^e]; its DOP
// bounds the sub-triangle over that slot only. Two leaves are tested only when
// their slots are nested (share an interval of positive length). A root's
// slots partition [0,1], so any time t lies in nested slots of both roots:
// any contact of two roots at any t is seen through a pair of leaves tested.
// Candidates of all slots are unioned into root pairs (sort + unique); the
// narrow phase then runs on the whole step [0,1], so the earliest time of
// impact is found, not a per-slot one.
//
// The set returned. Let L be the leaves (root, barycentric corners, slot) and
// D(x) their DOPs. The triangle pairs T are the root pairs (A, B) whose root
// swept DOPs overlap and that are tested in some cell. It holds that
//   T_leaf ⊆ T ⊆ T_root,
// T_leaf = {(A,B): root DOPs overlap and some leaves a of A, b of B with
//           nested slots have overlapping DOPs}  (brute_force_leaf_triangle_pairs),
// T_root = {(A,B): root DOPs overlap}             (the brute force broad phase).
// T ⊆ T_root: every output pair passed the root DOP test. T_leaf ⊆ T: if D(a)
// and D(b) overlap, their axis slabs share a point, so by monotone cell
// mapping their blocks share a cell; both roots are registered there; by the
// rule of control_bits.hpp the pair is tested in some cell: in a cell C where
// one of the two is registered at home, either C is the smallest cell of R
// (tested) or the smallest cell of R has a smaller id and again has one at
// home and the other registered (the scan keeps a home registration in every
// run, and the redirect cells are homes of accepted leaves of the same unit,
// lying in the other leaf's block); induction on cell id ends in a test. In a
// cell where both are phantom, one redirect leads to a cell with one at home
// if R is not empty; if it is empty, the pair is tested in the low corner of
// the blocks' intersection or passed on to that corner, a cell of smaller id. The CCD output is then the
// representative-triangle features of T, culled by vertex/face and edge/edge
// swept DOPs; the static output is T itself. For the largest-triangle grid
// no triangle is split and T = T_root exactly.
// No contact is lost: a contact at time t lies in leaves of both roots whose
// slots hold t, whose DOPs contain it (children tile their parent; the
// rounding pad covers interpolation error).
#pragma once

#include <vector>

#include "libcd/bounding_volume/float_box.hpp"
#include "libcd/bounding_volume/primitive_bounds.hpp"
#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/culling/representative_triangles.hpp"
#include "libcd/subdivision/virtual_subdivision.hpp"

namespace snag {

class VirtualSubdivisionGrid : public BroadPhase {
 public:
  /// Where pairs are tested: the uniform grid's cells (steps 4-5 above), or
  /// those cells with the crowded ones subdivided (grid/adaptive_cells.hpp).
  /// The adaptive grid returns exactly T_leaf: a pair of leaves is tested in
  /// the one cell that owns it, and kept when the leaves' DOPs and the roots'
  /// DOPs overlap.
  enum class Cells { kUniform, kAdaptive };

  /// subdivide = true: the VSS grid; false: the cell fits the largest triangle.
  explicit VirtualSubdivisionGrid(bool subdivide = true, Cells cells = Cells::kUniform)
      : subdivide_(subdivide), cells_(cells) {}

  void build(const Scene& scene, const BroadPhaseSettings& settings) override;
  void detect_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, std::vector<VertexFaceCandidate>& vf,
                  std::vector<EdgeEdgeCandidate>& ee) override;
  void detect_static(const std::vector<Vec3>& x, std::vector<TrianglePair>& pairs) override;
  const BroadPhaseStats& stats() const override { return stats_; }

  /// The leaves and primitive bounds of the last detection (for oracles and tools).
  const std::vector<Leaf>& leaves() const { return leaves_; }
  const PrimitiveBounds& bounds() const { return bounds_; }
  const GridSpec& grid() const { return grid_; }

 private:
  struct PairTests;
  std::vector<TrianglePair> triangle_pairs(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1);
  PairTests uniform_pair_tests();
  PairTests adaptive_pair_tests();

  bool subdivide_;
  Cells cells_;
  const Scene* scene_ = nullptr;
  BroadPhaseSettings settings_;
  RepresentativeTriangles reps_;
  BroadPhaseStats stats_;
  std::vector<Leaf> leaves_;
  PrimitiveBounds bounds_;
  std::vector<FloatBox> root_boxes_;  ///< float_box_of(bounds_.triangles[f]): each test's first filter
  GridSpec grid_;
};

}  // namespace snag
