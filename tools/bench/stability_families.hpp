// Generated families of hard CCD queries, each swept over one knob, to see
// where each method starts to fail: whole-step coplanar vertex-face and
// edge-edge motion, (nearly) parallel and collinear edges, contact at
// exactly t = 0 or t = 1, grazing (touching without crossing), tiny motion,
// coincident elements, and a plain crossing scaled from 1e-6 to 1e6 and
// translated far from the origin. Every sample's ground truth comes from the
// exact method on the doubles actually generated (construction aims at
// half hits, half near misses; rounding decides the rest).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tools/bench/method_counts.hpp"

namespace snag::bench {

struct StabilityFamily {
  std::string name;         ///< e.g. "vf-coplanar"
  bool edge_edge = false;
  std::string knob;         ///< what the knob is, e.g. "distance"
  std::string description;  ///< one sentence
  std::vector<double> knob_values;  ///< increasing, > 0 (charted on a log scale)
};

/// Every family, in a fixed order.
std::vector<StabilityFamily> stability_families();

/// `samples` queries of `family` at knob value `knob`, with their exact
/// ground truth; the same seed gives the same queries.
std::vector<LabelledQuery> family_queries(const StabilityFamily& family, double knob, int samples,
                                          std::uint64_t seed);

}  // namespace snag::bench
