// The fields of an event from the points of its query: one definition for
// host and device code, so that events built on the GPU (CudaNarrowPhase's
// *_events calls) are bit-identical to those event_builder.hpp builds on the
// CPU (the device code is compiled with --fmad=false).
#pragma once

#include "libcd/core/host_device.hpp"
#include "libcd/narrow_phase/ccd_result.hpp"
#include "libcd/pipeline/event.hpp"
#include "libcd/pipeline/event_position.hpp"

namespace snag {

/// A collision event (frame 0) of a kYes or kUncertain answer, without its position.
SNAG_HD_INLINE Event collision_fields(ContactType type, Index a, Index b, const CcdResult& result) {
  Event e;
  e.kind = EventKind::kCollision;
  e.type = type;
  e.a = a;
  e.b = b;
  e.toi_lo = result.toi_lo;
  e.toi_hi = result.toi_hi;
  e.certainty = result.answer == CcdAnswer::kYes ? Certainty::kProven : Certainty::kUncertain;
  return e;
}

/// The collision event of vertex `vertex` against face `face`, whose vertex
/// moves from v_t0 to v_t1: at the vertex, at the middle of the toi enclosure.
SNAG_HD_INLINE Event vertex_face_fields(Index vertex, Index face, Vec3 v_t0, Vec3 v_t1, const CcdResult& result) {
  Event e = collision_fields(ContactType::kVertexFace, vertex, face, result);
  e.position = lerp(v_t0, v_t1, 0.5 * (e.toi_lo + e.toi_hi));
  return e;
}

/// The collision event of edges edge_a and edge_b, whose ends (a0, a1, b0,
/// b1) move from ends_t0 to ends_t1: the segments' meeting point at the
/// middle of the toi enclosure.
SNAG_HD_INLINE Event edge_edge_fields(Index edge_a, Index edge_b, const Vec3 ends_t0[4], const Vec3 ends_t1[4],
                                      const CcdResult& result) {
  Event e = collision_fields(ContactType::kEdgeEdge, edge_a, edge_b, result);
  const double t = 0.5 * (e.toi_lo + e.toi_hi);
  e.position = segments_meeting_point(lerp(ends_t0[0], ends_t1[0], t), lerp(ends_t0[1], ends_t1[1], t),
                                      lerp(ends_t0[2], ends_t1[2], t), lerp(ends_t0[3], ends_t1[3], t));
  return e;
}

/// The intersection event (frame 0) of intersecting triangles a < b with corners pa and pb.
SNAG_HD_INLINE Event intersection_fields(Index a, Index b, const Vec3 pa[3], const Vec3 pb[3]) {
  Event e;
  e.kind = EventKind::kIntersection;
  e.type = ContactType::kTriangleTriangle;
  e.a = a;
  e.b = b;
  e.position = triangles_meeting_point(pa, pb);
  return e;
}

}  // namespace snag
