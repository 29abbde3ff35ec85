#include "tools/bench/ccd_tiers.hpp"

#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"

namespace snag::bench {

namespace {

TieredAnswer decided(CcdTier tier, const CcdResult& result) {
  return {tier, result.answer == CcdAnswer::kYes};
}

}  // namespace

const char* tier_id(CcdTier tier) {
  switch (tier) {
    case CcdTier::kEarlyExit: return "early_exit";
    case CcdTier::kStructure: return "structure";
    case CcdTier::kTimeSearch: return "time_search";
    case CcdTier::kFullSearch: return "full_search";
    case CcdTier::kExact: return "exact";
  }
  return "?";
}

TieredAnswer certified_with_tier(const CcdQueryPoints& query) {
  const auto& p = query.points;
  const CcdSettings settings;
  CcdResult result;
  if (query.edge_edge) {
    if (edge_edge_early_exit(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings, &result))
      return decided(CcdTier::kEarlyExit, result);
    const ccd_detail::EdgeEdgeContact contact{{p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]}};
    if (edge_edge_structure(contact, settings, &result)) return decided(CcdTier::kStructure, result);
    if (edge_edge_quick_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings, &result))
      return decided(CcdTier::kTimeSearch, result);
    result = ccd_detail::inclusion_ccd(contact, settings);
  } else {
    if (vertex_face_early_exit(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings, &result))
      return decided(CcdTier::kEarlyExit, result);
    const ccd_detail::VertexFaceContact contact{{p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]}};
    if (vertex_face_structure(contact, settings, &result)) return decided(CcdTier::kStructure, result);
    if (vertex_face_quick_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings, &result))
      return decided(CcdTier::kTimeSearch, result);
    result = ccd_detail::inclusion_ccd(contact, settings);
  }
  if (result.answer != CcdAnswer::kUncertain) return decided(CcdTier::kFullSearch, result);
  return {CcdTier::kExact, exact_collides(query)};
}

}  // namespace snag::bench
