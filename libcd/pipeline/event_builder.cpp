#include "libcd/pipeline/event_builder.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <chrono>
#include <cstdint>

#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "libcd/pipeline/event_fields.hpp"

namespace snag {

namespace {

// Events per task of the passes over a step's events: each is a few
// nanoseconds of work.
constexpr std::size_t kEventsPerTask = 8192;
/// Up to this many sorted runs, sort_events_from merges them; more, it sorts.
constexpr std::size_t kMostRunsToMerge = 4096;

/// Copies events [from, from + count) over [to, to + count), on all threads.
void copy_events(const Event* from, std::size_t count, Event* to) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kEventsPerTask),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      std::copy(from + range.begin(), from + range.end(), to + range.begin());
                    });
}

/// Removes events[dropped[0]], events[dropped[1]], ... (ascending), the
/// order kept: each event after the first dropped one moves down by the
/// number dropped before it, out of place (a block's targets are the
/// sources of the block before it), on all threads.
void remove_events(std::vector<Event>& events, const std::vector<std::size_t>& dropped, EventScratch& scratch) {
  const std::size_t from = dropped.front(), kept = events.size() - from - dropped.size();
  Event* room = scratch.room(kept);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(from, events.size(), kEventsPerTask),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      auto next = std::lower_bound(dropped.begin(), dropped.end(), range.begin());
                      for (std::size_t k = range.begin(); k < range.end();) {
                        const std::size_t end = next != dropped.end() ? std::min(*next, range.end()) : range.end();
                        const auto before = static_cast<std::size_t>(next - dropped.begin());
                        std::copy(events.begin() + static_cast<std::ptrdiff_t>(k),
                                  events.begin() + static_cast<std::ptrdiff_t>(end), room + (k - from - before));
                        k = end;
                        if (next != dropped.end() && *next == k) {
                          ++k;
                          ++next;
                        }
                      }
                    });
  copy_events(room, kept, events.data() + from);
  events.resize(from + kept);
}

/// Where the runs of events[first, end) that are in event order start,
/// after `first` itself: the events out of order with the one before them.
std::vector<std::size_t> run_starts(const std::vector<Event>& events, std::size_t first) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(first + 1, events.size(), kEventsPerTask), std::vector<std::size_t>{},
      [&](const tbb::blocked_range<std::size_t>& range, std::vector<std::size_t> starts) {
        for (std::size_t i = range.begin(); i < range.end(); ++i)
          if (event_order(events[i], events[i - 1])) starts.push_back(i);
        return starts;
      },
      [](std::vector<std::size_t> left, const std::vector<std::size_t>& right) {  // left holds the earlier events
        left.insert(left.end(), right.begin(), right.end());
        return left;
      });
}

/// An event's place in event_order as three words, compared in order: the
/// frame; kind and type; a and b.
struct OrderKey {
  std::uint64_t frame, kind_type, ids;
};

OrderKey order_key(const Event& e) {
  return {e.frame, static_cast<std::uint64_t>(e.kind) << 2 | static_cast<std::uint64_t>(e.type),
          static_cast<std::uint64_t>(e.a) << 32 | e.b};
}

bool operator<(const OrderKey& x, const OrderKey& y) {
  if (x.frame != y.frame) return x.frame < y.frame;
  if (x.kind_type != y.kind_type) return x.kind_type < y.kind_type;
  return x.ids < y.ids;
}

/// Merges the sorted runs of events[bounds.front(), bounds.back()) (run r is
/// [bounds[r], bounds[r + 1])) into event order. The output is cut into
/// parts at splitter events sampled evenly from the input; each run is cut
/// at each splitter by a binary search, so part p takes from every run the
/// events between splitters p and p + 1, and its place in the output is the
/// count of events before its splitter. The parts merge on all threads into
/// the scratch room, which is copied back.
void merge_runs(std::vector<Event>& events, const std::vector<std::size_t>& bounds, EventScratch& scratch) {
  const std::size_t first = bounds.front(), count = bounds.back() - first, runs = bounds.size() - 1;
  const std::size_t parts = std::max<std::size_t>(1, count / kEventsPerTask);
  std::vector<Event> splitters;  // splitters[p - 1] starts part p
  for (std::size_t p = 1; p < parts; ++p) splitters.push_back(events[first + p * count / parts]);
  std::sort(splitters.begin(), splitters.end(), event_order);
  // cuts[p * runs + r]: where part p starts in run r.
  std::vector<std::size_t> cuts((parts + 1) * runs);
  tbb::parallel_for(std::size_t{0}, parts + 1, [&](std::size_t p) {
    for (std::size_t r = 0; r < runs; ++r) {
      const auto run_begin = events.begin() + static_cast<std::ptrdiff_t>(bounds[r]);
      const auto run_end = events.begin() + static_cast<std::ptrdiff_t>(bounds[r + 1]);
      cuts[p * runs + r] = p == 0       ? bounds[r]
                           : p == parts ? bounds[r + 1]
                                        : static_cast<std::size_t>(
                                              std::lower_bound(run_begin, run_end, splitters[p - 1], event_order) -
                                              events.begin());
    }
  });
  Event* room = scratch.room(count);
  tbb::parallel_for(std::size_t{0}, parts, [&](std::size_t p) {
    struct Cursor {
      OrderKey key;  // of *at
      const Event* at;
      const Event* end;
    };
    // A heap of the runs' pieces, the one with the least next event on top.
    const auto later = [](const Cursor& x, const Cursor& y) { return y.key < x.key; };
    std::vector<Cursor> heap;
    std::size_t out = 0;
    for (std::size_t r = 0; r < runs; ++r) {
      out += cuts[p * runs + r] - bounds[r];
      const Event* begin = events.data() + cuts[p * runs + r];
      const Event* end = events.data() + cuts[(p + 1) * runs + r];
      if (begin < end) heap.push_back({order_key(*begin), begin, end});
    }
    std::make_heap(heap.begin(), heap.end(), later);
    Event* to = room + out;
    while (!heap.empty()) {
      std::pop_heap(heap.begin(), heap.end(), later);
      Cursor& next = heap.back();
      *to++ = *next.at++;
      if (next.at == next.end) {
        heap.pop_back();
      } else {
        next.key = order_key(*next.at);
        std::push_heap(heap.begin(), heap.end(), later);
      }
    }
  });
  copy_events(room, count, events.data() + first);
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

Event* EventScratch::room(std::size_t count) {
  if (events_.size() < count) {
    events_.clear();
    events_.shrink_to_fit();
    events_.resize(count);
  }
  return events_.data();
}

void sort_events_from(std::vector<Event>& events, std::size_t first, EventScratch* scratch) {
  if (events.size() <= first + 1) return;
  std::vector<std::size_t> bounds = run_starts(events, first);
  if (bounds.empty()) return;
  if (bounds.size() + 1 > kMostRunsToMerge) {
    tbb::parallel_sort(events.begin() + static_cast<std::ptrdiff_t>(first), events.end(), event_order);
    return;
  }
  bounds.insert(bounds.begin(), first);
  bounds.push_back(events.size());
  EventScratch own;
  merge_runs(events, bounds, scratch != nullptr ? *scratch : own);
}

void append_events(std::vector<Event>& to, const Event* from, std::size_t count) {
  const std::size_t first = to.size();
  to.resize(first + count);
  copy_events(from, count, to.data() + first);
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
                                    std::size_t first, EventScratch* scratch) {
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
  std::vector<std::size_t> dropped;
  for (std::size_t j = 0; j < uncertain.size(); ++j)
    if (results[j].answer == CcdAnswer::kNo) dropped.push_back(uncertain[j]);
  if (dropped.empty()) return uncertain.size();
  EventScratch own;
  remove_events(events, dropped, scratch != nullptr ? *scratch : own);
  return uncertain.size();
}

}  // namespace snag
