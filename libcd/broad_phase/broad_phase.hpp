// The broad phase stage: an interface, its settings and counters, and a
// factory (after ipc-toolkit's broad_phase/). Every broad phase returns the
// same kinds of exact sets: sorted, unique, never a VF or EE pair sharing a
// vertex. See each implementation for the set it returns.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "libcd/broad_phase/candidates.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/grid/cell_size.hpp"
#include "libcd/scene/scene.hpp"

namespace snag {

struct BroadPhaseSettings {
  double lambda = kDefaultLambda;   ///< cell size = 3·λ·r_avg (> 1)
  double thickness = 0;             ///< pairs within this distance are kept; scene units, ≥ 0
  int max_subdivision_levels = 16;  ///< safety limit on Loop levels per triangle
  int max_time_halvings = 12;       ///< safety limit on time halvings per triangle (CCD)
  unsigned threads = 0;             ///< worker threads; 0 = all cores
  /// Count duplicate_culled_tests exactly. This keeps the key of every culled
  /// test until the end of the pair stage (8 bytes each, often most of the
  /// tests), so it is for benchmarks of the chapter's duplicate-test claim,
  /// not for production runs.
  bool count_culled_duplicates = false;
  /// The adaptive grid (kAdaptiveGrid, grid/adaptive_cells.hpp): a cell with
  /// more registrations than adaptive_cell_limit (≥ 2) is split into 2×2×2
  /// children, at most adaptive_max_depth ([0, 8]) levels below the grid.
  std::size_t adaptive_cell_limit = 64;
  int adaptive_max_depth = 4;
  /// CCD: leave out the triangle pairs that a fixed direction keeps more
  /// than the thickness apart over the step before their feature pairs are
  /// made (TriangleSeparation, culling/representative_triangles.hpp). Their
  /// feature pairs cannot touch, so the events are the same either way; off,
  /// the candidates are all the feature pairs whose DOPs overlap (for tests
  /// of that set and of the separation itself).
  bool separate_triangles = true;
};

/// Counts and times of one detection. The virtual subdivision chapter's
/// claims are about these counts. Grid fields are 0 for brute force.
struct BroadPhaseStats {
  // grid
  double cell_size = 0;
  int grid_dims[3] = {0, 0, 0};
  std::size_t cells_used = 0;
  std::size_t cells_subdivided = 0;     ///< adaptive grid: crowded cells split into children
  int deepest_level = 0;                ///< adaptive grid: deepest level below the grid with a registration
  // virtual subdivision
  std::size_t root_triangles = 0;
  std::size_t triangles_subdivided = 0;  ///< Loop splits, all levels
  std::size_t time_halvings = 0;         ///< time slot splits, all levels
  std::size_t oversized_leaves = 0;      ///< accepted at the safety limits
  std::vector<std::size_t> triangles_per_level, subdivided_per_level, halved_per_level;
  std::size_t leaf_triangles = 0;
  // registration
  std::size_t registrations = 0, home_registrations = 0, phantom_registrations = 0;
  std::size_t duplicate_registrations_removed = 0;  ///< by the scan after the sort
  // pair tests (one per work item); the VSS grids test the roots' float boxes
  // first: same_root_tests to tests_after_control_bits count among the tests
  // whose boxes meet
  std::size_t tests = 0;                          ///< pairs enumerated in cells
  std::size_t culled_by_boxes = 0;                ///< VSS grids: the roots' float boxes apart (float_box.hpp)
  std::size_t same_root_tests = 0;                ///< both registrations of one root (left by the scan, or other slots)
  std::size_t removed_by_time_slots = 0;          ///< slots not nested
  std::size_t removed_by_control_bits = 0;
  std::size_t removed_by_extended_control_bits = 0;
  std::size_t fallback_tests = 0;                 ///< phantom-phantom pairs tested (see control_bits.hpp)
  std::size_t tests_after_control_bits = 0;
  std::size_t culled_by_dop = 0;                  ///< tests culled by the triangles' 18-DOPs
  /// Of the tests the DOPs kept, those whose root pair another kept test had
  /// already given (exact; removed by the final sort and unique).
  std::size_t duplicate_root_pair_tests = 0;
  /// Of the tests the DOPs culled, those whose root pair another culled test
  /// had already given: exact with settings.count_culled_duplicates, else 0.
  /// The duplicates among all tests after the control bits are the sum of the two.
  std::size_t duplicate_culled_tests = 0;
  std::size_t triangle_pairs = 0;                 ///< unique triangle pairs after DOP culling
  /// CCD, of triangle_pairs: those kept apart over the step (settings.separate_triangles), which give no features.
  std::size_t separated_triangle_pairs = 0;
  /// detect_static_leaving_out: pairs sharing an apart vertex, left out
  /// before the DOP test (not in tests' culled_by_dop nor triangle_pairs).
  std::size_t left_out_apart = 0;
  // features
  std::size_t vf_before_culling = 0, vf_after_culling = 0;
  std::size_t ee_before_culling = 0, ee_after_culling = 0;
  std::size_t candidates = 0;  ///< final output size
  std::size_t memory_bytes = 0;  ///< bytes of the main arrays (peak working set estimate)
  // seconds per stage
  double seconds_bounds = 0, seconds_subdivision = 0, seconds_registration = 0, seconds_pairs = 0,
         seconds_features = 0, seconds_total = 0;
};

class BroadPhase {
 public:
  virtual ~BroadPhase() = default;

  /// Binds a scene (topology) and settings; call again when they change.
  /// Throws UsageError for settings out of range (λ ≤ 1 for the grid, negative thickness).
  virtual void build(const Scene& scene, const BroadPhaseSettings& settings) = 0;

  /// Continuous candidates for the step x_t0 → x_t1 (#V global positions each).
  /// Throws UsageError when build() was not called or the sizes differ from the scene's.
  virtual void detect_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                          std::vector<VertexFaceCandidate>& vf, std::vector<EdgeEdgeCandidate>& ee) = 0;

  /// Static triangle pairs at positions x (#V). Throws like detect_ccd.
  virtual void detect_static(const std::vector<Vec3>& x, std::vector<TrianglePair>& pairs) = 0;
  /// detect_static, where a pair of triangles sharing a vertex v with
  /// apart[v] != 0 (#V flags) may be left out: the caller has shown that
  /// such pairs do not intersect (narrow_phase/vertex_fans.hpp). This
  /// default leaves none out; the box grid leaves out all of them.
  /// `find_apart` (may be empty) is called once, before the flags are read,
  /// on this broad phase's threads and possibly alongside its own work (the
  /// box grid runs it while it registers the boxes): it must fill `apart`
  /// and may do other work of the caller's that reads nothing this writes.
  virtual void detect_static_leaving_out(const std::vector<Vec3>& x, const std::vector<unsigned char>& apart,
                                         std::vector<TrianglePair>& pairs, const std::function<void()>& find_apart) {
    (void)apart;
    if (find_apart) find_apart();
    detect_static(x, pairs);
  }
  /// detect_static_leaving_out with `apart` already filled.
  void detect_static_leaving_out(const std::vector<Vec3>& x, const std::vector<unsigned char>& apart,
                                 std::vector<TrianglePair>& pairs) {
    detect_static_leaving_out(x, apart, pairs, {});
  }

  /// Counts of the last detection.
  virtual const BroadPhaseStats& stats() const = 0;
};

enum class BroadPhaseMethod {
  kVirtualSubdivisionGrid,  ///< the chapter's method (virtual_subdivision_grid.hpp)
  kLargestTriangleGrid,     ///< Grand's grid, cell fits the largest triangle, no subdivision
  kBruteForce,              ///< all triangle pairs (brute_force.hpp)
  kBoxGrid,                 ///< the CPU's grid of triangle boxes, queried triangle by triangle (box_grid.hpp)
  kAdaptiveGrid,            ///< the VSS grid with crowded cells subdivided (grid/adaptive_cells.hpp)
  kSweepAndPrune,           ///< boxes sorted along one axis and swept (sweep_and_prune.hpp); CPU only
};

std::unique_ptr<BroadPhase> make_broad_phase(BroadPhaseMethod method);

/// The method's name in benchmarks and reports: "vss-grid", "largest-grid",
/// "brute-force", "box-grid", "adaptive-grid" or "sweep-and-prune".
const char* broad_phase_method_name(BroadPhaseMethod method);

}  // namespace snag
