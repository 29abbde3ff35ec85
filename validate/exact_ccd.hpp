// Exact continuous collision detection for one vertex–face (VF) or edge–edge
// (EE) pair under linear motion: collides or not, with no tolerance, and the
// earliest time of impact as an exact isolating interval.
//
// Coordinates are taken as exact rationals (every double is one). The answer
// is exact in every configuration: coplanar for the whole step, parallel or
// collinear edges, zero-length edges, zero-area faces, contact at exactly
// t = 0 or t = 1, touching without crossing, no motion.
#pragma once

#include <array>
#include <string>

#include "libcd/geometry/vec3.hpp"

namespace snag::validate {

/// The answer of an exact CCD query.
struct ExactCcdResult {
  /// True when the pair comes within the thickness at some t in [0, 1].
  bool collides = false;
  /// The earliest time of impact t* lies in [toi_lo, toi_hi], both rounded
  /// outward to doubles and clamped to [0, 1]. Both are 1 when !collides.
  double toi_lo = 1, toi_hi = 1;
  /// The same interval as exact rationals "num/den" (before rounding to
  /// doubles); equal when t* is known exactly. Empty when !collides.
  std::string toi_lo_exact, toi_hi_exact;
  /// True when interval arithmetic decided the query (ExactMethod::kFiltered)
  /// and the rational method did not run. The answer is exact either way.
  bool filtered = false;
};

/// How a query given as doubles is decided. kFiltered first decides it with
/// interval arithmetic over the same sign conditions, which settles most
/// queries of zero thickness, and runs the rational method only when an
/// interval cannot tell a sign; kRational always runs the rational method.
/// Both give the same answer: collides, and a time of impact interval that
/// holds the same t* (the interval itself may be refined differently).
enum class ExactMethod { kFiltered, kRational };

/// A point with exact rational coordinates, each written "num/den" or "num"
/// in base 10 (for instance "-6589603590721879/162259276829213363391578010288128").
struct RationalVec3 {
  std::string x, y, z;
};

/// Exact vertex–face CCD.
/// points: 8 positions, v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1
///   (the row order of the CCD query files); each vertex moves linearly,
///   x(t) = x_t0 + t (x_t1 - x_t0), t in [0, 1].
/// thickness: d >= 0, in the units of the coordinates; contact means the
///   distance between the point and the closed triangle is <= d.
/// toi_width: the isolating interval of the earliest time of impact is
///   refined to an exact width <= toi_width (> 0) before outward rounding.
/// Throws snag::UsageError when thickness < 0, toi_width <= 0 or a value is
/// not finite.
ExactCcdResult exact_vertex_face_ccd(const std::array<Vec3, 8>& points, double thickness = 0,
                                     double toi_width = 1e-9, ExactMethod method = ExactMethod::kFiltered);

/// Exact edge–edge CCD between the closed segments (ea0, ea1) and (eb0, eb1).
/// points: ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1.
/// Other parameters and exceptions as exact_vertex_face_ccd.
ExactCcdResult exact_edge_edge_ccd(const std::array<Vec3, 8>& points, double thickness = 0,
                                   double toi_width = 1e-9, ExactMethod method = ExactMethod::kFiltered);

/// exact_vertex_face_ccd on exact rational coordinates.
/// Also throws snag::UsageError when a coordinate is not a rational "num/den".
ExactCcdResult exact_vertex_face_ccd(const std::array<RationalVec3, 8>& points,
                                     double thickness = 0, double toi_width = 1e-9);

/// exact_edge_edge_ccd on exact rational coordinates.
/// Also throws snag::UsageError when a coordinate is not a rational "num/den".
ExactCcdResult exact_edge_edge_ccd(const std::array<RationalVec3, 8>& points,
                                   double thickness = 0, double toi_width = 1e-9);

}  // namespace snag::validate
