#include "libcd/pipeline/pair_thickness.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>

#include "libcd/pipeline/event_builder.hpp"
#include "libcd/pipeline/event_objects.hpp"

namespace snag {

namespace {

VertexFaceCandidate candidate_of(const Event& e, VertexFaceCandidate) { return {e.a, e.b}; }
EdgeEdgeCandidate candidate_of(const Event& e, EdgeEdgeCandidate) { return {e.a, e.b}; }

// Decides events[k] for k in `chosen` (collisions of one type) at `thickness`
// as the CPU back end decides its candidates: the filter on all cores, then
// append_collision_events (certification, event building). Writes the new
// event, or marks it dropped.
template <class Candidate>
void redecide(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
              const std::vector<std::size_t>& chosen, double thickness, CcdSettings ccd, const Certifier* certifier,
              std::vector<Event>& events, std::vector<char>& dropped) {
  if (chosen.empty()) return;
  ccd.thickness = thickness;
  std::vector<CcdResult> results(chosen.size());
  tbb::parallel_for(std::size_t{0}, chosen.size(), [&](std::size_t j) {
    results[j] = ccd_test(scene, x_t0, x_t1, candidate_of(events[chosen[j]], Candidate{}), ccd);
  });
  CcdHits<Candidate> hits;
  std::vector<std::size_t> hit_event;  // the event index of each hit
  for (std::size_t j = 0; j < chosen.size(); ++j) {
    if (results[j].answer == CcdAnswer::kNo) {
      dropped[chosen[j]] = 1;
      continue;
    }
    hits.candidates.push_back(candidate_of(events[chosen[j]], Candidate{}));
    hits.results.push_back(results[j]);
    hit_event.push_back(chosen[j]);
  }
  NarrowPhaseStats unused;
  std::vector<Event> decided;
  append_collision_events(scene, x_t0, x_t1, chosen.size(), hits, certifier, thickness, unused, decided);
  // append_collision_events appends one event per hit that still collides, in hit order.
  std::size_t next = 0;
  for (std::size_t k = 0; k < hits.results.size(); ++k) {
    const std::size_t i = hit_event[k];
    if (hits.results[k].answer == CcdAnswer::kNo) {
      dropped[i] = 1;
      continue;
    }
    assert(next < decided.size());
    Event e = decided[next++];
    e.frame = events[i].frame;
    events[i] = e;
  }
}

}  // namespace

RedecideCounts redecide_at_pair_thickness(const Scene& scene, const std::vector<Vec3>& x_t0,
                                          const std::vector<Vec3>& x_t1, const std::vector<double>& object_thickness,
                                          double run_thickness, const CcdSettings& ccd, const Certifier* certifier,
                                          std::vector<Event>& events) {
  assert(object_thickness.size() == scene.objects().size());
  // Events to decide again, grouped by pair thickness (one group per distinct
  // value, at most one per pair of objects) and by type.
  struct Group {
    double thickness;
    std::vector<std::size_t> vertex_face, edge_edge;
  };
  std::vector<Group> groups;
  for (std::size_t i = 0; i < events.size(); ++i) {
    const Event& e = events[i];
    if (e.kind != EventKind::kCollision) continue;
    const bool vf = e.type == ContactType::kVertexFace;
    const auto [a, b] = element_objects(scene, e);
    const double thickness = 0.5 * (object_thickness[a] + object_thickness[b]);
    if (!(thickness < run_thickness)) continue;
    auto group = std::find_if(groups.begin(), groups.end(), [&](const Group& g) { return g.thickness == thickness; });
    if (group == groups.end()) group = groups.insert(groups.end(), Group{thickness, {}, {}});
    (vf ? group->vertex_face : group->edge_edge).push_back(i);
  }

  RedecideCounts counts;
  std::vector<char> dropped(events.size(), 0);
  for (const Group& g : groups) {
    counts.redecided += g.vertex_face.size() + g.edge_edge.size();
    redecide<VertexFaceCandidate>(scene, x_t0, x_t1, g.vertex_face, g.thickness, ccd, certifier, events, dropped);
    redecide<EdgeEdgeCandidate>(scene, x_t0, x_t1, g.edge_edge, g.thickness, ccd, certifier, events, dropped);
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < events.size(); ++i) {
    if (dropped[i]) continue;
    events[kept++] = events[i];
  }
  counts.removed = events.size() - kept;
  events.resize(kept);
  return counts;
}

}  // namespace snag
