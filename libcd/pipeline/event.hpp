// What a scan finds: collisions between consecutive frames (CCD) and
// intersections within a frame (DCD), with global element ids.
#pragma once

#include <cstddef>
#include <tuple>

#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag {

enum class EventKind { kCollision, kIntersection };
/// Collision type: vertex–face or edge–edge. Intersections are triangle pairs.
enum class ContactType { kVertexFace, kEdgeEdge, kTriangleTriangle };

/// How sure the scan is of an event.
enum class Certainty {
  kProven,     ///< decided by a floating-point test with a proven error bound, or exactly
  kUncertain,  ///< the floating-point filter could not decide: may be a false positive
};

struct Event {
  EventKind kind = EventKind::kCollision;
  ContactType type = ContactType::kVertexFace;
  std::size_t frame = 0;  ///< collision: the step from frame to frame + 1; intersection: the frame
  /// Collisions: the earliest time of impact lies in [toi_lo, toi_hi], in
  /// frames relative to `frame` (0 = frame, 1 = frame + 1).
  double toi_lo = 0, toi_hi = 0;
  /// Global ids: VF: a = vertex, b = face; EE: a, b = edges; triangles: a < b faces.
  Index a = 0, b = 0;
  Vec3 position;  ///< where: the contact point at toi (collisions), a point of the overlap (intersections)
  Certainty certainty = Certainty::kProven;
};

/// The deterministic order of events in reports: frame, kind, type, a, b.
inline bool event_order(const Event& x, const Event& y) {
  return std::make_tuple(x.frame, x.kind, x.type, x.a, x.b) < std::make_tuple(y.frame, y.kind, y.type, y.a, y.b);
}

}  // namespace snag
