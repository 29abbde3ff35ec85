// The CCD methods snag-bench compares, each on one vertex-face or edge-edge
// query: Provot's cubic in float and in double (provot_cubic_ccd.hpp),
// snag's conservative floating-point filter alone (snag-scan --precision
// fast: it may answer "uncertain"), the filter with exact certification of
// what it leaves uncertain (snag-scan's default), and the exact method alone
// (validate/exact_ccd.hpp). Thickness 0 throughout: the query sets' ground
// truth is contact at distance 0.
#pragma once

#include <array>
#include <string>

#include "libcd/geometry/vec3.hpp"

namespace snag::bench {

enum class CcdMethod { kCubicFloat, kCubicDouble, kFilter, kCertified, kExact };
inline constexpr int kCcdMethodCount = 5;
inline constexpr CcdMethod kCcdMethods[kCcdMethodCount] = {CcdMethod::kCubicFloat, CcdMethod::kCubicDouble,
                                                          CcdMethod::kFilter, CcdMethod::kCertified,
                                                          CcdMethod::kExact};

/// The method's id in the JSON ("cubic-float", "cubic-double", "filter",
/// "certified", "exact") and a label for people.
const char* method_id(CcdMethod method);
const char* method_label(CcdMethod method);

/// One query: 8 positions (the row order of the query files, see
/// io/ccd_query_csv.hpp), scene units, every point moving linearly over t in [0, 1].
struct CcdQueryPoints {
  bool edge_edge = false;
  std::array<Vec3, 8> points;
};

enum class CcdVerdict { kNo, kYes, kUncertain };

/// Runs `method` on `query`. Only kFilter answers kUncertain.
/// Throws snag::UsageError from the exact method when a coordinate is not finite.
CcdVerdict run_ccd_method(CcdMethod method, const CcdQueryPoints& query);

/// The exact answer (the ground truth of generated and scene queries).
bool exact_collides(const CcdQueryPoints& query);

}  // namespace snag::bench
