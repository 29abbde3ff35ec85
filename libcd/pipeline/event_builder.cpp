#include "libcd/pipeline/event_builder.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <chrono>

#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "libcd/pipeline/event_fields.hpp"

namespace snag {

namespace {

// Events per task of the passes over a step's events: each is a few
// nanoseconds of work.
constexpr std::size_t kEventsPerTask = 8192;

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

// The candidate a collision event was built from.
VertexFaceCandidate vertex_face_of(const Event& e) { return VertexFaceCandidate{e.a, e.b}; }
EdgeEdgeCandidate edge_edge_of(const Event& e) { return EdgeEdgeCandidate{e.a, e.b}; }

// The whole test, then the certifier, of the query behind an uncertain
// collision event.
CcdResult settle(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, const Event& e,
                 const CcdSettings& settings) {
  return e.type == ContactType::kVertexFace ? ccd_test(scene, x_t0, x_t1, vertex_face_of(e), settings)
                                            : ccd_test(scene, x_t0, x_t1, edge_edge_of(e), settings);
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
  return vertex_face_fields(c.vertex, c.face, x_t0[c.vertex], x_t1[c.vertex], result);
}

Event edge_edge_event(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                      const EdgeEdgeCandidate& c, const CcdResult& result) {
  const std::array<Vec3, 8> p = edge_edge_points(scene, x_t0, x_t1, c);
  return edge_edge_fields(c.edge_a, c.edge_b, &p[0], &p[4], result);
}

Event intersection_event(const Scene& scene, const std::vector<Vec3>& x, const TrianglePair& pair) {
  const Triangle& ta = scene.triangles()[pair.a];
  const Triangle& tb = scene.triangles()[pair.b];
  const Vec3 a[3] = {x[ta[0]], x[ta[1]], x[ta[2]]};
  const Vec3 b[3] = {x[tb[0]], x[tb[1]], x[tb[2]]};
  return intersection_fields(pair.a, pair.b, a, b);
}

void sort_events_from(std::vector<Event>& events, std::size_t first) {
  if (events.size() <= first + 1) return;
  // Each block checks its events against the one before them.
  const bool sorted = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(first + 1, events.size(), kEventsPerTask), true,
      [&](const tbb::blocked_range<std::size_t>& range, bool so_far) {
        for (std::size_t i = range.begin(); so_far && i < range.end(); ++i) so_far = !event_order(events[i], events[i - 1]);
        return so_far;
      },
      [](bool a, bool b) { return a && b; });
  if (!sorted) tbb::parallel_sort(events.begin() + static_cast<std::ptrdiff_t>(first), events.end(), event_order);
}

void append_events(std::vector<Event>& to, const Event* from, std::size_t count) {
  const std::size_t first = to.size();
  to.resize(first + count);
  Event* out = to.data() + first;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kEventsPerTask),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      std::copy(from + range.begin(), from + range.end(), out + range.begin());
                    });
}

void append_intersection_events(const Scene& scene, const std::vector<Vec3>& x,
                                const std::vector<TrianglePair>& intersecting, std::vector<Event>& events) {
  const std::size_t first = events.size();
  events.resize(first + intersecting.size());
  tbb::parallel_for(std::size_t{0}, intersecting.size(),
                    [&](std::size_t k) { events[first + k] = intersection_event(scene, x, intersecting[k]); });
}

std::size_t settle_collision_events(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                    std::size_t vf_tests, std::size_t ee_tests, const CcdSettings& settings,
                                    const Certifier* certifier, NarrowPhaseStats& stats, std::vector<Event>& events,
                                    std::size_t first) {
  // The vertex-face hits and the uncertain events, in order, on all threads.
  struct Found {
    std::size_t vf_hits = 0;
    std::vector<std::size_t> uncertain;
  };
  Found found = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(first, events.size(), kEventsPerTask), Found{},
      [&](const tbb::blocked_range<std::size_t>& range, Found sum) {
        for (std::size_t k = range.begin(); k < range.end(); ++k) {
          if (events[k].certainty == Certainty::kUncertain) sum.uncertain.push_back(k);
          sum.vf_hits += events[k].type == ContactType::kVertexFace;
        }
        return sum;
      },
      [](Found left, const Found& right) {  // left holds the earlier events
        left.vf_hits += right.vf_hits;
        left.uncertain.insert(left.uncertain.end(), right.uncertain.begin(), right.uncertain.end());
        return left;
      });
  const std::size_t vf_hits = found.vf_hits;
  const std::vector<std::size_t>& uncertain = found.uncertain;
  std::size_t hits[2] = {vf_hits, events.size() - first - vf_hits};  // vertex-face, edge-edge
  std::vector<CcdResult> results(uncertain.size());
  tbb::parallel_for(std::size_t{0}, uncertain.size(),
                    [&](std::size_t j) { results[j] = settle(scene, x_t0, x_t1, events[uncertain[j]], settings); });
  // As append_collision_events counts after search_uncertain: hits ruled
  // out by the search are "no", those it leaves uncertain "uncertain".
  std::size_t still[2] = {0, 0};
  std::vector<std::size_t> certify;
  for (std::size_t j = 0; j < uncertain.size(); ++j) {
    const int edge_edge = events[uncertain[j]].type == ContactType::kEdgeEdge;
    if (results[j].answer == CcdAnswer::kNo) --hits[edge_edge];
    if (results[j].answer == CcdAnswer::kUncertain) {
      ++still[edge_edge];
      certify.push_back(j);
    }
  }
  stats.vf_tests += vf_tests;
  stats.ee_tests += ee_tests;
  stats.vf_yes += hits[0] - still[0];
  stats.ee_yes += hits[1] - still[1];
  stats.vf_no += vf_tests - hits[0];
  stats.ee_no += ee_tests - hits[1];
  stats.vf_uncertain += still[0];
  stats.ee_uncertain += still[1];
  if (certifier != nullptr && !certify.empty()) {
    const auto start = std::chrono::steady_clock::now();
    tbb::parallel_for(std::size_t{0}, certify.size(), [&](std::size_t c) {
      const std::size_t j = certify[c];
      const Event& e = events[uncertain[j]];
      const ExactAnswer exact =
          e.type == ContactType::kVertexFace
              ? decide_exactly(*certifier, scene, x_t0, x_t1, vertex_face_of(e), settings.thickness)
              : decide_exactly(*certifier, scene, x_t0, x_t1, edge_edge_of(e), settings.thickness);
      results[j] = CcdResult{exact.collides ? CcdAnswer::kYes : CcdAnswer::kNo, exact.toi_lo, exact.toi_hi};
    });
    stats.seconds_certify += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats.certified += certify.size();
    for (std::size_t j : certify) stats.certified_true += results[j].answer == CcdAnswer::kYes;
  }
  if (uncertain.empty()) return 0;
  // The settled events are built again from their new answers; those that
  // do not collide are dropped, the order kept.
  tbb::parallel_for(std::size_t{0}, uncertain.size(), [&](std::size_t j) {
    Event& e = events[uncertain[j]];
    if (results[j].answer == CcdAnswer::kNo) return;
    e = e.type == ContactType::kVertexFace ? vertex_face_event(scene, x_t0, x_t1, vertex_face_of(e), results[j])
                                           : edge_edge_event(scene, x_t0, x_t1, edge_edge_of(e), results[j]);
  });
  std::size_t j = 0;
  while (j < uncertain.size() && results[j].answer != CcdAnswer::kNo) ++j;
  if (j == uncertain.size()) return uncertain.size();
  std::size_t kept = uncertain[j];  // the first dropped: the events after it move down
  for (std::size_t k = uncertain[j]; k < events.size(); ++k) {
    if (j < uncertain.size() && uncertain[j] == k && results[j++].answer == CcdAnswer::kNo) continue;
    events[kept++] = events[k];
  }
  events.resize(kept);
  return uncertain.size();
}

}  // namespace snag
