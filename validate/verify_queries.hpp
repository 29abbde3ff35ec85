// Evaluation of CCD methods on query sets with exact ground truth (the CSV
// format of io/ccd_query_csv.hpp): the exact method of exact_ccd.hpp on the
// queries' exact rationals, and the floating-point filter that snag-scan runs
// (vertex_face_ccd / edge_edge_ccd, default CcdSettings), each compared with
// the ground truth.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "io/ccd_query_csv.hpp"

namespace snag::validate {

/// Confusion counts of one method on one kind of query (VF or EE).
struct QueryCounts {
  std::size_t queries = 0;
  std::size_t positives = 0;        ///< queries whose ground truth is a collision
  std::size_t true_positives = 0;   ///< answered yes, truth yes
  std::size_t false_positives = 0;  ///< answered yes, truth no
  std::size_t false_negatives = 0;  ///< answered no, truth yes
  std::size_t uncertain = 0;        ///< answered neither (the filter only)
  std::size_t uncertain_positives = 0;  ///< of the uncertain, truth yes
  double seconds = 0;               ///< wall time over all queries of this kind
};

/// One query a method got wrong.
struct QueryDisagreement {
  std::string method;  ///< "exact" or "filter"
  std::string file;
  std::size_t line = 0;  ///< 1-based line of the query's first row
  bool edge_edge = false;
  bool truth = false;
  std::string answer;  ///< "yes", "no" or "uncertain"
};

struct QueryEvaluation {
  QueryCounts exact_vf, exact_ee, filter_vf, filter_ee;
  /// Wrong answers: the exact method's false positives and negatives, and the
  /// filter's false positives and negatives (its uncertain answers are not
  /// wrong, only counted). In query order, exact first.
  std::vector<QueryDisagreement> disagreements;
};

/// Runs both methods on every query (one thread; times are per method).
/// Throws snag::UsageError when a coordinate cannot be parsed by the exact
/// method (the reader has already checked them).
QueryEvaluation evaluate_ccd_queries(const std::vector<io::CcdQuery>& queries);

}  // namespace snag::validate
