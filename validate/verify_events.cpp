#include "validate/verify_events.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <tuple>

#include "validate/exact_ccd.hpp"
#include "validate/exact_triangle_intersection.hpp"
#include "validate/verify_candidates.hpp"
#include "validate/verify_exclusion.hpp"

namespace snag::validate {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// An event's identity: kind, type, frame and the pair, EE and triangle pairs
// in increasing id order.
using EventKey = std::tuple<int, int, std::size_t, Index, Index>;

EventKey key_of(const Event& e) {
  Index a = e.a, b = e.b;
  if (e.type != ContactType::kVertexFace && b < a) std::swap(a, b);
  return {static_cast<int>(e.kind), static_cast<int>(e.type), e.frame, a, b};
}

// The two frames' positions of the pair, in the row order of exact_ccd.hpp.
std::array<Vec3, 8> ccd_points(const Scene& scene, const Event& e, const std::vector<Vec3>& x_t0,
                               const std::vector<Vec3>& x_t1) {
  if (e.type == ContactType::kVertexFace) {
    const Triangle& f = scene.triangles()[e.b];
    return {x_t0[e.a], x_t0[f[0]], x_t0[f[1]], x_t0[f[2]], x_t1[e.a], x_t1[f[0]], x_t1[f[1]], x_t1[f[2]]};
  }
  const Edge& a = scene.edges()[e.a];
  const Edge& b = scene.edges()[e.b];
  return {x_t0[a[0]], x_t0[a[1]], x_t0[b[0]], x_t0[b[1]], x_t1[a[0]], x_t1[a[1]], x_t1[b[0]], x_t1[b[1]]};
}

// Whether the pair shares a vertex id (then it is never a pair).
bool shares_vertex(const Scene& scene, const Event& e) {
  if (e.type == ContactType::kVertexFace) {
    const Triangle& f = scene.triangles()[e.b];
    return e.a == f[0] || e.a == f[1] || e.a == f[2];
  }
  const Edge& a = scene.edges()[e.a];
  const Edge& b = scene.edges()[e.b];
  return a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1];
}

// The contact thickness of a collision's pair of objects.
double pair_thickness(const Scene& scene, const Event& e, const VerifySettings& settings) {
  if (settings.object_thickness.empty()) return settings.thickness;
  const bool vf = e.type == ContactType::kVertexFace;
  const std::size_t a = vf ? scene.object_of_vertex(e.a) : scene.object_of_edge(e.a);
  const std::size_t b = vf ? scene.object_of_triangle(e.b) : scene.object_of_edge(e.b);
  return 0.5 * (settings.object_thickness[a] + settings.object_thickness[b]);
}

ExactCcdResult exact_ccd(const Scene& scene, const Event& e, const std::vector<Vec3>& x_t0,
                         const std::vector<Vec3>& x_t1, const VerifySettings& settings) {
  const std::array<Vec3, 8> points = ccd_points(scene, e, x_t0, x_t1);
  const double thickness = pair_thickness(scene, e, settings);
  return e.type == ContactType::kVertexFace ? exact_vertex_face_ccd(points, thickness, settings.toi_width)
                                            : exact_edge_edge_ccd(points, thickness, settings.toi_width);
}

EventCheck check_collision(const Scene& scene, const Event& e, const std::vector<Vec3>& x_t0,
                           const std::vector<Vec3>& x_t1, const VerifySettings& settings) {
  EventCheck check;
  if (shares_vertex(scene, e)) {
    check.verdict = Verdict::kFalse;
    check.reason = e.type == ContactType::kVertexFace ? "the vertex is a corner of the face"
                                                      : "the edges share a vertex";
    return check;
  }
  const ExactCcdResult exact = exact_ccd(scene, e, x_t0, x_t1, settings);
  if (!exact.collides) {
    check.verdict = Verdict::kFalse;
    check.reason = "no contact in the step";
    return check;
  }
  check.exact_toi_lo = exact.toi_lo;
  check.exact_toi_hi = exact.toi_hi;
  const double tolerance = settings.toi_tolerance;
  if (e.toi_lo > exact.toi_hi + tolerance || e.toi_hi < exact.toi_lo - tolerance) {
    check.verdict = Verdict::kToiMismatch;
    check.reason = "the reported time of impact misses the exact earliest one";
  }
  return check;
}

std::array<Vec3, 3> corners(const Triangle& t, const std::vector<Vec3>& x) { return {x[t[0]], x[t[1]], x[t[2]]}; }

// The scan's rule for one triangle pair (triangle_triangle.hpp): degenerate
// triangles are never paired, a duplicated face intersects its twin, other
// pairs by exact_triangles_intersect. Sets `reason` when false.
bool triangles_intersect_exactly(const Scene& scene, Index a, Index b, const std::vector<Vec3>& x,
                                 const char** reason) {
  const Triangle& ta = scene.triangles()[a];
  const Triangle& tb = scene.triangles()[b];
  if (a == b) {
    *reason = "a face paired with itself";
    return false;
  }
  const std::array<Vec3, 3> pa = corners(ta, x), pb = corners(tb, x);
  if (exact_triangle_is_degenerate(pa) || exact_triangle_is_degenerate(pb)) {
    *reason = "a face is degenerate (collinear corners) and is never paired";
    return false;
  }
  int shared = 0;
  for (Index u : ta)
    for (Index v : tb) shared += u == v;
  if (shared >= 3) return true;
  if (exact_triangles_intersect(pa, {ta[0], ta[1], ta[2]}, pb, {tb[0], tb[1], tb[2]})) return true;
  *reason = "the triangles do not intersect";
  return false;
}

// Holds the positions of at most two frames, reading on demand; a read
// replaces the frame used least recently, so a step's two frames stay.
class FrameWindow {
 public:
  explicit FrameWindow(const FrameSource& source) : source_(source) {}
  const std::vector<Vec3>& frame(std::size_t i) {
    for (int s = 0; s < 2; ++s) {
      if (slots_[s].index == i) {
        last_used_ = s;
        return slots_[s].x;
      }
    }
    const int s = 1 - last_used_;
    source_.read_frame(i, slots_[s].x);
    slots_[s].index = i;
    last_used_ = s;
    ++reads_;
    return slots_[s].x;
  }
  std::size_t reads() const { return reads_; }

 private:
  struct Slot {
    std::size_t index = static_cast<std::size_t>(-1);
    std::vector<Vec3> x;
  };
  const FrameSource& source_;
  Slot slots_[2];
  int last_used_ = 1;
  std::size_t reads_ = 0;
};

}  // namespace

VerifyResult verify_events(const FrameSource& source, const std::vector<Event>& reported,
                           const VerifySettings& settings) {
  const Scene& scene = source.scene();
  VerifyResult result;
  result.checks.resize(reported.size());

  // Reported events by frame (collisions: step), duplicates marked false.
  std::vector<std::size_t> order(reported.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t i, std::size_t j) { return key_of(reported[i]) < key_of(reported[j]); });
  std::vector<EventKey> reported_keys;
  std::vector<std::size_t> to_check;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const EventKey key = key_of(reported[order[k]]);
    if (!reported_keys.empty() && reported_keys.back() == key) {
      result.checks[order[k]].verdict = Verdict::kFalse;
      result.checks[order[k]].reason = "listed twice";
      continue;
    }
    reported_keys.push_back(key);
    to_check.push_back(order[k]);
  }
  // to_check is in key order: frame-major within each kind. Regroup by frame.
  std::stable_sort(to_check.begin(), to_check.end(),
                   [&](std::size_t i, std::size_t j) { return reported[i].frame < reported[j].frame; });

  // The candidate sets are complete for the thickest pair, hence for every pair.
  double search_thickness = settings.thickness;
  for (double h : settings.object_thickness) search_thickness = std::max(search_thickness, h);

  FrameWindow window(source);
  const std::size_t frame_count = source.frame_count();
  std::size_t next = 0;
  for (std::size_t f = 0; f < frame_count; ++f) {
    std::size_t end = next;
    while (end < to_check.size() && reported[to_check[end]].frame == f) ++end;
    const bool step_exists = f + 1 < frame_count;
    if (end == next && !settings.exhaustive) continue;

    const auto start = Clock::now();
    const std::vector<Vec3>& x_f = window.frame(f);
    const std::vector<Vec3>* x_t1 = nullptr;
    bool has_collisions = settings.exhaustive && settings.collisions && step_exists;
    for (std::size_t k = next; k < end; ++k) has_collisions |= reported[to_check[k]].kind == EventKind::kCollision;
    if (has_collisions && step_exists) x_t1 = &window.frame(f + 1);

    tbb::parallel_for(next, end, [&](std::size_t k) {
      const std::size_t i = to_check[k];
      const Event& e = reported[i];
      if (e.kind == EventKind::kCollision) {
        result.checks[i] = check_collision(scene, e, x_f, *x_t1, settings);
      } else {
        const char* reason = "";
        if (!triangles_intersect_exactly(scene, e.a, e.b, x_f, &reason)) {
          result.checks[i].verdict = Verdict::kFalse;
          result.checks[i].reason = reason;
        }
      }
    });
    result.seconds_reported += seconds_since(start);
    next = end;
    if (!settings.exhaustive) continue;

    const auto exhaustive_start = Clock::now();
    auto reported_pair = [&](EventKind kind, ContactType type, Index a, Index b) {
      return std::binary_search(reported_keys.begin(), reported_keys.end(),
                                EventKey{static_cast<int>(kind), static_cast<int>(type), f, a, b});
    };
    std::vector<Event> tests;
    if (settings.intersections) {
      for (const TrianglePair& pair : complete_triangle_candidates(scene, x_f)) {
        if (reported_pair(EventKind::kIntersection, ContactType::kTriangleTriangle, pair.a, pair.b)) continue;
        Event e;
        e.kind = EventKind::kIntersection;
        e.type = ContactType::kTriangleTriangle;
        e.frame = f;
        e.a = pair.a;
        e.b = pair.b;
        tests.push_back(e);
      }
    }
    if (settings.collisions && step_exists) {
      std::vector<VertexFaceCandidate> vf;
      std::vector<EdgeEdgeCandidate> ee;
      complete_ccd_candidates(scene, x_f, *x_t1, search_thickness, vf, ee);
      for (const VertexFaceCandidate& c : vf) {
        if (reported_pair(EventKind::kCollision, ContactType::kVertexFace, c.vertex, c.face)) continue;
        Event e;
        e.frame = f;
        e.a = c.vertex;
        e.b = c.face;
        tests.push_back(e);
      }
      for (const EdgeEdgeCandidate& c : ee) {
        if (reported_pair(EventKind::kCollision, ContactType::kEdgeEdge, c.edge_a, c.edge_b)) continue;
        Event e;
        e.type = ContactType::kEdgeEdge;
        e.frame = f;
        e.a = c.edge_a;
        e.b = c.edge_b;
        tests.push_back(e);
      }
    }
    std::vector<unsigned char> hit(tests.size(), 0);
    std::atomic<std::size_t> excluded[2] = {{0}, {0}};
    tbb::parallel_for(std::size_t{0}, tests.size(), [&](std::size_t k) {
      Event& e = tests[k];
      if (e.kind == EventKind::kIntersection) {
        const char* reason = "";
        hit[k] = triangles_intersect_exactly(scene, e.a, e.b, x_f, &reason);
        return;
      }
      // Pairs certainly apart (verify_exclusion.hpp) cannot touch; every
      // other pair is decided by the exact CCD.
      if (certainly_apart(ccd_points(scene, e, x_f, *x_t1), e.type == ContactType::kEdgeEdge,
                          pair_thickness(scene, e, settings))) {
        ++excluded[e.type == ContactType::kEdgeEdge];
        return;
      }
      const ExactCcdResult exact = exact_ccd(scene, e, x_f, *x_t1, settings);
      hit[k] = exact.collides;
      e.toi_lo = exact.toi_lo;
      e.toi_hi = exact.toi_hi;
    });
    for (std::size_t k = 0; k < tests.size(); ++k) {
      const Event& e = tests[k];
      if (e.kind == EventKind::kIntersection) {
        ++result.triangle_pairs_tested;
      } else {
        ++(e.type == ContactType::kVertexFace ? result.vf_tested : result.ee_tested);
      }
      if (hit[k]) result.missed.push_back(e);
    }
    result.vf_excluded += excluded[0];
    result.ee_excluded += excluded[1];
    result.seconds_exhaustive += seconds_since(exhaustive_start);
  }
  std::sort(result.missed.begin(), result.missed.end(), event_order);
  result.frames_read = window.reads();
  return result;
}

}  // namespace snag::validate
