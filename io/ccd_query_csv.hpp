// Reader of CCD query files with exact ground truth (the CSV format of the
// benchmark of Wang et al., "A Large Scale Benchmark and an Inclusion-Based
// Algorithm for Continuous Collision Detection", ACM TOG 2021).
//
// A file holds 8 rows per query, each `xnum,xden,ynum,yden,znum,zden,truth`:
// one point whose coordinates are the rationals num/den (den a power of two),
// and the query's ground truth (0 or 1, the same on its 8 rows). Rows are
// ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1 (edge-edge)
// or v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1 (vertex-face).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "libcd/geometry/vec3.hpp"

namespace snag::io {

/// One coordinate as the exact rational numerator / 2^denominator_log2, with
/// the decimal text it was read from (for exact arithmetic elsewhere).
struct ExactCoordinate {
  std::int64_t numerator = 0;      ///< fits: the reader checks |numerator| < 2^63
  int denominator_log2 = 0;        ///< the denominator is 2^denominator_log2
  std::string numerator_text;      ///< as written, e.g. "-8388609"
  std::string denominator_text;    ///< as written, e.g. "8388608"
};

/// One query: 8 points (order in the file comment), exactly as doubles and as
/// rationals, and the ground truth.
struct CcdQuery {
  bool is_edge_edge = false;
  std::array<Vec3, 8> points;                                ///< exact values
  std::array<std::array<ExactCoordinate, 3>, 8> exact;       ///< [point][axis]
  bool truth = false;  ///< true when the primitives touch at some t in [0, 1]
  std::string file;    ///< the file it came from
  std::size_t line = 0;  ///< 1-based line of its first row
};

/// Reads every query of one file.
/// \param path          a CSV file in the format above
/// \param is_edge_edge  the kind of its queries (the format does not say)
/// \throws InputError (file and line) when the file cannot be read, a row does
///   not have 7 integer columns, a denominator is not a positive power of two,
///   a coordinate is not exactly representable as a double, the truth is not
///   0/1 or differs within a query, or the row count is not a multiple of 8.
std::vector<CcdQuery> read_ccd_query_csv(const std::string& path, bool is_edge_edge);

/// Reads every `*.csv` file under `root` whose parent folder is named
/// `vertex-face` or `edge-edge` (which gives the kind), in sorted path order.
/// \throws InputError when `root` is not a folder or a file is bad (as above).
std::vector<CcdQuery> read_ccd_query_tree(const std::string& root);

}  // namespace snag::io
