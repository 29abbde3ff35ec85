// Settings and result of the continuous collision detection (CCD) narrow
// phase: vertex_face_ccd and edge_edge_ccd.
#pragma once

namespace snag {

/// Tuning of the conservative CCD kernels. Time is the normalised step
/// parameter t in [0, 1] (frame f at t = 0, frame f + 1 at t = 1).
struct CcdSettings {
  /// Contact distance d >= 0 in scene units; 0 means touching.
  double thickness = 0;
  /// Width of the time interval, in step units, to which the earliest time of
  /// contact is narrowed before a contact is certified (also the smallest
  /// width to which the surface parameters are bisected).
  double time_tolerance = 1e-6;
  /// Boxes of (t, u, v) examined before giving up with kUncertain.
  int max_iterations = 2048;
};

/// What floating point could prove about a pair.
enum class CcdAnswer {
  kNo,         ///< proven: the distance stays above the thickness for all t in [0, 1]
  kYes,        ///< proven: the distance reaches the thickness at some t in [0, 1]
  kUncertain,  ///< neither could be proven; exact arithmetic must decide
};

/// The answer and, for kYes and kUncertain, an enclosure of the earliest time
/// of contact: for kYes the earliest time lies in [toi_lo, toi_hi]; for
/// kUncertain, if there is a contact at all, the earliest lies in
/// [toi_lo, toi_hi]. For kNo both are 1.
struct CcdResult {
  CcdAnswer answer = CcdAnswer::kUncertain;
  double toi_lo = 0;
  double toi_hi = 1;
};

}  // namespace snag
