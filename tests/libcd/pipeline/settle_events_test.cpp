// settle_collision_events (event_builder.hpp), the host's part of collision
// events built on the device: against append_collision_events over the whole
// test's answers, the path of the CPU back end. The device's screen is
// modelled by its contract: what it decides equals the whole test, and any
// candidate may be left undecided (an event with certainty kUncertain and a
// meaningless toi), whatever the whole test then answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "libcd/pipeline/backend.hpp"
#include "libcd/pipeline/event_builder.hpp"
#include "tests/common/event_compare.hpp"
#include "tests/common/grid_object.hpp"

namespace snag {
namespace {

/// A cloth grid at rest and a body grid that sinks through it, tilted, so
/// that the step has vertex-face and edge-edge collisions.
struct Step {
  Scene scene{{test::grid_object("cloth", 6), test::grid_object("body", 5)}};
  std::vector<Vec3> x_t0, x_t1;
  Step() {
    for (int i = 0; i <= 5; ++i) {
      for (int j = 0; j <= 5; ++j) {
        const Vec3 p{i / 5.0, j / 5.0, 0.001 * std::sin(3.0 * i + j)};
        x_t0.push_back(p);
        x_t1.push_back(p);
      }
    }
    for (int i = 0; i <= 4; ++i) {
      for (int j = 0; j <= 4; ++j) {
        const double x = 0.05 + 0.9 * i / 4.0, y = 0.05 + 0.9 * j / 4.0;
        x_t0.push_back({x, y, 0.2});
        x_t1.push_back({x, y, -0.05 + 0.1 * x * y});
      }
    }
  }
};

/// Every vertex-face and edge-edge pair that shares no vertex.
struct AllCandidates {
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  explicit AllCandidates(const Scene& scene) {
    for (Index v = 0; v < scene.vertex_count(); ++v) {
      for (Index f = 0; f < scene.triangles().size(); ++f) {
        const Triangle& t = scene.triangles()[f];
        if (t[0] != v && t[1] != v && t[2] != v) vf.push_back({v, f});
      }
    }
    for (Index a = 0; a < scene.edges().size(); ++a) {
      for (Index b = a + 1; b < scene.edges().size(); ++b) {
        const Edge& p = scene.edges()[a];
        const Edge& q = scene.edges()[b];
        if (p[0] != q[0] && p[0] != q[1] && p[1] != q[0] && p[1] != q[1]) ee.push_back({a, b});
      }
    }
  }
};

/// The CPU back end's path: the whole test on every candidate, then
/// append_collision_events.
template <class Candidate>
void whole_test_events(const Step& step, const std::vector<Candidate>& candidates, const CcdSettings& settings,
                       const Certifier* certifier, NarrowPhaseStats& stats, std::vector<Event>& events) {
  CcdHits<Candidate> hits;
  for (const Candidate& c : candidates) {
    const CcdResult result = ccd_test(step.scene, step.x_t0, step.x_t1, c, settings);
    if (result.answer == CcdAnswer::kNo) continue;
    hits.candidates.push_back(c);
    hits.results.push_back(result);
  }
  append_collision_events(step.scene, step.x_t0, step.x_t1, candidates.size(), hits, certifier, settings.thickness,
                          stats, events);
}

/// What a screen may give for candidates [begin, end): the whole test's
/// event where it decides, an undecided event (toi [0, 1], kUncertain) for
/// one hit in two, one miss in three and everything the whole test leaves
/// uncertain.
Event screen_event(const Step& step, const VertexFaceCandidate& c, const CcdResult& result) {
  return vertex_face_event(step.scene, step.x_t0, step.x_t1, c, result);
}
Event screen_event(const Step& step, const EdgeEdgeCandidate& c, const CcdResult& result) {
  return edge_edge_event(step.scene, step.x_t0, step.x_t1, c, result);
}

template <class Candidate>
void screen_events(const Step& step, const std::vector<Candidate>& candidates, std::size_t begin, std::size_t end,
                   const CcdSettings& settings, std::vector<Event>& events) {
  const CcdResult undecided{CcdAnswer::kUncertain, 0.0, 1.0};
  for (std::size_t k = begin; k < end; ++k) {
    const CcdResult whole = ccd_test(step.scene, step.x_t0, step.x_t1, candidates[k], settings);
    const bool leave = whole.answer == CcdAnswer::kUncertain ||
                       (whole.answer == CcdAnswer::kYes ? k % 2 == 0 : k % 3 == 0);
    if (leave) {
      events.push_back(screen_event(step, candidates[k], undecided));
    } else if (whole.answer == CcdAnswer::kYes) {
      events.push_back(screen_event(step, candidates[k], whole));
    }
  }
}

/// A certifier that answers "collides, toi in [0.25, 0.5]".
class FixedCertifier final : public Certifier {
 public:
  ExactAnswer vertex_face(const std::array<Vec3, 8>&, double) const override { return {true, 0.25, 0.5}; }
  ExactAnswer edge_edge(const std::array<Vec3, 8>&, double) const override { return {true, 0.25, 0.5}; }
};

TEST(SettleCollisionEvents, GivesTheEventsAndCountsOfTheWholeTestWithAndWithoutACertifier) {
  const Step step;
  const AllCandidates candidates(step.scene);
  // Fewer (t, u, v) boxes than the default, so that the whole test leaves
  // some queries uncertain for the certifier.
  CcdSettings few_boxes;
  few_boxes.max_iterations = 8;
  const FixedCertifier certifier;
  for (const CcdSettings& settings : {CcdSettings{}, few_boxes}) {
    for (const Certifier* certify : {static_cast<const Certifier*>(nullptr), static_cast<const Certifier*>(&certifier)}) {
      NarrowPhaseStats want_stats;
      std::vector<Event> want;
      whole_test_events(step, candidates.vf, settings, certify, want_stats, want);
      whole_test_events(step, candidates.ee, settings, certify, want_stats, want);
      ASSERT_GT(want_stats.vf_yes, 0u);
      ASSERT_GT(want_stats.ee_yes, 0u);

      // As the device gives them: after an event of an earlier call, in two
      // chunks, each vertex-face then edge-edge.
      std::vector<Event> events(1);
      events[0].a = 7;
      const std::size_t vf_half = candidates.vf.size() / 2, ee_half = candidates.ee.size() / 2;
      screen_events(step, candidates.vf, 0, vf_half, settings, events);
      screen_events(step, candidates.ee, 0, ee_half, settings, events);
      screen_events(step, candidates.vf, vf_half, candidates.vf.size(), settings, events);
      screen_events(step, candidates.ee, ee_half, candidates.ee.size(), settings, events);
      const std::size_t undecided = static_cast<std::size_t>(std::count_if(
          events.begin() + 1, events.end(), [](const Event& e) { return e.certainty == Certainty::kUncertain; }));
      NarrowPhaseStats stats;
      EXPECT_EQ(settle_collision_events(step.scene, step.x_t0, step.x_t1, candidates.vf.size(), candidates.ee.size(),
                                        settings, certify, stats, events, 1),
                undecided);
      EXPECT_EQ(events[0].a, 7u) << "events before `first` are left alone";
      events.erase(events.begin());
      sort_events_from(events, 0);
      test::expect_same_events(want, events, "settled");
      test::expect_same_counts(want_stats, stats, "settled");
      if (settings.max_iterations == few_boxes.max_iterations) {
        EXPECT_GT(want_stats.vf_uncertain + want_stats.ee_uncertain, 0u) << "the certifier must be asked";
      }
    }
  }
}

TEST(SettleCollisionEvents, LeavesDecidedEventsAsTheyAre) {
  const Step step;
  std::vector<Event> events;
  NarrowPhaseStats stats;
  EXPECT_EQ(settle_collision_events(step.scene, step.x_t0, step.x_t1, 10, 5, CcdSettings{}, nullptr, stats, events, 0),
            0u);
  EXPECT_TRUE(events.empty());
  EXPECT_EQ(stats.vf_no, 10u);
  EXPECT_EQ(stats.ee_no, 5u);
}

// The passes over a step's events run on all threads, in tasks of thousands
// of events: in a long list each event is settled in place as it is alone,
// and the list keeps its order.
TEST(SettleCollisionEvents, LongListsAreSettledInPlaceAsTheirEventsAlone) {
  const Step step;
  const AllCandidates candidates(step.scene);
  std::vector<Event> screened;
  screen_events(step, candidates.vf, 0, candidates.vf.size(), CcdSettings{}, screened);
  screen_events(step, candidates.ee, 0, candidates.ee.size(), CcdSettings{}, screened);
  const auto decided = std::find_if(screened.begin(), screened.end(),
                                    [](const Event& e) { return e.certainty == Certainty::kProven; });
  ASSERT_NE(decided, screened.end());
  constexpr std::size_t kBetween = 3001;  // decided events before each screened one
  std::vector<Event> events, want;
  std::size_t undecided = 0, vf = 0, ee = 0;
  for (const Event& e : screened) {
    events.insert(events.end(), kBetween, *decided);
    want.insert(want.end(), kBetween, *decided);
    events.push_back(e);
    std::vector<Event> alone{e};
    NarrowPhaseStats alone_stats;
    undecided += settle_collision_events(step.scene, step.x_t0, step.x_t1, 1, 1, CcdSettings{}, nullptr, alone_stats,
                                         alone, 0);
    want.insert(want.end(), alone.begin(), alone.end());
  }
  for (const Event& e : events) (e.type == ContactType::kVertexFace ? vf : ee) += 1;
  ASSERT_GT(undecided, 2u);
  ASSERT_GT(events.size(), 20000u);
  ASSERT_LT(want.size(), events.size()) << "the search must rule some out, so that the events after them move down";
  NarrowPhaseStats stats;
  EXPECT_EQ(settle_collision_events(step.scene, step.x_t0, step.x_t1, vf, ee, CcdSettings{}, nullptr, stats, events, 0),
            undecided);
  test::expect_same_events(want, events, "long list");
}

// Events with distinct keys, in event order.
std::vector<Event> ordered_events(std::size_t count) {
  std::vector<Event> events(count);
  for (std::size_t i = 0; i < count; ++i) {
    events[i].a = static_cast<Index>(i / 7);
    events[i].b = static_cast<Index>(i % 7);
    events[i].toi_lo = static_cast<double>(i);
  }
  return events;
}

TEST(SortEventsFrom, FindsOneStepOutOfOrderAnywhereInALongList) {
  const std::vector<Event> sorted = ordered_events(50000);
  for (std::size_t at : {std::size_t{1}, std::size_t{8192}, std::size_t{8193}, std::size_t{31111}, std::size_t{49999}}) {
    std::vector<Event> events = sorted;
    std::swap(events[at - 1], events[at]);
    sort_events_from(events, 0);
    test::expect_same_events(sorted, events, "swapped at " + std::to_string(at));
  }
  std::vector<Event> events = sorted;
  sort_events_from(events, 0);
  test::expect_same_events(sorted, events, "already sorted");
  // Only events [first, end) are ordered.
  events = sorted;
  std::swap(events[0], events[1]);
  std::swap(events[40000], events[40001]);
  sort_events_from(events, 2);
  EXPECT_EQ(events[0].toi_lo, 1.0);
  EXPECT_EQ(events[1].toi_lo, 0.0);
  EXPECT_EQ(events[40000].toi_lo, 40000.0);
}

// A step found in chunks: each chunk's events in order, the chunks one after
// the other. The runs are merged into event order, events before `first`
// left alone; with more runs than are worth merging, the events are sorted.
TEST(SortEventsFrom, MergesTheSortedRunsOfChunks) {
  const std::vector<Event> sorted = ordered_events(120000);
  for (std::size_t runs : {std::size_t{2}, std::size_t{21}, std::size_t{50}, std::size_t{5000}}) {
    std::mt19937_64 rng(runs);
    std::vector<std::vector<Event>> chunks(runs);
    for (const Event& e : sorted) chunks[rng() % runs].push_back(e);  // each chunk stays in order
    std::vector<Event> events = ordered_events(3);
    events[0].toi_lo = 7;  // before `first`: not moved
    for (const auto& chunk : chunks) events.insert(events.end(), chunk.begin(), chunk.end());
    sort_events_from(events, 3);
    EXPECT_EQ(events[0].toi_lo, 7.0);
    events.erase(events.begin(), events.begin() + 3);
    test::expect_same_events(sorted, events, std::to_string(runs) + " runs");
  }
  // Reversed: every event starts a run.
  std::vector<Event> events(sorted.rbegin(), sorted.rend());
  sort_events_from(events, 0);
  test::expect_same_events(sorted, events, "reversed");
  // Two runs, one of a single event, at either end.
  events = sorted;
  std::rotate(events.begin(), events.begin() + 1, events.end());
  sort_events_from(events, 0);
  test::expect_same_events(sorted, events, "first event last");
  events = sorted;
  std::rotate(events.rbegin(), events.rbegin() + 1, events.rend());
  sort_events_from(events, 0);
  test::expect_same_events(sorted, events, "last event first");
}

TEST(AppendEvents, CopiesALongListAfterWhatIsThere) {
  const std::vector<Event> more = ordered_events(70000);
  std::vector<Event> events = ordered_events(3), want = events;
  want.insert(want.end(), more.begin(), more.end());
  append_events(events, more.data(), more.size());
  test::expect_same_events(want, events, "appended");
  append_events(events, nullptr, 0);
  EXPECT_EQ(events.size(), want.size());
}

}  // namespace
}  // namespace snag
