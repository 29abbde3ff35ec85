// The GPU narrow phase (libcd/cuda/narrow_phase.cuh; plain C++ here, so the
// CPU oracles are compiled by the host compiler) against the CPU
// functions it runs: every query of the exact ground-truth sets
// (../shared/data/ccd-queries) in one batch per kind, with both schedules
// (screen then search, single pass): no false negatives, and each hit and its
// time of impact bit-identical to vertex_face_ccd / edge_edge_ccd on the CPU;
// and random triangle pairs against triangles_intersect, predicate counts included.
// Events built on the device are bit-identical to those the host builds of
// the same hits with the same formulas (event_fields.hpp).
#include "libcd/cuda/narrow_phase.cuh"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "gpu_test.hpp"
#include "io/ccd_query_csv.hpp"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/triangle_triangle.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "libcd/pipeline/event.hpp"
#include "libcd/pipeline/event_fields.hpp"
#include "tests/common/event_compare.hpp"

namespace snag {
namespace {

using test::same_bits;

/// The queries laid out as a scene: 4 vertices per query; VF: vertex 4q
/// against face q = (4q+1, 4q+2, 4q+3); EE: edge 2q = (4q, 4q+1) against edge
/// 2q+1 = (4q+2, 4q+3).
struct QueryBatch {
  std::vector<Vec3> x_t0, x_t1;
  std::vector<Triangle> triangles;
  std::vector<Edge> edges;
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  std::vector<const io::CcdQuery*> vf_queries, ee_queries;
};

QueryBatch make_batch(const std::vector<io::CcdQuery>& queries) {
  QueryBatch batch;
  for (const io::CcdQuery& query : queries) {
    const Index base = static_cast<Index>(batch.x_t0.size());
    for (int i = 0; i < 4; ++i) {
      batch.x_t0.push_back(query.points[i]);
      batch.x_t1.push_back(query.points[4 + i]);
    }
    if (query.is_edge_edge) {
      const Index e = static_cast<Index>(batch.edges.size());
      batch.edges.push_back({base, base + 1});
      batch.edges.push_back({base + 2, base + 3});
      batch.ee.push_back({e, e + 1});
      batch.ee_queries.push_back(&query);
    } else {
      const Index f = static_cast<Index>(batch.triangles.size());
      batch.triangles.push_back({base + 1, base + 2, base + 3});
      batch.vf.push_back({base, f});
      batch.vf_queries.push_back(&query);
    }
  }
  return batch;
}

/// A QueryBatch uploaded to the device.
struct DeviceBatch {
  explicit DeviceBatch(const QueryBatch& batch) {
    x_t0.upload(batch.x_t0);
    x_t1.upload(batch.x_t1);
    triangles.upload(batch.triangles);
    edges.upload(batch.edges);
    vf.upload(batch.vf);
    ee.upload(batch.ee);
  }
  DeviceBuffer<Vec3> x_t0, x_t1;
  DeviceBuffer<Triangle> triangles;
  DeviceBuffer<Edge> edges;
  DeviceBuffer<VertexFaceCandidate> vf;
  DeviceBuffer<EdgeEdgeCandidate> ee;

  /// The vertex-face and edge-edge hits of every candidate of the batch
  /// (and, when asked, their candidates).
  void find_hits(CudaNarrowPhase& narrow, const CcdSettings& settings, CcdPasses passes, std::vector<CcdHit>& vf_hits,
                 std::vector<CcdHit>& ee_hits, std::vector<VertexFaceCandidate>* vf_candidates = nullptr,
                 std::vector<EdgeEdgeCandidate>* ee_candidates = nullptr) const {
    narrow.vertex_face(x_t0.data(), x_t1.data(), triangles.data(), vf.data(), vf.size(), settings, passes, vf_hits,
                       vf_candidates);
    narrow.edge_edge(x_t0.data(), x_t1.data(), edges.data(), ee.data(), ee.size(), settings, passes, ee_hits,
                     ee_candidates);
  }
};

CcdResult cpu_answer(const io::CcdQuery& q, const CcdSettings& settings) {
  const auto& p = q.points;
  return q.is_edge_edge ? edge_edge_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings)
                        : vertex_face_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings);
}

void expect_same_as_cpu(const std::vector<const io::CcdQuery*>& queries, const std::vector<CcdHit>& hits,
                        const CcdSettings& settings, const char* schedule) {
  std::size_t next_hit = 0, false_negatives = 0, cpu_hits = 0;
  for (std::size_t q = 0; q < queries.size(); ++q) {
    const CcdResult cpu = cpu_answer(*queries[q], settings);
    const bool gpu_hit = next_hit < hits.size() && hits[next_hit].candidate == q;
    if (queries[q]->truth && !gpu_hit) ++false_negatives;
    if (cpu.answer == CcdAnswer::kNo) {
      EXPECT_FALSE(gpu_hit) << schedule << ": " << queries[q]->file << ":" << queries[q]->line;
      if (gpu_hit) ++next_hit;
      continue;
    }
    ++cpu_hits;
    ASSERT_TRUE(gpu_hit) << schedule << ": missed " << queries[q]->file << ":" << queries[q]->line;
    const CcdResult gpu = hits[next_hit++].result;
    EXPECT_EQ(gpu.answer, cpu.answer) << schedule << ": " << queries[q]->file << ":" << queries[q]->line;
    EXPECT_TRUE(same_bits(gpu.toi_lo, cpu.toi_lo) && same_bits(gpu.toi_hi, cpu.toi_hi))
        << schedule << ": " << queries[q]->file << ":" << queries[q]->line << " gpu [" << gpu.toi_lo << ", "
        << gpu.toi_hi << "] cpu [" << cpu.toi_lo << ", " << cpu.toi_hi << "]";
  }
  EXPECT_EQ(next_hit, hits.size()) << schedule << ": hits out of candidate order";
  EXPECT_EQ(cpu_hits, hits.size()) << schedule;
  EXPECT_EQ(false_negatives, 0u) << schedule;
}

class NarrowPhaseCcdQueries : public test::GpuTest {};

TEST_F(NarrowPhaseCcdQueries, MatchesCpuWithNoFalseNegativesOnAllQueries) {
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(test::shared_data_dir() + "/ccd-queries");
  ASSERT_GT(queries.size(), 1000u);
  const QueryBatch batch = make_batch(queries);
  ASSERT_FALSE(batch.vf.empty());
  ASSERT_FALSE(batch.ee.empty());
  std::size_t positives = 0;
  for (const auto& q : queries) positives += q.truth;
  ASSERT_GT(positives, 0u);

  const DeviceBatch device(batch);
  CudaNarrowPhase narrow(nullptr);
  CcdSettings settings;
  for (const CcdPasses passes : {CcdPasses::kScreenThenSearch, CcdPasses::kSinglePass}) {
    const char* schedule = passes == CcdPasses::kSinglePass ? "single pass" : "screen then search";
    std::vector<CcdHit> vf_hits, ee_hits;
    device.find_hits(narrow, settings, passes, vf_hits, ee_hits);
    expect_same_as_cpu(batch.vf_queries, vf_hits, settings, schedule);
    expect_same_as_cpu(batch.ee_queries, ee_hits, settings, schedule);
  }
}

TEST_F(NarrowPhaseCcdQueries, RoundsOfAnySizeGiveTheSameHitsAndTheirCandidates) {
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(test::shared_data_dir() + "/ccd-queries");
  const QueryBatch batch = make_batch(queries);
  ASSERT_GT(batch.vf.size(), 1000u);
  const DeviceBatch device(batch);
  CudaNarrowPhase narrow(nullptr);
  narrow.set_chunk_size(97);  // many rounds, the last one partial
  std::vector<CcdHit> vf_hits, ee_hits;
  std::vector<VertexFaceCandidate> vf_candidates;
  std::vector<EdgeEdgeCandidate> ee_candidates;
  device.find_hits(narrow, CcdSettings{}, CcdPasses::kScreenThenSearch, vf_hits, ee_hits, &vf_candidates,
                   &ee_candidates);
  expect_same_as_cpu(batch.vf_queries, vf_hits, CcdSettings{}, "rounds of 97");
  expect_same_as_cpu(batch.ee_queries, ee_hits, CcdSettings{}, "rounds of 97");
  ASSERT_EQ(vf_candidates.size(), vf_hits.size());
  ASSERT_EQ(ee_candidates.size(), ee_hits.size());
  for (std::size_t k = 0; k < vf_hits.size(); ++k) EXPECT_TRUE(vf_candidates[k] == batch.vf[vf_hits[k].candidate]);
  for (std::size_t k = 0; k < ee_hits.size(); ++k) EXPECT_TRUE(ee_candidates[k] == batch.ee[ee_hits[k].candidate]);
}

TEST_F(NarrowPhaseCcdQueries, LanesTakingQueriesInTurnGiveTheSameHits) {
  // One block of 128 lanes runs the time search of every query the early
  // exits leave: each lane takes a new query whenever its search ends, many
  // times over, and hands over the intervals it isolates.
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(test::shared_data_dir() + "/ccd-queries");
  const QueryBatch batch = make_batch(queries);
  ASSERT_GT(batch.vf.size(), 10u * 128u);
  ASSERT_GT(batch.ee.size(), 10u * 128u);
  const DeviceBatch device(batch);
  CudaNarrowPhase narrow(nullptr);
  narrow.set_quick_block_limit(1);
  std::vector<CcdHit> vf_hits, ee_hits;
  device.find_hits(narrow, CcdSettings{}, CcdPasses::kScreenThenSearch, vf_hits, ee_hits);
  expect_same_as_cpu(batch.vf_queries, vf_hits, CcdSettings{}, "one block of lanes");
  expect_same_as_cpu(batch.ee_queries, ee_hits, CcdSettings{}, "one block of lanes");
}

/// Runs the CPU's whole test on the hits a screen left undecided (kUncertain)
/// and drops those it rules out; returns how many there were.
std::size_t finish_on_cpu(const std::vector<const io::CcdQuery*>& queries, const CcdSettings& settings,
                          std::vector<CcdHit>& hits) {
  std::size_t undecided = 0;
  std::vector<CcdHit> kept;
  for (CcdHit hit : hits) {
    if (hit.result.answer == CcdAnswer::kUncertain) {
      ++undecided;
      hit.result = cpu_answer(*queries[hit.candidate], settings);
    }
    if (hit.result.answer != CcdAnswer::kNo) kept.push_back(hit);
  }
  hits = kept;
  return undecided;
}

TEST_F(NarrowPhaseCcdQueries, ScreenOnlyLeavesTheUndecidedToTheCaller) {
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(test::shared_data_dir() + "/ccd-queries");
  const QueryBatch batch = make_batch(queries);
  const DeviceBatch device(batch);
  CudaNarrowPhase narrow(nullptr);
  const CcdSettings settings;
  std::vector<CcdHit> vf_hits, ee_hits;
  device.find_hits(narrow, settings, CcdPasses::kScreenOnly, vf_hits, ee_hits);
  const std::size_t undecided =
      finish_on_cpu(batch.vf_queries, settings, vf_hits) + finish_on_cpu(batch.ee_queries, settings, ee_hits);
  EXPECT_GT(undecided, 0u) << "the hard queries must leave some undecided";
  expect_same_as_cpu(batch.vf_queries, vf_hits, settings, "screen only");
  expect_same_as_cpu(batch.ee_queries, ee_hits, settings, "screen only");
}

/// Whether the host's CCD early exits decide a query (the range check included).
bool early_exits_decide(const io::CcdQuery& q, const CcdSettings& settings) {
  const auto& p = q.points;
  CcdResult result;
  return q.is_edge_edge ? edge_edge_early_exit(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings, &result)
                        : vertex_face_early_exit(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings, &result);
}

/// The CCD queries whose early exits (the host's) decide nothing.
std::vector<io::CcdQuery> queries_the_early_exits_leave(const std::vector<io::CcdQuery>& queries,
                                                        const CcdSettings& settings) {
  std::vector<io::CcdQuery> left;
  for (const io::CcdQuery& q : queries)
    if (!early_exits_decide(q, settings)) left.push_back(q);
  return left;
}

// kQuickAfterEarlyExits on the candidates the early exits leave (the
// feature stage's screen hands on those): the hits of kScreenOnly, answers
// and times bit for bit, an out-of-range query's kUncertain included.
TEST_F(NarrowPhaseCcdQueries, QuickAfterEarlyExitsIsTheScreenOnWhatTheyLeave) {
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(test::shared_data_dir() + "/ccd-queries");
  const CcdSettings settings;
  std::vector<io::CcdQuery> left = queries_the_early_exits_leave(queries, settings);
  ASSERT_GT(left.size(), 100u);
  ASSERT_LT(left.size(), queries.size());
  for (const bool edge_edge : {false, true}) {  // one of each kind out of range
    io::CcdQuery far = *std::find_if(left.begin(), left.end(),
                                     [&](const io::CcdQuery& q) { return q.is_edge_edge == edge_edge; });
    far.points[5].y = 1e61;
    ASSERT_TRUE(early_exits_decide(far, settings));
    left.push_back(far);
  }
  const QueryBatch batch = make_batch(left);
  const DeviceBatch device(batch);
  CudaNarrowPhase narrow(nullptr);
  std::vector<CcdHit> vf_screen, ee_screen, vf_quick, ee_quick;
  device.find_hits(narrow, settings, CcdPasses::kScreenOnly, vf_screen, ee_screen);
  device.find_hits(narrow, settings, CcdPasses::kQuickAfterEarlyExits, vf_quick, ee_quick);
  for (const auto& [screen, quick, kind] : {std::tuple{&vf_screen, &vf_quick, "vertex-face"},
                                            std::tuple{&ee_screen, &ee_quick, "edge-edge"}}) {
    ASSERT_EQ(quick->size(), screen->size()) << kind;
    ASSERT_GT(screen->size(), 1u) << kind;
    for (std::size_t k = 0; k < screen->size(); ++k) {
      const CcdHit &a = (*screen)[k], &b = (*quick)[k];
      EXPECT_EQ(b.candidate, a.candidate) << kind;
      EXPECT_EQ(b.result.answer, a.result.answer) << kind << " hit " << k;
      EXPECT_TRUE(same_bits(b.result.toi_lo, a.result.toi_lo) && same_bits(b.result.toi_hi, a.result.toi_hi))
          << kind << " hit " << k;
    }
    // The out-of-range query is the last candidate of its kind: kUncertain over the step.
    EXPECT_EQ(quick->back().result.answer, CcdAnswer::kUncertain) << kind;
    EXPECT_EQ(quick->back().result.toi_lo, 0.0) << kind;
    EXPECT_EQ(quick->back().result.toi_hi, 1.0) << kind;
  }
}

// The time search's isolated queries take the room the round leaves: with a
// round's room for many more candidates than it has (the default chunk size),
// it searches them in one launch once the last round's survivors sized the
// first; in rounds of a budget just their size, in slices of the room of the
// hits' events (a third of the candidates). Both give the CPU's answers.
TEST_F(NarrowPhaseCcdQueries, TimeSearchTakesTheRoomTheRoundLeaves) {
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(test::shared_data_dir() + "/ccd-queries");
  const CcdSettings settings;
  const std::vector<io::CcdQuery> left = queries_the_early_exits_leave(queries, settings);
  const QueryBatch batch = make_batch(left);  // points into `left`
  ASSERT_GT(std::min(batch.vf.size(), batch.ee.size()), 100u);
  const DeviceBatch device(batch);
  for (const bool tight : {false, true}) {
    const char* schedule = tight ? "rounds of a tight budget" : "a roomy round";
    CudaNarrowPhase narrow(nullptr);
    if (tight) narrow.set_chunk_size(std::min(batch.vf.size(), batch.ee.size()));
    std::vector<CcdHit> vf_first, ee_first, vf_hits, ee_hits;
    device.find_hits(narrow, settings, CcdPasses::kQuickAfterEarlyExits, vf_first, ee_first);
    narrow.reset_timings();
    device.find_hits(narrow, settings, CcdPasses::kQuickAfterEarlyExits, vf_hits, ee_hits);
    const NarrowPhaseTimings& timings = narrow.timings();
    if (tight) {
      EXPECT_GE(timings.time_searches, timings.rounds + 2) << schedule;  // 3 in the round its candidates fill
    } else {
      EXPECT_EQ(timings.rounds, 2u) << schedule;
      EXPECT_EQ(timings.time_searches, 2u) << schedule;
    }
    finish_on_cpu(batch.vf_queries, settings, vf_hits);
    finish_on_cpu(batch.ee_queries, settings, ee_hits);
    expect_same_as_cpu(batch.vf_queries, vf_hits, settings, schedule);
    expect_same_as_cpu(batch.ee_queries, ee_hits, settings, schedule);
  }
}

TEST_F(NarrowPhaseCcdQueries, MatchesCpuWithThickness) {
  const std::vector<io::CcdQuery> queries =
      io::read_ccd_query_tree(test::shared_data_dir() + "/ccd-queries/unit-tests");
  ASSERT_FALSE(queries.empty());
  const QueryBatch batch = make_batch(queries);
  const DeviceBatch device(batch);
  CudaNarrowPhase narrow(nullptr);
  CcdSettings settings;
  settings.thickness = 1e-3;
  std::vector<CcdHit> vf_hits, ee_hits;
  device.find_hits(narrow, settings, CcdPasses::kScreenThenSearch, vf_hits, ee_hits);
  expect_same_as_cpu(batch.vf_queries, vf_hits, settings, "thickness 1e-3");
  expect_same_as_cpu(batch.ee_queries, ee_hits, settings, "thickness 1e-3");
}

/// The event the host builds of a candidate of the batch with this answer.
Event host_event(const QueryBatch& batch, const VertexFaceCandidate& c, const CcdResult& result) {
  return vertex_face_fields(c.vertex, c.face, batch.x_t0[c.vertex], batch.x_t1[c.vertex], result);
}
Event host_event(const QueryBatch& batch, const EdgeEdgeCandidate& c, const CcdResult& result) {
  const Edge& a = batch.edges[c.edge_a];
  const Edge& b = batch.edges[c.edge_b];
  const Vec3 ends_t0[4] = {batch.x_t0[a[0]], batch.x_t0[a[1]], batch.x_t0[b[0]], batch.x_t0[b[1]]};
  const Vec3 ends_t1[4] = {batch.x_t1[a[0]], batch.x_t1[a[1]], batch.x_t1[b[0]], batch.x_t1[b[1]]};
  return edge_edge_fields(c.edge_a, c.edge_b, ends_t0, ends_t1, result);
}

TEST_F(NarrowPhaseCcdQueries, EventsBuiltOnTheDeviceAreTheHostsOfTheSameHits) {
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(test::shared_data_dir() + "/ccd-queries");
  const QueryBatch batch = make_batch(queries);
  const DeviceBatch device(batch);
  CudaNarrowPhase narrow(nullptr);
  const CcdSettings settings;
  // Many rounds, the last one partial; in rounds of 11 the events of a
  // round with more than 4 hits are built in several slices.
  for (const auto& [chunk, passes] : {std::pair{97, CcdPasses::kScreenOnly}, std::pair{97, CcdPasses::kSinglePass},
                                      std::pair{11, CcdPasses::kScreenOnly}}) {
    narrow.set_chunk_size(chunk);
    std::vector<CcdHit> vf_hits, ee_hits;
    std::vector<Event> events;
    device.find_hits(narrow, settings, passes, vf_hits, ee_hits);
    narrow.vertex_face_events(device.x_t0.data(), device.x_t1.data(), device.triangles.data(), device.vf.data(),
                              batch.vf.size(), settings, passes, events);
    narrow.edge_edge_events(device.x_t0.data(), device.x_t1.data(), device.edges.data(), device.ee.data(),
                            batch.ee.size(), settings, passes, events);
    ASSERT_GT(vf_hits.size(), 0u);
    ASSERT_GT(ee_hits.size(), 0u);
    ASSERT_EQ(events.size(), vf_hits.size() + ee_hits.size());
    std::vector<Event> host;
    for (const CcdHit& hit : vf_hits) host.push_back(host_event(batch, batch.vf[hit.candidate], hit.result));
    for (const CcdHit& hit : ee_hits) host.push_back(host_event(batch, batch.ee[hit.candidate], hit.result));
    test::expect_same_events(host, events, std::string(passes == CcdPasses::kScreenOnly ? "screen only" : "single pass") +
                                               ", rounds of " + std::to_string(chunk));
    const auto uncertain = std::count_if(host.begin(), host.end(),
                                         [](const Event& e) { return e.certainty == Certainty::kUncertain; });
    if (passes == CcdPasses::kScreenOnly) EXPECT_GT(uncertain, 0u) << "the screen leaves the hard queries undecided";
  }
  std::vector<Event> events;
  EXPECT_THROW(narrow.vertex_face_events(device.x_t0.data(), device.x_t1.data(), device.triangles.data(),
                                         device.vf.data(), batch.vf.size(), settings, CcdPasses::kScreenThenSearch,
                                         events),
               std::invalid_argument);
}

/// The bits a radix sort needs for ids up to max_id (at least 1).
int id_bits(std::size_t max_id) {
  int bits = 1;
  while (bits < 64 && (max_id >> bits) != 0) ++bits;
  return bits;
}

/// The hits' events of candidates[k] as the host builds them, round by round
/// (`round` candidates each) and each round's sorted in event order.
template <class Candidate>
std::vector<Event> events_in_round_order(const QueryBatch& batch, const std::vector<Candidate>& candidates,
                                         const std::vector<CcdHit>& hits, std::size_t round) {
  std::vector<Event> events;
  std::size_t begin = 0;
  for (std::size_t k = 0; k <= hits.size(); ++k) {
    if (k == hits.size() || hits[k].candidate / round != hits[begin].candidate / round) {
      std::sort(events.begin() + static_cast<std::ptrdiff_t>(begin), events.end(), event_order);
      begin = k;
    }
    if (k < hits.size()) events.push_back(host_event(batch, candidates[hits[k].candidate], hits[k].result));
  }
  return events;
}

// set_event_order: each round's events come in event order, whatever the
// candidates' order (the broad phase's unsorted ones): the candidates
// shuffled, in one round and in rounds of 97, against the host's events of
// the same hits sorted round by round; without it, in candidate order.
TEST_F(NarrowPhaseCcdQueries, EventOrderSortsEachRoundsEventsWhateverTheCandidatesOrder) {
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(test::shared_data_dir() + "/ccd-queries");
  QueryBatch batch = make_batch(queries);
  std::mt19937 rng(14);
  std::shuffle(batch.vf.begin(), batch.vf.end(), rng);
  std::shuffle(batch.ee.begin(), batch.ee.end(), rng);
  const DeviceBatch device(batch);
  const CcdSettings settings;
  const int face_bits = id_bits(batch.triangles.size() - 1), edge_bits = id_bits(batch.edges.size() - 1);
  for (const std::size_t round : {batch.vf.size() + batch.ee.size(), std::size_t{97}}) {
    CudaNarrowPhase narrow(nullptr);
    narrow.set_chunk_size(round);
    std::vector<CcdHit> vf_hits, ee_hits;
    device.find_hits(narrow, settings, CcdPasses::kScreenOnly, vf_hits, ee_hits);
    ASSERT_GT(vf_hits.size(), 1u);
    ASSERT_GT(ee_hits.size(), 1u);
    std::vector<Event> vf_events, ee_events, vf_plain, ee_plain;
    narrow.set_event_order(face_bits, id_bits(batch.x_t0.size() - 1) + face_bits);
    narrow.vertex_face_events(device.x_t0.data(), device.x_t1.data(), device.triangles.data(), device.vf.data(),
                              batch.vf.size(), settings, CcdPasses::kScreenOnly, vf_events);
    narrow.set_event_order(edge_bits, 2 * edge_bits);
    narrow.edge_edge_events(device.x_t0.data(), device.x_t1.data(), device.edges.data(), device.ee.data(),
                            batch.ee.size(), settings, CcdPasses::kScreenOnly, ee_events);
    const std::string where = "rounds of " + std::to_string(round);
    test::expect_same_events(events_in_round_order(batch, batch.vf, vf_hits, round), vf_events,
                             where + ", vertex-face");
    test::expect_same_events(events_in_round_order(batch, batch.ee, ee_hits, round), ee_events, where + ", edge-edge");
    EXPECT_FALSE(std::is_sorted(vf_hits.begin(), vf_hits.end(),
                                [&](const CcdHit& x, const CcdHit& y) {
                                  return event_order(host_event(batch, batch.vf[x.candidate], x.result),
                                                     host_event(batch, batch.vf[y.candidate], y.result));
                                }))
        << where << ": the shuffled candidates' hits must come out of event order";
    narrow.set_event_order(0, 0);
    narrow.vertex_face_events(device.x_t0.data(), device.x_t1.data(), device.triangles.data(), device.vf.data(),
                              batch.vf.size(), settings, CcdPasses::kScreenOnly, vf_plain);
    std::vector<Event> in_candidate_order;
    for (const CcdHit& hit : vf_hits)
      in_candidate_order.push_back(host_event(batch, batch.vf[hit.candidate], hit.result));
    test::expect_same_events(in_candidate_order, vf_plain, where + ", vertex-face without event order");
  }
}

// Deferred events: a call leaves its last round's events staged until
// flush_events(), or until the next call, which appends them first; the
// order is that of appending at once; drop_events() forgets them.
TEST_F(NarrowPhaseCcdQueries, DeferredEventsComeInTheOrderOfAppendingAtOnce) {
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(test::shared_data_dir() + "/ccd-queries");
  const QueryBatch batch = make_batch(queries);
  const DeviceBatch device(batch);
  const CcdSettings settings;
  auto vertex_face = [&](CudaNarrowPhase& narrow, std::vector<Event>& events) {
    narrow.vertex_face_events(device.x_t0.data(), device.x_t1.data(), device.triangles.data(), device.vf.data(),
                              batch.vf.size(), settings, CcdPasses::kScreenOnly, events);
  };
  auto edge_edge = [&](CudaNarrowPhase& narrow, std::vector<Event>& events) {
    narrow.edge_edge_events(device.x_t0.data(), device.x_t1.data(), device.edges.data(), device.ee.data(),
                            batch.ee.size(), settings, CcdPasses::kScreenOnly, events);
  };
  for (const std::size_t chunk : {std::size_t{97}, CudaNarrowPhase::kDefaultChunkSize}) {
    const std::string where = "rounds of " + std::to_string(chunk);
    CudaNarrowPhase at_once(nullptr), deferred(nullptr);
    at_once.set_chunk_size(chunk);
    deferred.set_chunk_size(chunk);
    deferred.set_defer_events(true);
    std::vector<Event> expected;
    vertex_face(at_once, expected);
    const std::size_t vf_events = expected.size();
    edge_edge(at_once, expected);
    ASSERT_GT(vf_events, 0u) << where;
    ASSERT_GT(expected.size(), vf_events) << where;

    std::vector<Event> events;
    vertex_face(deferred, events);
    // Earlier rounds are appended when the next one starts; the last waits.
    const bool one_round = chunk >= batch.vf.size() && chunk >= batch.ee.size();
    if (one_round) EXPECT_EQ(events.size(), 0u) << where;
    EXPECT_LE(events.size(), vf_events) << where;
    edge_edge(deferred, events);  // appends the vertex-face events first
    if (one_round) EXPECT_EQ(events.size(), vf_events) << where;
    EXPECT_GE(events.size(), vf_events) << where;
    EXPECT_LE(events.size(), expected.size()) << where;
    deferred.flush_events();
    test::expect_same_events(expected, events, where);
    deferred.flush_events();  // nothing left
    EXPECT_EQ(events.size(), expected.size()) << where;

    // Dropped events are not appended, by a flush or by the next call.
    std::vector<Event> dropped;
    vertex_face(deferred, dropped);
    const std::size_t kept = dropped.size();
    deferred.drop_events();
    deferred.flush_events();
    EXPECT_EQ(dropped.size(), kept) << where;
    std::vector<Event> again;
    edge_edge(deferred, again);
    deferred.flush_events();
    EXPECT_EQ(dropped.size(), kept) << where;
    EXPECT_EQ(again.size(), expected.size() - vf_events) << where;
  }
}

// As the back end runs them: a vertex-face and an edge-edge narrow phase
// append to one list, each flushing both's deferred events while its first
// round runs, and the appends go to a thread of their own; in many rounds,
// so that each round's pinned buffer alternates and waits for that thread.
TEST_F(NarrowPhaseCcdQueries, DeferredEventsCopiedOnAThreadComeInTheOrderOfAppendingAtOnce) {
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(test::shared_data_dir() + "/ccd-queries");
  const QueryBatch batch = make_batch(queries);
  const DeviceBatch device(batch);
  const CcdSettings settings;
  for (const std::size_t chunk : {std::size_t{97}, CudaNarrowPhase::kDefaultChunkSize}) {
    const std::string where = "rounds of " + std::to_string(chunk);
    CudaNarrowPhase at_once(nullptr), vertex_face(nullptr), edge_edge(nullptr);
    TaskQueueThread copies;
    for (CudaNarrowPhase* narrow : {&at_once, &vertex_face, &edge_edge}) narrow->set_chunk_size(chunk);
    for (CudaNarrowPhase* narrow : {&vertex_face, &edge_edge}) {
      narrow->set_defer_events(true);
      narrow->set_event_copies(&copies);
    }
    const std::function<void()> flush_both = [&] {
      vertex_face.flush_events();
      edge_edge.flush_events();
    };
    std::vector<Event> expected, events;
    for (int step = 0; step < 3; ++step) {  // as chunks of a step
      at_once.vertex_face_events(device.x_t0.data(), device.x_t1.data(), device.triangles.data(), device.vf.data(),
                                 batch.vf.size(), settings, CcdPasses::kScreenOnly, expected);
      at_once.edge_edge_events(device.x_t0.data(), device.x_t1.data(), device.edges.data(), device.ee.data(),
                               batch.ee.size(), settings, CcdPasses::kScreenOnly, expected);
      vertex_face.vertex_face_events(device.x_t0.data(), device.x_t1.data(), device.triangles.data(), device.vf.data(),
                                     batch.vf.size(), settings, CcdPasses::kScreenOnly, events, flush_both);
      edge_edge.edge_edge_events(device.x_t0.data(), device.x_t1.data(), device.edges.data(), device.ee.data(),
                                 batch.ee.size(), settings, CcdPasses::kScreenOnly, events, flush_both);
    }
    flush_both();
    copies.wait();
    ASSERT_GT(expected.size(), 0u) << where;
    test::expect_same_events(expected, events, where);
  }
}

class NarrowPhaseTrianglePairs : public test::GpuTest {};

TEST_F(NarrowPhaseTrianglePairs, MatchesCpuOnRandomPairsWithSharedVertices) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> coordinate(0, 1);
  std::vector<Vec3> x(300);
  for (Vec3& p : x) p = {coordinate(random), coordinate(random), coordinate(random)};
  // Points on a tilted plane, rounded to doubles: nearly coplanar, so the
  // floating-point filter cannot decide and the exact stage runs.
  const Vec3 origin{0.1, 0.2, 0.3}, u{0.7, 0.1, 0.3}, v{0.2, 0.9, -0.4};
  for (int i = 0; i < 30; ++i) x[i] = origin + coordinate(random) * u + coordinate(random) * v;
  std::uniform_int_distribution<Index> vertex(0, 299);
  std::vector<Triangle> triangles(400);
  for (Triangle& t : triangles) t = {vertex(random), vertex(random), vertex(random)};
  for (int i = 0; i < 20; ++i) triangles[i] = {Index(i), Index(i + 1), Index(i + 2)};  // in the coplanar set
  std::vector<TrianglePair> pairs;
  for (Index a = 0; a < 400; ++a)
    for (Index b = a + 1; b < 400; b += 1 + a % 5) pairs.push_back({a, b});

  std::vector<std::uint32_t> cpu_hits;
  PredicateCounters cpu_counters;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Triangle& ta = triangles[pairs[i].a];
    const Triangle& tb = triangles[pairs[i].b];
    const Vec3 a[3] = {x[ta[0]], x[ta[1]], x[ta[2]]};
    const Vec3 b[3] = {x[tb[0]], x[tb[1]], x[tb[2]]};
    if (triangles_intersect(a, ta.data(), b, tb.data(), &cpu_counters)) cpu_hits.push_back(std::uint32_t(i));
  }
  ASSERT_FALSE(cpu_hits.empty());
  ASSERT_GT(cpu_counters.exact, 0u);

  DeviceBuffer<Vec3> d_x;
  DeviceBuffer<Triangle> d_triangles;
  DeviceBuffer<TrianglePair> d_pairs;
  d_x.upload(x);
  d_triangles.upload(triangles);
  d_pairs.upload(pairs);
  CudaNarrowPhase narrow(nullptr);
  std::vector<std::uint32_t> gpu_hits;
  TrianglePairCounts gpu_counts;
  narrow.triangle_pairs(d_x.data(), d_triangles.data(), d_pairs.data(), pairs.size(), gpu_hits, gpu_counts);
  EXPECT_EQ(gpu_hits, cpu_hits);
  EXPECT_EQ(gpu_counts.predicate_calls, cpu_counters.calls);
  EXPECT_EQ(gpu_counts.predicate_exact, cpu_counters.exact);

  // In rounds of 101 pairs, with the intersecting pairs themselves.
  narrow.set_chunk_size(101);
  std::vector<std::uint32_t> round_hits;
  std::vector<TrianglePair> round_pairs;
  TrianglePairCounts round_counts;
  narrow.triangle_pairs(d_x.data(), d_triangles.data(), d_pairs.data(), pairs.size(), round_hits, round_counts,
                        &round_pairs);
  EXPECT_EQ(round_hits, cpu_hits);
  EXPECT_EQ(round_counts.predicate_calls, cpu_counters.calls);
  ASSERT_EQ(round_pairs.size(), cpu_hits.size());
  for (std::size_t k = 0; k < cpu_hits.size(); ++k) EXPECT_TRUE(round_pairs[k] == pairs[cpu_hits[k]]);

  // Built into intersection events on the device, in rounds of 101 pairs.
  std::vector<Event> events;
  TrianglePairCounts event_counts;
  EXPECT_EQ(narrow.triangle_pair_events(d_x.data(), d_triangles.data(), d_pairs.data(), pairs.size(), events,
                                        event_counts),
            cpu_hits.size());
  EXPECT_EQ(event_counts.predicate_exact, cpu_counters.exact);
  std::vector<Event> host;
  for (const std::uint32_t k : cpu_hits) {
    const TrianglePair pair = pairs[k];
    const Triangle& ta = triangles[pair.a];
    const Triangle& tb = triangles[pair.b];
    const Vec3 a[3] = {x[ta[0]], x[ta[1]], x[ta[2]]};
    const Vec3 b[3] = {x[tb[0]], x[tb[1]], x[tb[2]]};
    host.push_back(intersection_fields(pair.a, pair.b, a, b));
  }
  test::expect_same_events(host, events, "intersection events");
}

TEST_F(NarrowPhaseTrianglePairs, EmptyInputGivesNoHits) {
  CudaNarrowPhase narrow(nullptr);
  std::vector<std::uint32_t> hits;
  TrianglePairCounts counts;
  narrow.triangle_pairs(nullptr, nullptr, nullptr, 0, hits, counts);
  std::vector<CcdHit> ccd_hits;
  narrow.vertex_face(nullptr, nullptr, nullptr, nullptr, 0, CcdSettings{}, CcdPasses::kScreenThenSearch, ccd_hits);
  std::vector<Event> events;
  narrow.vertex_face_events(nullptr, nullptr, nullptr, nullptr, 0, CcdSettings{}, CcdPasses::kScreenOnly, events);
  EXPECT_EQ(narrow.triangle_pair_events(nullptr, nullptr, nullptr, 0, events, counts), 0u);
  EXPECT_TRUE(events.empty());
  EXPECT_TRUE(hits.empty());
  EXPECT_TRUE(ccd_hits.empty());
  EXPECT_EQ(counts.predicate_calls, 0u);
}

}  // namespace
}  // namespace snag
