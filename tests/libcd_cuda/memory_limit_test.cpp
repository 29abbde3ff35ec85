// Bounded device memory: the CUDA broad phase run in many chunks of root
// triangles and parts of pairs gives exactly the candidates of one chunk (and
// the same counts), and the CUDA back end under a small --device-memory limit
// gives exactly the events of the unlimited run and of the CPU back end, with
// the bytes its buffers hold (DeviceMemoryTracker) never above the limit. A
// limit too small for the topology, for a stage before the pair tests (checked
// before the stage allocates) or for one chunk is a UsageError (exit 2 from
// snag-scan), never a crash; a limit at which each detection fits alone
// holds the whole scan, and a scan whose detections run together or one
// after the other, by the limit, gives the same events. Oracles: the
// unchunked GPU run and the CPU back end.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "gpu_test.hpp"
#include "libcd/core/error.hpp"
#include "libcd/cpu/cpu_backend.hpp"
#include "libcd/cuda/cuda_backend.hpp"
#include "libcd/cuda/cuda_broad_phase.cuh"
#include "libcd/cuda/device_memory_tracker.hpp"
#include "ply_mesh.hpp"
#include "tests/common/event_compare.hpp"

namespace snag {
namespace {

/// The cloth_ball92 -> 93 step of the reference data.
struct ClothBallStep {
  test::PlyMesh m92 = test::read_binary_ply(test::shared_data_dir() + "/meshes/cloth_ball92.ply");
  test::PlyMesh m93 = test::read_binary_ply(test::shared_data_dir() + "/meshes/cloth_ball93.ply");
  Scene scene{{make_object("cloth_ball", static_cast<Index>(m92.positions.size()), m92.triangles)}};
};

struct Candidates {
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  std::vector<TrianglePair> pairs;
  BroadPhaseStats ccd, statics;
  std::size_t ccd_chunks = 0;  ///< chunks the CCD detection ran in
};

Candidates detect(CudaBroadPhase& broad, const ClothBallStep& step) {
  Candidates out;
  broad.detect_ccd(step.m92.positions, step.m93.positions, out.vf, out.ee);
  out.ccd = broad.stats();
  out.ccd_chunks = broad.last_chunks();
  broad.detect_static(step.m93.positions, out.pairs);
  out.statics = broad.stats();
  return out;
}

void expect_same_counts(const BroadPhaseStats& one, const BroadPhaseStats& chunked, const std::string& where) {
  EXPECT_EQ(one.tests, chunked.tests) << where;
  EXPECT_EQ(one.culled_by_boxes, chunked.culled_by_boxes) << where;
  EXPECT_EQ(one.same_root_tests, chunked.same_root_tests) << where;
  EXPECT_EQ(one.removed_by_time_slots, chunked.removed_by_time_slots) << where;
  EXPECT_EQ(one.removed_by_control_bits, chunked.removed_by_control_bits) << where;
  EXPECT_EQ(one.removed_by_extended_control_bits, chunked.removed_by_extended_control_bits) << where;
  EXPECT_EQ(one.culled_by_dop, chunked.culled_by_dop) << where;
  EXPECT_EQ(one.duplicate_root_pair_tests, chunked.duplicate_root_pair_tests) << where;
  EXPECT_EQ(one.triangle_pairs, chunked.triangle_pairs) << where;
  EXPECT_EQ(one.separated_triangle_pairs, chunked.separated_triangle_pairs) << where;
  EXPECT_EQ(one.vf_before_culling, chunked.vf_before_culling) << where;
  EXPECT_EQ(one.ee_before_culling, chunked.ee_before_culling) << where;
  EXPECT_EQ(one.candidates, chunked.candidates) << where;
}

class MemoryLimit : public test::GpuTest {};

TEST_F(MemoryLimit, ChunkedBroadPhaseOnClothBallGivesTheCandidatesOfOneChunk) {
  const ClothBallStep step;
  auto whole = CudaBroadPhase::create(BroadPhaseMethod::kVirtualSubdivisionGrid);
  whole->build(step.scene, BroadPhaseSettings{});
  const Candidates one = detect(*whole, step);
  ASSERT_EQ(one.ccd_chunks, 1u);
  ASSERT_GT(one.pairs.size(), 100000u);
  ASSERT_GT(one.vf.size() + one.ee.size(), 1000000u);

  // Rooms of a few percent of the step's keys and candidates: tens of chunks
  // and parts; the second detection reuses the first one's ranges.
  auto chunked = CudaBroadPhase::create(BroadPhaseMethod::kVirtualSubdivisionGrid);
  chunked->build(step.scene, BroadPhaseSettings{});
  chunked->set_chunk_rooms(one.ccd.triangle_pairs / 20, (one.vf.size() + one.ee.size()) / 50);
  for (int run = 0; run < 2; ++run) {
    const std::string where = "run " + std::to_string(run);
    const Candidates many = detect(*chunked, step);
    EXPECT_GT(many.ccd_chunks, 10u) << where;
    EXPECT_EQ(many.vf, one.vf) << where;
    EXPECT_EQ(many.ee, one.ee) << where;
    EXPECT_EQ(many.pairs, one.pairs) << where;
    expect_same_counts(one.ccd, many.ccd, where + " ccd");
    expect_same_counts(one.statics, many.statics, where + " static");
  }
  // Parts of pairs inside each chunk: a candidate room far under a chunk's.
  chunked->set_chunk_rooms(one.ccd.triangle_pairs / 4, (one.vf.size() + one.ee.size()) / 100);
  Candidates parts;
  chunked->detect_ccd(step.m92.positions, step.m93.positions, parts.vf, parts.ee);
  EXPECT_GT(chunked->last_feature_parts(), 50u);
  EXPECT_EQ(parts.vf, one.vf);
  EXPECT_EQ(parts.ee, one.ee);
  expect_same_counts(one.ccd, chunked->stats(), "parts");
}

// The same on a small random soup with rooms of a few keys and candidates
// (tens of chunks and parts): small enough for the sanitizers.
TEST_F(MemoryLimit, ChunksOfAFewTestsGiveTheCandidatesOfOneChunk) {
  std::mt19937_64 random(14);
  std::uniform_real_distribution<double> where(0, 1), corner(-0.05, 0.05), drift(-0.02, 0.02);
  std::vector<Vec3> x_t0, x_t1;
  std::vector<Triangle> triangles;
  for (Index t = 0; t < 1500; ++t) {
    const Vec3 center{where(random), where(random), where(random)};
    const Vec3 move{drift(random), drift(random), drift(random)};
    for (int k = 0; k < 3; ++k) {
      x_t0.push_back(center + Vec3{corner(random), corner(random), corner(random)});
      x_t1.push_back(x_t0.back() + move);
    }
    triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  const Scene scene({make_object("soup", static_cast<Index>(x_t0.size()), triangles)});
  auto whole = CudaBroadPhase::create(BroadPhaseMethod::kVirtualSubdivisionGrid);
  whole->build(scene, BroadPhaseSettings{});
  Candidates one;
  whole->detect_ccd(x_t0, x_t1, one.vf, one.ee);
  one.ccd = whole->stats();
  whole->detect_static(x_t1, one.pairs);
  ASSERT_GT(one.vf.size() + one.ee.size(), 500u);

  auto chunked = CudaBroadPhase::create(BroadPhaseMethod::kVirtualSubdivisionGrid);
  chunked->build(scene, BroadPhaseSettings{});
  chunked->set_chunk_rooms(one.ccd.triangle_pairs / 20 + 8, (one.vf.size() + one.ee.size()) / 30 + 16);
  Candidates many;
  chunked->detect_ccd(x_t0, x_t1, many.vf, many.ee);
  EXPECT_GT(chunked->last_chunks(), 10u);
  EXPECT_GT(chunked->last_feature_parts(), 20u);
  EXPECT_EQ(many.vf, one.vf);
  EXPECT_EQ(many.ee, one.ee);
  expect_same_counts(one.ccd, chunked->stats(), "soup");
  chunked->detect_static(x_t1, many.pairs);
  EXPECT_EQ(many.pairs, one.pairs);
}

TEST_F(MemoryLimit, OneTriangleOverTheRoomOnClothBallIsAUsageError) {
  const ClothBallStep step;
  auto broad = CudaBroadPhase::create(BroadPhaseMethod::kVirtualSubdivisionGrid);
  broad->build(step.scene, BroadPhaseSettings{});
  broad->set_chunk_rooms(1, 0);  // every triangle keeps more than one test with its neighbours
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  EXPECT_THROW(broad->detect_ccd(step.m92.positions, step.m93.positions, vf, ee), UsageError);
  broad->set_chunk_rooms(0, 10);  // under the 15 candidates one pair may yield
  EXPECT_THROW(broad->detect_ccd(step.m92.positions, step.m93.positions, vf, ee), UsageError);
}

/// Bytes of the census entries of `broad` whose names start with one of `prefixes`.
std::size_t census_bytes(const CudaBroadPhase& broad, const std::vector<std::string>& prefixes) {
  std::size_t total = 0;
  for (const auto& [name, bytes] : broad.memory_census())
    for (const std::string& prefix : prefixes)
      if (name.rfind(prefix, 0) == 0) total += bytes;
  return total;
}

// A budget too small for the bounds, or for the subdivision once the bounds
// fit, is refused before that stage allocates past it: the UsageError names
// the stage, and the broad phase then holds no more than its budget (it used
// to allocate the bounds, subdivision and registration first and refuse only
// before the pair tests). The stages' sizes come from the census of an
// unlimited detection of the same step.
TEST_F(MemoryLimit, BudgetTooSmallForClothBallBoundsOrSubdivisionIsRefusedBeforeTheyAllocate) {
  const ClothBallStep step;
  auto unlimited = CudaBroadPhase::create(BroadPhaseMethod::kVirtualSubdivisionGrid);
  unlimited->build(step.scene, BroadPhaseSettings{});
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  unlimited->detect_ccd(step.m92.positions, step.m93.positions, vf, ee);
  const std::size_t before_bounds = census_bytes(*unlimited, {"topology", "uploaded positions"});
  const std::size_t bounds = census_bytes(*unlimited, {"bounds:"});
  ASSERT_GT(bounds, std::size_t{4} << 20);  // so that 1 MiB over the stages before is too little for it

  const std::pair<std::size_t, const char*> cases[] = {{before_bounds + (1 << 20), "bounds"},
                                                       {before_bounds + bounds + (1 << 20), "subdivision"}};
  for (const auto& [budget, stage] : cases) {
    auto broad = CudaBroadPhase::create(BroadPhaseMethod::kVirtualSubdivisionGrid);
    broad->build(step.scene, BroadPhaseSettings{});
    broad->set_memory_budget(budget);
    const std::string where = std::string("budget ") + std::to_string(budget) + " bytes (" + stage + ")";
    try {
      broad->detect_ccd(step.m92.positions, step.m93.positions, vf, ee);
      ADD_FAILURE() << where << ": accepted";
    } catch (const UsageError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("too small"), std::string::npos) << where << ": " << message;
      EXPECT_NE(message.find(stage), std::string::npos) << where << ": " << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << where << ": one line";
    }
    EXPECT_LE(broad->held_bytes(), budget) << where;
  }
}

// Under a budget, a detection gives its stage buffers back once the pair
// tests start, and keeps its chunk buffers for the next one. The next
// detection's stages, allocated again, take the room of those chunks (they
// are sized again after the registration): under a budget at which the
// stages just fit, the second detection of the same step used to be refused
// in its bounds or subdivision although the first one fitted. The stages'
// sizes come from the census of an unlimited detection of the step.
TEST_F(MemoryLimit, NextDetectionsStagesTakeTheRoomOfTheLastOnesChunksOnClothBall) {
  const ClothBallStep step;
  auto unlimited = CudaBroadPhase::create(BroadPhaseMethod::kVirtualSubdivisionGrid);
  unlimited->build(step.scene, BroadPhaseSettings{});
  Candidates one;
  unlimited->detect_ccd(step.m92.positions, step.m93.positions, one.vf, one.ee);
  const std::size_t chunks =
      census_bytes(*unlimited, {"pairs: kept test keys (chunk)", "pairs: sorted keys (chunk)",
                                "pairs: unique pairs (chunk)", "pairs: cell tests and tiles", "features: tallies",
                                "features: keys (part)", "features: candidates (part)"});
  const std::size_t stages = unlimited->held_bytes() - chunks;
  ASSERT_GT(chunks, std::size_t{16} << 20);  // far over the budget's 1 MiB above the stages

  auto broad = CudaBroadPhase::create(BroadPhaseMethod::kVirtualSubdivisionGrid);
  broad->build(step.scene, BroadPhaseSettings{});
  const std::size_t budget = stages + (1 << 20);
  broad->set_memory_budget(budget);
  for (int run = 0; run < 3; ++run) {
    const std::string where = "run " + std::to_string(run) + ", budget " + std::to_string(budget) + " bytes";
    Candidates limited;
    try {
      broad->detect_ccd(step.m92.positions, step.m93.positions, limited.vf, limited.ee);
    } catch (const UsageError& error) {
      ADD_FAILURE() << where << ": " << error.what();
      continue;
    }
    EXPECT_EQ(limited.vf, one.vf) << where;
    EXPECT_EQ(limited.ee, one.ee) << where;
    expect_same_counts(unlimited->stats(), broad->stats(), where);
    EXPECT_GT(census_bytes(*broad, {"pairs: kept test keys (chunk)"}), 0u) << where << ": chunks kept";
    EXPECT_LE(broad->held_bytes(), budget) << where;
  }
}

/// A CUDA back end bound to the cloth_ball scene under `limit` (0: none).
std::unique_ptr<Backend> bound_backend(const ClothBallStep& step, std::size_t limit) {
  auto gpu = make_cuda_backend();
  BackendSettings settings;
  settings.device_memory_bytes = limit;
  gpu->bind(step.scene, settings);
  return gpu;
}

/// The events `calls` gets from a back end bound under `limit`, and the
/// bytes the back end's buffers held at most meanwhile.
struct LimitedRun {
  std::vector<Event> events;
  std::size_t peak_bytes = 0;
};

template <class Calls>
LimitedRun run_limited(const ClothBallStep& step, std::size_t limit, Calls calls) {
  DeviceMemoryTracker& tracker = DeviceMemoryTracker::instance();
  const std::size_t before = tracker.current_bytes();
  tracker.reset_peak();
  LimitedRun run;
  {
    auto gpu = bound_backend(step, limit);
    run.events = calls(*gpu);
  }
  run.peak_bytes = tracker.peak_bytes() - before;
  return run;
}

/// Frame 92, step 92 -> 93, frame 93 and step 93 -> 92 under `limit`.
LimitedRun run_limited(const ClothBallStep& step, std::size_t limit) {
  return run_limited(step, limit, [&](Backend& gpu) {
    std::vector<Event> frame92, collisions, frame93;
    gpu.intersections(step.m92.positions, frame92);
    gpu.collisions(step.m92.positions, step.m93.positions, collisions);
    gpu.intersections(step.m93.positions, frame93);
    // A second step: the plan of the first, the buffers given back or kept.
    std::vector<Event> again;
    gpu.collisions(step.m93.positions, step.m92.positions, again);
    std::vector<Event> events;
    for (const auto* part : {&frame92, &collisions, &frame93, &again})
      events.insert(events.end(), part->begin(), part->end());
    return events;
  });
}

TEST_F(MemoryLimit, BackEndOnClothBallUnderALimitGivesTheEventsOfTheUnlimitedRunAndOfTheCpu) {
  const ClothBallStep step;
  const LimitedRun unlimited = run_limited(step, 0);
  ASSERT_GT(unlimited.events.size(), 100000u);

  std::vector<Event> cpu_events;
  {
    auto cpu = make_cpu_backend();
    cpu->bind(step.scene, BackendSettings{});
    std::vector<Event> part;
    cpu->intersections(step.m92.positions, cpu_events);
    cpu->collisions(step.m92.positions, step.m93.positions, part);
    cpu_events.insert(cpu_events.end(), part.begin(), part.end());
    part.clear();
    cpu->intersections(step.m93.positions, part);
    cpu_events.insert(cpu_events.end(), part.begin(), part.end());
    part.clear();
    cpu->collisions(step.m93.positions, step.m92.positions, part);
    cpu_events.insert(cpu_events.end(), part.begin(), part.end());
  }
  test::expect_same_events(cpu_events, unlimited.events, "unlimited against the CPU");

  // Limits of a half, a quarter and an eighth of the unlimited run's peak:
  // each either fits (same events, peak within the limit) or is refused with
  // a UsageError; the half must fit.
  int fitted = 0;
  for (const std::size_t divisor : {2, 4, 8}) {
    const std::size_t limit = unlimited.peak_bytes / divisor;
    const std::string where = "limit " + std::to_string(limit) + " bytes (1/" + std::to_string(divisor) + ")";
    try {
      const LimitedRun limited = run_limited(step, limit);
      ++fitted;
      EXPECT_LE(limited.peak_bytes, limit) << where;
      test::expect_same_events(unlimited.events, limited.events, where);
    } catch (const UsageError& error) {
      EXPECT_NE(std::string(error.what()).find("too small"), std::string::npos) << where << ": " << error.what();
      EXPECT_NE(divisor, 2u) << where << ": " << error.what();
    }
  }
  EXPECT_GE(fitted, 1);
}

/// The smallest limit, to 1/64 of `high`, under which `run(limit)` is not
/// refused (UsageError); `high` must not be.
template <class Run>
std::size_t smallest_limit(std::size_t high, Run run) {
  std::size_t low = 0;  // refused
  while (high - low > high / 64) {
    const std::size_t middle = low + (high - low) / 2;
    try {
      run(middle);
      high = middle;
    } catch (const UsageError&) {
      low = middle;
    }
  }
  return high;
}

/// Runs one kind of detection alone under `limit` (UsageError when refused):
/// the steps 92 -> 93 and 93 -> 92 (frames 92 and 93) one after the other in
/// one back end, and the second again in a back end of its own. In a scan the
/// other detection may have the buffers of this one given back, so that a
/// detection also runs from nothing after the first; 93 -> 92 from nothing
/// takes a little more than after 92 -> 93, whose buffers it finds held.
void detection_alone(const ClothBallStep& step, std::size_t limit, bool static_detection) {
  auto run = [&](Backend& gpu, bool first_too) {
    std::vector<Event> events;
    if (static_detection) {
      if (first_too) gpu.intersections(step.m92.positions, events);
      gpu.intersections(step.m93.positions, events);
    } else {
      if (first_too) gpu.collisions(step.m92.positions, step.m93.positions, events);
      gpu.collisions(step.m93.positions, step.m92.positions, events);
    }
  };
  run(*bound_backend(step, limit), true);
  run(*bound_backend(step, limit), false);
}

// A scan alternates static and CCD detections, and each keeps its buffers
// for the next step unless they hold more than half of the room. Under a
// limit at which each detection fits on its own, the whole scan fits, with
// the unlimited run's events: a detection refused beside the other's buffers
// gets them given back and runs again.
TEST_F(MemoryLimit, ClothBallScanFitsUnderTheLimitAtWhichEachDetectionFitsAlone) {
  const ClothBallStep step;
  const LimitedRun unlimited = run_limited(step, 0);
  auto collisions_alone = [&](std::size_t limit) { detection_alone(step, limit, false); };
  auto intersections_alone = [&](std::size_t limit) { detection_alone(step, limit, true); };
  const std::size_t high = 2 * unlimited.peak_bytes;
  ASSERT_NO_THROW(collisions_alone(high));
  ASSERT_NO_THROW(intersections_alone(high));
  const std::size_t ccd_alone = smallest_limit(high, collisions_alone);
  const std::size_t static_alone = smallest_limit(high, intersections_alone);
  const std::size_t limit = std::max(ccd_alone, static_alone);
  const std::string where = "limit " + std::to_string(limit) + " bytes (CCD alone " + std::to_string(ccd_alone) +
                            ", static alone " + std::to_string(static_alone) + ")";
  try {
    const LimitedRun limited = run_limited(step, limit);
    EXPECT_LE(limited.peak_bytes, limit) << where;
    test::expect_same_events(unlimited.events, limited.events, where);
  } catch (const UsageError& error) {
    ADD_FAILURE() << where << ": " << error.what();
  }
}

/// The events of a scan of `frames` frames (92, 93, 92, ...) in a scan's
/// order of calls: the frame after the step prepared, the step's collisions,
/// then its first frame's intersections.
std::vector<Event> scan_in_order(Backend& backend, const ClothBallStep& step, std::size_t frames) {
  auto x = [&](std::size_t f) -> const std::vector<Vec3>& {
    return f % 2 == 0 ? step.m92.positions : step.m93.positions;
  };
  std::vector<Event> events;
  for (std::size_t f = 0; f < frames; ++f) {
    if (f + 2 < frames) backend.prepare(x(f + 2));
    if (f + 1 < frames) backend.collisions(x(f), x(f + 1), events);
    backend.intersections(x(f), events);
  }
  return events;
}

LimitedRun scan_limited(const ClothBallStep& step, std::size_t limit, std::size_t frames) {
  return run_limited(step, limit, [&](Backend& gpu) { return scan_in_order(gpu, step, frames); });
}

// In a scan the static detection of a frame runs ahead beside the CCD of the
// step after it when each seems to fit in half of the room, else after it;
// one that did not fit runs again alone. Under every limit from the one at
// which each detection fits alone (where stage buffers are given back after
// each run, so that both seem small) to four times the unlimited scan's
// peak, a scan of five frames gives the unlimited scan's events, which are
// the CPU's, within the limit.
TEST_F(MemoryLimit, ClothBallScanUnderLimitsGivesTheEventsOfTheUnlimitedScanAndOfTheCpu) {
  const ClothBallStep step;
  constexpr std::size_t kFrames = 5;
  const LimitedRun unlimited = scan_limited(step, 0, kFrames);
  ASSERT_GT(unlimited.events.size(), 200000u);
  auto cpu = make_cpu_backend();
  cpu->bind(step.scene, BackendSettings{});
  test::expect_same_events(scan_in_order(*cpu, step, kFrames), unlimited.events, "unlimited scan against the CPU");

  const std::size_t high = 2 * unlimited.peak_bytes;
  const std::size_t alone =
      std::max(smallest_limit(high, [&](std::size_t limit) { detection_alone(step, limit, false); }),
               smallest_limit(high, [&](std::size_t limit) { detection_alone(step, limit, true); }));
  const double peak = static_cast<double>(unlimited.peak_bytes);
  for (const std::size_t limit :
       {alone, alone * 5 / 4, alone * 3 / 2, 2 * alone, 3 * alone, static_cast<std::size_t>(peak),
        static_cast<std::size_t>(2 * peak), static_cast<std::size_t>(4 * peak)}) {
    const std::string where = "limit " + std::to_string(limit) + " bytes (each detection alone fits under " +
                              std::to_string(alone) + ", unlimited peak " + std::to_string(unlimited.peak_bytes) + ")";
    try {
      const LimitedRun limited = scan_limited(step, limit, kFrames);
      EXPECT_LE(limited.peak_bytes, limit) << where;
      test::expect_same_events(unlimited.events, limited.events, where);
    } catch (const UsageError& error) {
      ADD_FAILURE() << where << ": " << error.what();
    }
  }
}

TEST_F(MemoryLimit, LimitTooSmallForClothBallIsAUsageError) {
  const ClothBallStep step;
  {
    auto gpu = make_cuda_backend();
    BackendSettings settings;
    settings.device_memory_bytes = 1 << 20;  // under the topology and two frames
    try {
      gpu->bind(step.scene, settings);
      ADD_FAILURE() << "bind() accepted 1 MiB";
    } catch (const UsageError& error) {
      EXPECT_NE(std::string(error.what()).find("too small"), std::string::npos) << error.what();
    }
  }
  {
    auto gpu = make_cuda_backend();
    BackendSettings settings;
    settings.device_memory_bytes = 8 << 20;  // the topology and frames fit, the broad phase does not
    gpu->bind(step.scene, settings);
    std::vector<Event> events;
    EXPECT_THROW(gpu->collisions(step.m92.positions, step.m93.positions, events), UsageError);
  }
}

}  // namespace
}  // namespace snag
