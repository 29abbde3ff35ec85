// Events from narrow-phase answers, built the same way by every back end so
// that their reports are bit-identical: the ids, the time-of-impact enclosure,
// the certainty, and a representative position (event_position.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "libcd/broad_phase/candidates.hpp"
#include "libcd/narrow_phase/ccd_result.hpp"
#include "libcd/pipeline/backend.hpp"
#include "libcd/pipeline/event.hpp"
#include "libcd/scene/scene.hpp"

namespace snag {

/// The 8 positions of a VF query: v_t0, f0_t0, f1_t0, f2_t0, then the same at t1
/// (the row order of Certifier::vertex_face). x_t0, x_t1: #V global positions.
std::array<Vec3, 8> vertex_face_points(const Scene& scene, const std::vector<Vec3>& x_t0,
                                       const std::vector<Vec3>& x_t1, const VertexFaceCandidate& candidate);
/// The 8 positions of an EE query: ea0, ea1, eb0, eb1 at t0, then at t1.
std::array<Vec3, 8> edge_edge_points(const Scene& scene, const std::vector<Vec3>& x_t0,
                                     const std::vector<Vec3>& x_t1, const EdgeEdgeCandidate& candidate);

/// A collision event (frame 0; the scan sets it) from a kYes or kUncertain
/// answer; the position is the contact point at the middle of the toi enclosure.
Event vertex_face_event(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                        const VertexFaceCandidate& candidate, const CcdResult& result);
Event edge_edge_event(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                      const EdgeEdgeCandidate& candidate, const CcdResult& result);

/// The CCD candidates a filter did not rule out: candidates[k] answered
/// results[k] (kYes or kUncertain), in candidate order.
template <class Candidate>
struct CcdHits {
  std::vector<Candidate> candidates;
  std::vector<CcdResult> results;
  void clear() {
    candidates.clear();
    results.clear();
  }
};

/// The whole floating-point CCD test of one candidate (vertex_face_ccd or
/// edge_edge_ccd of libcd/narrow_phase/ on its 8 points), as the CPU back end
/// runs it.
CcdResult ccd_test(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                   const VertexFaceCandidate& candidate, const CcdSettings& settings);
CcdResult ccd_test(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                   const EdgeEdgeCandidate& candidate, const CcdSettings& settings);

/// What both back ends do with the filter's answers to `tests` CCD queries of
/// one kind, given its hits: adds the yes/no/uncertain counts to `stats`
/// (vf_* or ee_*), certifies the uncertain hits with `certifier` when it is
/// not null (in parallel; stats' certification fields), and appends the
/// events of the hits that collide, in hit order. hits.results are updated
/// with the exact answers.
void append_collision_events(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                             std::size_t tests, CcdHits<VertexFaceCandidate>& hits, const Certifier* certifier,
                             double thickness, NarrowPhaseStats& stats, std::vector<Event>& events);
void append_collision_events(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                             std::size_t tests, CcdHits<EdgeEdgeCandidate>& hits, const Certifier* certifier,
                             double thickness, NarrowPhaseStats& stats, std::vector<Event>& events);

/// Room that the passes over a step's events reuse from one step to the
/// next (a back end keeps one): a step's events are tens of megabytes, and
/// memory taken fresh each step costs a page fault for every page it writes.
class EventScratch {
 public:
  /// At least `count` events of room, their contents unspecified.
  Event* room(std::size_t count);

 private:
  std::vector<Event> events_;
};

/// For collision events built on the device from a screen's hits
/// (CudaNarrowPhase::vertex_face_events, edge_edge_events): events[first,
/// end) are the hits of vf_tests vertex-face and ee_tests edge-edge queries,
/// with certainty kUncertain where the screen left the query undecided. Those
/// get the whole test (ccd_test with `settings`), then `certifier` (when not
/// null, at settings.thickness) for what is still uncertain; their events are
/// built again from the new answers and those that do not collide are
/// dropped, the order kept. Adds to `stats` what append_collision_events
/// adds after search by ccd_test, so that both give the same counts and the
/// same events. Returns how many were searched. The dropped events are
/// removed on all threads, through `scratch` (null: room of its own).
std::size_t settle_collision_events(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                    std::size_t vf_tests, std::size_t ee_tests, const CcdSettings& settings,
                                    const Certifier* certifier, NarrowPhaseStats& stats, std::vector<Event>& events,
                                    std::size_t first, EventScratch* scratch = nullptr);

/// Sorts events[first, end) by event_order, in parallel (on the calling task arena). The collisions of a step usually
/// arrive in that order already (candidates are sorted by the ids events are
/// ordered by, vertex-face before edge-edge), and then nothing is moved: the
/// check is one pass, on all threads. A step found in chunks arrives as a
/// few sorted runs (each chunk's vertex-face and edge-edge events), which
/// are merged, through `scratch` (null: room of its own); more than a few
/// thousand runs are sorted. Event keys are unique, so the result does not
/// depend on the input order.
void sort_events_from(std::vector<Event>& events, std::size_t first, EventScratch* scratch = nullptr);

/// Appends events [from, from + count) to `to`, copied on all threads (of
/// the calling task arena): a step's events are many megabytes.
void append_events(std::vector<Event>& to, const Event* from, std::size_t count);

/// An intersection event (frame 0) of an intersecting triangle pair at positions x.
Event intersection_event(const Scene& scene, const std::vector<Vec3>& x, const TrianglePair& pair);

/// Appends the intersection events of the intersecting `pairs`, in order
/// (built in parallel: each computes a point of the overlap).
void append_intersection_events(const Scene& scene, const std::vector<Vec3>& x,
                                const std::vector<TrianglePair>& intersecting, std::vector<Event>& events);

}  // namespace snag
