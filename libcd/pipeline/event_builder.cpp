#include "libcd/pipeline/event_builder.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>

#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "libcd/pipeline/event_position.hpp"

namespace snag {

namespace {

Event collision(ContactType type, Index a, Index b, const CcdResult& result) {
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

ExactAnswer decide_exactly(const Certifier& certifier, const Scene& scene, const std::vector<Vec3>& x_t0,
                           const std::vector<Vec3>& x_t1, const VertexFaceCandidate& c, double thickness) {
  return certifier.vertex_face(vertex_face_points(scene, x_t0, x_t1, c), thickness);
}

ExactAnswer decide_exactly(const Certifier& certifier, const Scene& scene, const std::vector<Vec3>& x_t0,
                           const std::vector<Vec3>& x_t1, const EdgeEdgeCandidate& c, double thickness) {
  return certifier.edge_edge(edge_edge_points(scene, x_t0, x_t1, c), thickness);
}

Event collision_event(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                      const VertexFaceCandidate& c, const CcdResult& result) {
  return vertex_face_event(scene, x_t0, x_t1, c, result);
}

Event collision_event(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                      const EdgeEdgeCandidate& c, const CcdResult& result) {
  return edge_edge_event(scene, x_t0, x_t1, c, result);
}

template <class Candidate>
std::size_t search_uncertain(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                             const CcdSettings& settings, CcdHits<Candidate>& hits) {
  std::vector<std::size_t> uncertain;
  for (std::size_t k = 0; k < hits.results.size(); ++k) {
    if (hits.results[k].answer == CcdAnswer::kUncertain) uncertain.push_back(k);
  }
  if (uncertain.empty()) return 0;
  tbb::parallel_for(std::size_t{0}, uncertain.size(), [&](std::size_t j) {
    const std::size_t k = uncertain[j];
    hits.results[k] = ccd_test(scene, x_t0, x_t1, hits.candidates[k], settings);
  });
  std::size_t kept = 0;
  for (std::size_t k = 0; k < hits.results.size(); ++k) {
    if (hits.results[k].answer == CcdAnswer::kNo) continue;
    hits.candidates[kept] = hits.candidates[k];
    hits.results[kept] = hits.results[k];
    ++kept;
  }
  hits.candidates.resize(kept);
  hits.results.resize(kept);
  return uncertain.size();
}

template <class Candidate>
void append_collisions(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                       std::size_t tests, CcdHits<Candidate>& hits, const Certifier* certifier, double thickness,
                       bool edge_edge, NarrowPhaseStats& stats, std::vector<Event>& events) {
  std::vector<std::size_t> uncertain;
  for (std::size_t k = 0; k < hits.results.size(); ++k) {
    if (hits.results[k].answer == CcdAnswer::kUncertain) uncertain.push_back(k);
  }
  const std::size_t yes = hits.results.size() - uncertain.size();
  (edge_edge ? stats.ee_tests : stats.vf_tests) += tests;
  (edge_edge ? stats.ee_yes : stats.vf_yes) += yes;
  (edge_edge ? stats.ee_no : stats.vf_no) += tests - hits.results.size();
  (edge_edge ? stats.ee_uncertain : stats.vf_uncertain) += uncertain.size();
  if (certifier != nullptr && !uncertain.empty()) {
    const auto start = std::chrono::steady_clock::now();
    tbb::parallel_for(std::size_t{0}, uncertain.size(), [&](std::size_t j) {
      const std::size_t k = uncertain[j];
      const ExactAnswer exact = decide_exactly(*certifier, scene, x_t0, x_t1, hits.candidates[k], thickness);
      CcdResult& result = hits.results[k];
      result.answer = exact.collides ? CcdAnswer::kYes : CcdAnswer::kNo;
      result.toi_lo = exact.toi_lo;
      result.toi_hi = exact.toi_hi;
    });
    stats.seconds_certify += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats.certified += uncertain.size();
    for (std::size_t k : uncertain) stats.certified_true += hits.results[k].answer == CcdAnswer::kYes;
  }
  std::vector<std::size_t> colliding;
  colliding.reserve(hits.results.size());
  for (std::size_t k = 0; k < hits.results.size(); ++k) {
    if (hits.results[k].answer != CcdAnswer::kNo) colliding.push_back(k);
  }
  const std::size_t first = events.size();
  events.resize(first + colliding.size());
  tbb::parallel_for(std::size_t{0}, colliding.size(), [&](std::size_t j) {
    const std::size_t k = colliding[j];
    events[first + j] = collision_event(scene, x_t0, x_t1, hits.candidates[k], hits.results[k]);
  });
}

}  // namespace

CcdResult ccd_test(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                   const VertexFaceCandidate& candidate, const CcdSettings& settings) {
  const std::array<Vec3, 8> p = vertex_face_points(scene, x_t0, x_t1, candidate);
  return vertex_face_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings);
}

CcdResult ccd_test(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                   const EdgeEdgeCandidate& candidate, const CcdSettings& settings) {
  const std::array<Vec3, 8> p = edge_edge_points(scene, x_t0, x_t1, candidate);
  return edge_edge_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings);
}

std::size_t search_uncertain_hits(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                  const CcdSettings& settings, CcdHits<VertexFaceCandidate>& hits) {
  return search_uncertain(scene, x_t0, x_t1, settings, hits);
}

std::size_t search_uncertain_hits(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                  const CcdSettings& settings, CcdHits<EdgeEdgeCandidate>& hits) {
  return search_uncertain(scene, x_t0, x_t1, settings, hits);
}

void append_collision_events(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                             std::size_t tests, CcdHits<VertexFaceCandidate>& hits, const Certifier* certifier,
                             double thickness, NarrowPhaseStats& stats, std::vector<Event>& events) {
  append_collisions(scene, x_t0, x_t1, tests, hits, certifier, thickness, false, stats, events);
}

void append_collision_events(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                             std::size_t tests, CcdHits<EdgeEdgeCandidate>& hits, const Certifier* certifier,
                             double thickness, NarrowPhaseStats& stats, std::vector<Event>& events) {
  append_collisions(scene, x_t0, x_t1, tests, hits, certifier, thickness, true, stats, events);
}

std::array<Vec3, 8> vertex_face_points(const Scene& scene, const std::vector<Vec3>& x_t0,
                                       const std::vector<Vec3>& x_t1, const VertexFaceCandidate& c) {
  const Triangle& f = scene.triangles()[c.face];
  return {x_t0[c.vertex], x_t0[f[0]], x_t0[f[1]], x_t0[f[2]], x_t1[c.vertex], x_t1[f[0]], x_t1[f[1]], x_t1[f[2]]};
}

std::array<Vec3, 8> edge_edge_points(const Scene& scene, const std::vector<Vec3>& x_t0,
                                     const std::vector<Vec3>& x_t1, const EdgeEdgeCandidate& c) {
  const Edge& a = scene.edges()[c.edge_a];
  const Edge& b = scene.edges()[c.edge_b];
  return {x_t0[a[0]], x_t0[a[1]], x_t0[b[0]], x_t0[b[1]], x_t1[a[0]], x_t1[a[1]], x_t1[b[0]], x_t1[b[1]]};
}

Event vertex_face_event(const Scene&, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                        const VertexFaceCandidate& c, const CcdResult& result) {
  Event e = collision(ContactType::kVertexFace, c.vertex, c.face, result);
  e.position = lerp(x_t0[c.vertex], x_t1[c.vertex], 0.5 * (e.toi_lo + e.toi_hi));
  return e;
}

Event edge_edge_event(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                      const EdgeEdgeCandidate& c, const CcdResult& result) {
  Event e = collision(ContactType::kEdgeEdge, c.edge_a, c.edge_b, result);
  const double t = 0.5 * (e.toi_lo + e.toi_hi);
  const Edge& a = scene.edges()[c.edge_a];
  const Edge& b = scene.edges()[c.edge_b];
  e.position = segments_meeting_point(lerp(x_t0[a[0]], x_t1[a[0]], t), lerp(x_t0[a[1]], x_t1[a[1]], t),
                                      lerp(x_t0[b[0]], x_t1[b[0]], t), lerp(x_t0[b[1]], x_t1[b[1]], t));
  return e;
}

Event intersection_event(const Scene& scene, const std::vector<Vec3>& x, const TrianglePair& pair) {
  const Triangle& ta = scene.triangles()[pair.a];
  const Triangle& tb = scene.triangles()[pair.b];
  const Vec3 a[3] = {x[ta[0]], x[ta[1]], x[ta[2]]};
  const Vec3 b[3] = {x[tb[0]], x[tb[1]], x[tb[2]]};
  Event e;
  e.kind = EventKind::kIntersection;
  e.type = ContactType::kTriangleTriangle;
  e.a = pair.a;
  e.b = pair.b;
  e.position = triangles_meeting_point(a, b);
  return e;
}

void sort_events_from(std::vector<Event>& events, std::size_t first) {
  const auto begin = events.begin() + static_cast<std::ptrdiff_t>(first);
  if (!std::is_sorted(begin, events.end(), event_order)) std::sort(begin, events.end(), event_order);
}

void append_intersection_events(const Scene& scene, const std::vector<Vec3>& x,
                                const std::vector<TrianglePair>& intersecting, std::vector<Event>& events) {
  const std::size_t first = events.size();
  events.resize(first + intersecting.size());
  tbb::parallel_for(std::size_t{0}, intersecting.size(),
                    [&](std::size_t k) { events[first + k] = intersection_event(scene, x, intersecting[k]); });
}

}  // namespace snag
