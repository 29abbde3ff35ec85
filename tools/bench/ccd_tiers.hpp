// Which tier of snag's certified CCD decides a query: the proven early exits
// (swept boxes, coplanarity sign, separating direction), the decisions by
// structure (contact at t = 0, a pair that moves as one), the search over
// time alone, the full (t, u, v) inclusion search, or exact arithmetic for
// what the floating-point filter left uncertain. The tiers are those of
// libcd/narrow_phase/vertex_face_ccd.hpp and edge_edge_ccd.hpp, called one
// after the other as vertex_face_ccd does.
#pragma once

#include "tools/bench/ccd_methods.hpp"

namespace snag::bench {

enum class CcdTier { kEarlyExit, kStructure, kTimeSearch, kFullSearch, kExact };
inline constexpr int kCcdTierCount = 5;

/// The tier's id in the JSON: "early_exit", "structure", "time_search", "full_search", "exact".
const char* tier_id(CcdTier tier);

struct TieredAnswer {
  CcdTier tier = CcdTier::kEarlyExit;
  bool collides = false;  ///< the certified answer (exact where the filter was uncertain)
};

/// The certified method's answer at thickness 0 and the tier that gave it.
/// Throws what the exact method throws.
TieredAnswer certified_with_tier(const CcdQueryPoints& query);

}  // namespace snag::bench
