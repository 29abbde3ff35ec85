#include "libcd/broad_phase/broad_phase.hpp"

#include "libcd/broad_phase/box_grid.hpp"
#include "libcd/broad_phase/brute_force.hpp"
#include "libcd/broad_phase/sweep_and_prune.hpp"
#include "libcd/broad_phase/virtual_subdivision_grid.hpp"

namespace snag {

std::unique_ptr<BroadPhase> make_broad_phase(BroadPhaseMethod method) {
  switch (method) {
    case BroadPhaseMethod::kVirtualSubdivisionGrid: return std::make_unique<VirtualSubdivisionGrid>(true);
    case BroadPhaseMethod::kLargestTriangleGrid: return std::make_unique<VirtualSubdivisionGrid>(false);
    case BroadPhaseMethod::kBruteForce: return std::make_unique<BruteForceBroadPhase>();
    case BroadPhaseMethod::kBoxGrid: return std::make_unique<BoxGridBroadPhase>();
    case BroadPhaseMethod::kAdaptiveGrid:
      return std::make_unique<VirtualSubdivisionGrid>(true, VirtualSubdivisionGrid::Cells::kAdaptive);
    case BroadPhaseMethod::kSweepAndPrune: return std::make_unique<SweepAndPruneBroadPhase>();
  }
  return nullptr;
}

const char* broad_phase_method_name(BroadPhaseMethod method) {
  switch (method) {
    case BroadPhaseMethod::kVirtualSubdivisionGrid: return "vss-grid";
    case BroadPhaseMethod::kLargestTriangleGrid: return "largest-grid";
    case BroadPhaseMethod::kBruteForce: return "brute-force";
    case BroadPhaseMethod::kBoxGrid: return "box-grid";
    case BroadPhaseMethod::kAdaptiveGrid: return "adaptive-grid";
    case BroadPhaseMethod::kSweepAndPrune: return "sweep-and-prune";
  }
  return "?";
}

}  // namespace snag
