// The CUDA back end against the CPU back end (its oracle): the same event
// vectors, bit for bit (kind, type, ids, times of impact, positions,
// certainty), and the same narrow-phase counts, on random soups of uneven
// sizes, on frames refilled in place (the device frame cache must not serve a
// stale frame), on frames other than the one whose intersections were started
// ahead, on the sample cache and a Blender-baked funnel through scan_cache,
// and on the real cloth_ball92 -> 93 step.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "gpu_test.hpp"
#include "io/open_cache.hpp"
#include "libcd/cpu/cpu_backend.hpp"
#include "libcd/cuda/cuda_backend.hpp"
#include "libcd/pipeline/scan.hpp"
#include "ply_mesh.hpp"
#include "snag/config.hpp"
#include "tests/common/event_compare.hpp"
#if SNAG_HAVE_CGAL
#include "validate/exact_certifier.hpp"
#endif

namespace snag {
namespace {

using test::expect_same_counts;
using test::expect_same_events;

/// The CPU back end doing the CUDA back end's work: the VSS grid for both
/// modes and the static test pair by pair, so that the counts match too.
/// The default CPU back end (box grid, the static test by frame) gives the
/// same events with other counts; SameScanOfTheSampleCache checks it as well.
std::unique_ptr<Backend> make_cpu_backend_counting_like_cuda(
    BroadPhaseMethod method = BroadPhaseMethod::kVirtualSubdivisionGrid) {
  return make_cpu_backend(CpuBackendOptions{method, false});
}

/// Both back ends bound to one scene with the same settings and broad phase
/// (the VSS grid, or the adaptive grid).
struct BackendPair {
  std::unique_ptr<Backend> cpu, gpu;
  BackendPair(const Scene& scene, const BackendSettings& settings,
              BroadPhaseMethod method = BroadPhaseMethod::kVirtualSubdivisionGrid)
      : cpu(make_cpu_backend_counting_like_cuda(method)), gpu(make_cuda_backend(method)) {
    cpu->bind(scene, settings);
    gpu->bind(scene, settings);
  }
  void compare_step(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, const std::string& where) {
    std::vector<Event> cpu_events, gpu_events;
    cpu->collisions(x_t0, x_t1, cpu_events);
    gpu->collisions(x_t0, x_t1, gpu_events);
    expect_same_events(cpu_events, gpu_events, where + " collisions");
    expect_same_counts(cpu->stats().narrow, gpu->stats().narrow, where + " collisions");
    EXPECT_EQ(cpu->stats().ccd_broad.candidates, gpu->stats().ccd_broad.candidates) << where;
    collisions_found += cpu_events.size();
  }
  void compare_frame(const std::vector<Vec3>& x, const std::string& where) {
    std::vector<Event> cpu_events, gpu_events;
    cpu->intersections(x, cpu_events);
    gpu->intersections(x, gpu_events);
    expect_same_events(cpu_events, gpu_events, where + " intersections");
    expect_same_counts(cpu->stats().narrow, gpu->stats().narrow, where + " intersections");
    intersections_found += cpu_events.size();
  }
  std::size_t collisions_found = 0, intersections_found = 0;
};

/// A soup of `count` small random triangles in the unit cube, moving by up to
/// `motion` per step: many crossings, and intersections in each frame.
struct Soup {
  Scene scene;
  std::vector<std::vector<Vec3>> frames;
};

Soup make_soup(std::size_t count, int frame_count, double motion, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0, 1), small(-0.04, 0.04), move(-motion, motion);
  std::vector<Vec3> x;
  std::vector<Triangle> triangles;
  for (std::size_t f = 0; f < count; ++f) {
    const Vec3 center{unit(random), unit(random), unit(random)};
    const Index base = static_cast<Index>(x.size());
    for (int k = 0; k < 3; ++k) x.push_back(center + Vec3{small(random), small(random), small(random)});
    triangles.push_back({base, base + 1, base + 2});
  }
  // Some triangles share a vertex or an edge with the next one.
  for (std::size_t f = 0; f + 1 < count; f += 7) triangles[f + 1][0] = triangles[f][2];
  Soup soup;
  soup.scene = Scene({make_object("soup", static_cast<Index>(x.size()), triangles)});
  soup.frames.push_back(x);
  for (int i = 1; i < frame_count; ++i) {
    for (Vec3& p : x) p = p + Vec3{move(random), move(random), move(random)};
    soup.frames.push_back(x);
  }
  return soup;
}

BackendSettings settings_with_certifier(bool certified) {
  BackendSettings settings;
#if SNAG_HAVE_CGAL
  static const std::unique_ptr<Certifier> certifier = validate::make_exact_certifier();
  if (certified) settings.certifier = certifier.get();
#else
  (void)certified;
#endif
  return settings;
}

class BackendEquality : public test::GpuTest {};

TEST_F(BackendEquality, SameEventsOnRandomSoupsOfUnevenSizes) {
  const std::size_t sizes[] = {1, 2, 37, 129, 1000, 4099};
  std::size_t collisions = 0, intersections = 0;
  for (const std::size_t size : sizes) {
    for (const bool certified : {false, true}) {
      const Soup soup = make_soup(size, 3, 0.03, 1000 + size);
      BackendPair pair(soup.scene, settings_with_certifier(certified));
      const std::string where = std::to_string(size) + " triangles" + (certified ? ", certified" : ", fast");
      for (std::size_t f = 0; f < soup.frames.size(); ++f) {
        pair.compare_frame(soup.frames[f], where + " frame " + std::to_string(f));
        if (f + 1 < soup.frames.size())
          pair.compare_step(soup.frames[f], soup.frames[f + 1], where + " step " + std::to_string(f));
      }
      collisions += pair.collisions_found;
      intersections += pair.intersections_found;
    }
  }
  EXPECT_GT(collisions, 0u) << "the soups must collide for the comparison to mean something";
  EXPECT_GT(intersections, 0u);
}

TEST_F(BackendEquality, SameEventsWithThickness) {
  const Soup soup = make_soup(700, 2, 0.02, 77);
  BackendSettings settings = settings_with_certifier(true);
  settings.thickness = 0.01;
  BackendPair pair(soup.scene, settings);
  pair.compare_step(soup.frames[0], soup.frames[1], "thickness 0.01");
  EXPECT_GT(pair.collisions_found, 0u);
}

TEST_F(BackendEquality, FrameRefilledInPlaceIsUploadedAgain) {
  const Soup soup = make_soup(500, 4, 0.03, 5);
  BackendPair pair(soup.scene, settings_with_certifier(false));
  // One pair of vectors refilled in place, as a reader would: same addresses,
  // new contents; and the scan's pattern of reusing x_t1 as the next x_t0.
  std::vector<Vec3> a = soup.frames[0], b = soup.frames[1];
  pair.compare_step(a, b, "step 0");
  pair.compare_frame(b, "frame 1");
  a = soup.frames[2];
  pair.compare_step(b, a, "step 1");
  b = soup.frames[3];
  pair.compare_step(a, b, "step 2");
  b = soup.frames[0];
  a = soup.frames[3];
  pair.compare_step(b, a, "step 0 -> 3");
  pair.compare_frame(a, "frame 3");
  pair.compare_frame(b, "frame 0");
  EXPECT_GT(pair.collisions_found, 0u);
}

// collisions() starts the static detection of its x_t1 ahead (once
// intersections were asked for); a caller that then asks for another frame, or
// for a frame whose slot was refilled, must get that frame's intersections.
TEST_F(BackendEquality, IntersectionsOfAFrameOtherThanTheOneStartedAhead) {
  const Soup soup = make_soup(900, 4, 0.03, 11);
  BackendPair pair(soup.scene, settings_with_certifier(true));
  pair.compare_frame(soup.frames[0], "frame 0");
  pair.compare_step(soup.frames[0], soup.frames[1], "step 0");  // starts frame 1 ahead
  pair.compare_frame(soup.frames[2], "frame 2 instead of 1");
  pair.compare_step(soup.frames[2], soup.frames[3], "step 2");  // starts frame 3 ahead
  pair.compare_step(soup.frames[0], soup.frames[1], "step 0 again");  // refills frame 3's slot
  pair.compare_frame(soup.frames[3], "frame 3");
  pair.compare_frame(soup.frames[1], "frame 1");
  EXPECT_GT(pair.collisions_found, 0u);
  EXPECT_GT(pair.intersections_found, 0u);
}

// collisions() also detects the next step ahead when a frame was prepared
// since its x_t1 (the scan prepares frame f + 2 before the step f -> f + 1):
// the next call must get its own step's collisions when it asks for another
// step, or for the prepared vector refilled in place.
TEST_F(BackendEquality, CollisionsOfAStepOtherThanTheOneDetectedAhead) {
  const Soup soup = make_soup(900, 5, 0.03, 13);
  const std::vector<std::vector<Vec3>>& x = soup.frames;
  BackendPair pair(soup.scene, settings_with_certifier(true));
  pair.compare_frame(x[0], "frame 0");
  pair.gpu->prepare(x[2]);
  pair.compare_step(x[0], x[1], "step 0");  // detects 1 -> 2 ahead
  pair.compare_frame(x[0], "frame 0 again");
  pair.compare_step(x[1], x[2], "step 1, detected ahead");
  pair.gpu->prepare(x[4]);
  pair.compare_step(x[2], x[3], "step 2");  // detects 3 -> 4 ahead
  pair.compare_step(x[3], x[0], "step 3 -> 0 instead of 3 -> 4");
  std::vector<Vec3> refilled = x[2];
  pair.gpu->prepare(refilled);
  pair.compare_step(x[0], x[1], "step 0 again");  // detects 1 -> 2 ahead
  refilled = x[4];
  pair.compare_step(x[1], refilled, "step 1 -> 4, the prepared vector refilled");
  const std::vector<Vec3> again = x[0];  // a t0 t1 t0 ... sequence: the frame after the step is its x_t0
  pair.gpu->prepare(again);
  pair.compare_step(x[0], x[1], "step 0, x_t0 prepared again");  // detects 1 -> 0 ahead
  pair.compare_step(x[1], again, "step 1 -> 0, detected ahead");
  pair.compare_frame(x[1], "frame 1");
  pair.compare_frame(refilled, "frame 4");
  EXPECT_GT(pair.collisions_found, 0u);
  EXPECT_GT(pair.intersections_found, 0u);
}

/// The sample caches: $SNAG_SAMPLES_DIR; else samples/ next to the reference
/// data named by $SNAG_SHARED_DATA_DIR (the GPU bundle's layout); else the
/// source tree's.
std::string samples_dir() {
  const char* from_environment = std::getenv("SNAG_SAMPLES_DIR");
  if (from_environment != nullptr && *from_environment != '\0') return from_environment;
  const std::filesystem::path beside_data = std::filesystem::path(test::shared_data_dir()) / ".." / "samples";
  if (std::filesystem::is_directory(beside_data / "cloth_ball")) return beside_data.string();
  return std::string(SNAG_SOURCE_DIR) + "/samples";
}

TEST_F(BackendEquality, SameScanOfTheSampleCache) {
  const std::string dir = samples_dir() + "/cloth_ball/";
  io::CacheOptions options;
  options.inputs = {{dir + "cloth.pc2", dir + "cloth_rest.obj", ""}, {dir + "body.pc2", dir + "body_rest.obj", ""}};
  options.frames.first = 14;  // the cloth starts to fold at frame 14: both kinds of events
  options.frames.last = 19;
  const auto source = io::open_cache(options);
  ScanSettings scan;
  const BackendSettings settings = settings_with_certifier(true);
  auto cpu = make_cpu_backend_counting_like_cuda();
  auto cpu_default = make_cpu_backend();
  auto gpu = make_cuda_backend();
  cpu->bind(source->scene(), settings);
  cpu_default->bind(source->scene(), settings);
  gpu->bind(source->scene(), settings);
  const ScanResult cpu_result = scan_cache(*source, *cpu, scan);
  const ScanResult cpu_default_result = scan_cache(*source, *cpu_default, scan);
  const ScanResult gpu_result = scan_cache(*source, *gpu, scan);
  expect_same_events(cpu_result.events, gpu_result.events, "samples/cloth_ball frames 14-19");
  expect_same_events(cpu_default_result.events, gpu_result.events, "samples/cloth_ball frames 14-19, default CPU");
  expect_same_counts(cpu_result.stats.narrow, gpu_result.stats.narrow, "samples/cloth_ball frames 14-19");
  EXPECT_GT(cpu_result.stats.narrow.vf_tests + cpu_result.stats.narrow.ee_tests, 0u);
}

/// The Blender-baked funnel (tests/real_assets/data/cloth_funnel, beside
/// samples/): a self-colliding cloth lying layer on layer in a funnel,
/// frames 33-44, its folds held about 5 mm apart; every frame scanned, with
/// certification.
TEST_F(BackendEquality, SameScanOfTheFunnelCache) {
  const std::string dir =
      (std::filesystem::path(samples_dir()) / ".." / "tests" / "real_assets" / "data" / "cloth_funnel").string() + "/";
  io::CacheOptions options;
  options.inputs = {{dir + "cloth.pc2", dir + "cloth_rest.obj", ""}, {dir + "body.pc2", dir + "body_rest.obj", ""}};
  const auto source = io::open_cache(options);
  ScanSettings scan;
  const BackendSettings settings = settings_with_certifier(true);
  auto cpu = make_cpu_backend_counting_like_cuda();
  auto gpu = make_cuda_backend();
  cpu->bind(source->scene(), settings);
  gpu->bind(source->scene(), settings);
  const ScanResult cpu_result = scan_cache(*source, *cpu, scan);
  const ScanResult gpu_result = scan_cache(*source, *gpu, scan);
  expect_same_events(cpu_result.events, gpu_result.events, "cloth_funnel");
  expect_same_counts(cpu_result.stats.narrow, gpu_result.stats.narrow, "cloth_funnel");
  std::size_t collisions = 0;
  for (const Event& event : cpu_result.events) collisions += event.kind == EventKind::kCollision;
  EXPECT_GT(collisions, 0u);
  EXPECT_GT(cpu_result.events.size() - collisions, 0u) << "intersections";
}

TEST_F(BackendEquality, SameEventsOnClothBall92To93) {
  const test::PlyMesh m92 = test::read_binary_ply(test::shared_data_dir() + "/meshes/cloth_ball92.ply");
  const test::PlyMesh m93 = test::read_binary_ply(test::shared_data_dir() + "/meshes/cloth_ball93.ply");
  ASSERT_EQ(m92.positions.size(), m93.positions.size());
  const Scene scene({make_object("cloth_ball", static_cast<Index>(m92.positions.size()), m92.triangles)});
  for (const bool certified : {false, true}) {
    BackendPair pair(scene, settings_with_certifier(certified));
    const std::string where = certified ? "cloth_ball92->93 certified" : "cloth_ball92->93 fast";
    pair.compare_frame(m92.positions, where);
    pair.compare_step(m92.positions, m93.positions, where);
    pair.compare_frame(m93.positions, where);
  }
}

TEST_F(BackendEquality, AdaptiveGridGivesTheSameEventsAndCounts) {
  // The adaptive grid on both back ends: the same events and counts, and the
  // uniform grid's events (the grid changes the candidates, not the answers).
  const test::PlyMesh m92 = test::read_binary_ply(test::shared_data_dir() + "/meshes/cloth_ball92.ply");
  const test::PlyMesh m93 = test::read_binary_ply(test::shared_data_dir() + "/meshes/cloth_ball93.ply");
  const Scene cloth({make_object("cloth_ball", static_cast<Index>(m92.positions.size()), m92.triangles)});
  const BackendSettings settings = settings_with_certifier(true);
  BackendPair adaptive(cloth, settings, BroadPhaseMethod::kAdaptiveGrid);
  adaptive.compare_step(m92.positions, m93.positions, "cloth_ball92->93 adaptive");
  adaptive.compare_frame(m93.positions, "cloth_ball93 adaptive");
  std::vector<Event> uniform_events, adaptive_events;
  auto uniform = make_cuda_backend();
  uniform->bind(cloth, settings);
  uniform->collisions(m92.positions, m93.positions, uniform_events);
  adaptive.gpu->collisions(m92.positions, m93.positions, adaptive_events);
  expect_same_events(uniform_events, adaptive_events, "cloth_ball92->93, uniform and adaptive GPU grids");
  EXPECT_GT(adaptive.collisions_found, 0u);

  const Soup soup = make_soup(4099, 3, 0.01, 77);
  BackendPair soup_pair(soup.scene, settings, BroadPhaseMethod::kAdaptiveGrid);
  for (std::size_t f = 0; f + 1 < soup.frames.size(); ++f) {
    soup_pair.compare_step(soup.frames[f], soup.frames[f + 1], "soup step " + std::to_string(f) + " adaptive");
    soup_pair.compare_frame(soup.frames[f + 1], "soup frame " + std::to_string(f + 1) + " adaptive");
  }
  EXPECT_GT(soup_pair.collisions_found + soup_pair.intersections_found, 0u);
}

}  // namespace
}  // namespace snag
