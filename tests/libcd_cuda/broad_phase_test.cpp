// The GPU broad phase (libcd/cuda/cuda_broad_phase) against its oracle, the
// CPU VirtualSubdivisionGrid: the same sorted VF, EE and triangle-pair vectors
// and the same counts, on random soups with very uneven triangles, fast movers
// forcing time halving, thickness > 0, crowded cells (whole and in chunks), the
// samples, and the reference frames cloth_ball92 -> 93; the same for the
// adaptive grid, whose hierarchy of crowded cells is also compared cell by
// cell with the CPU's; a soup around the origin with signed zeros (the
// bounds' reductions); steps of one scene whose levels differ from the step
// before (the subdivision's plan). Also: the exact radius sum does not depend
// on order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "contracted_early_exits.hpp"
#include "gpu_test.hpp"
#include "io/open_cache.hpp"
#include "libcd/broad_phase/virtual_subdivision_grid.hpp"
#include "libcd/core/error.hpp"
#include "libcd/cuda/adaptive_cells.cuh"
#include "libcd/cuda/cuda_broad_phase.cuh"
#include "libcd/cuda/cuda_broad_phase.hpp"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/grid/cell_size.hpp"
#include "libcd/grid/pair_index.hpp"
#include "libcd/grid/radius_sum.hpp"
#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "ply_mesh.hpp"

namespace snag {
namespace {

struct Soup {
  Scene scene;
  std::vector<Vec3> x_t0, x_t1;
};

// n triangles of very uneven sizes (tiny to scene-sized, slivers, degenerate,
// strips sharing edges); when moving, small random motion and ~3% fast movers
// that cross the scene (they force time halving).
Soup random_soup(unsigned seed, int n, bool moving) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> x;
  std::vector<Triangle> tris;
  auto point = [&] { return Vec3{u(rng) * 10, u(rng) * 10, u(rng) * 10}; };
  for (int k = 0; k < n; ++k) {
    const Index base = static_cast<Index>(x.size());
    const double kind = u(rng);
    const Vec3 c = point();
    const double size = kind < 0.5 ? 0.05 : (kind < 0.85 ? 0.4 : (kind < 0.95 ? 2.5 : 6.0));
    const Vec3 a = c, b = c + Vec3{size * (u(rng) - 0.5), size * (u(rng) - 0.5), size * (u(rng) - 0.5)};
    Vec3 d = c + Vec3{size * (u(rng) - 0.5), size * (u(rng) - 0.5), size * (u(rng) - 0.5)};
    if (k % 13 == 5) d = lerp(a, b, 0.3);
    if (k % 17 == 3) d = a + Vec3{1e-4, 0, 0};
    if (k % 7 == 2 && base >= 3) {
      x.push_back(d);
      tris.push_back({base - 1, base - 2, base});
      continue;
    }
    x.push_back(a);
    x.push_back(b);
    x.push_back(d);
    tris.push_back({base, base + 1, base + 2});
  }
  Soup soup{Scene({make_object("soup", static_cast<Index>(x.size()), tris)}), x, x};
  if (moving) {
    for (std::size_t v = 0; v < x.size(); ++v)
      soup.x_t1[v] = x[v] + Vec3{0.3 * (u(rng) - 0.5), 0.3 * (u(rng) - 0.5), 0.3 * (u(rng) - 0.5)};
    for (const Triangle& t : tris) {
      if (u(rng) < 0.03) {
        const Vec3 jump{8 * (u(rng) - 0.5), 8 * (u(rng) - 0.5), 8};
        for (Index v : t) soup.x_t1[v] = x[v] + jump;
      }
    }
  }
  return soup;
}

/// Every count of the two runs (times and memory excluded) must agree.
void expect_same_counts(const BroadPhaseStats& cpu, const BroadPhaseStats& gpu) {
  EXPECT_EQ(cpu.cell_size, gpu.cell_size);
  for (int a = 0; a < 3; ++a) EXPECT_EQ(cpu.grid_dims[a], gpu.grid_dims[a]);
  EXPECT_EQ(cpu.cells_used, gpu.cells_used);
  EXPECT_EQ(cpu.cells_subdivided, gpu.cells_subdivided);
  EXPECT_EQ(cpu.deepest_level, gpu.deepest_level);
  EXPECT_EQ(cpu.root_triangles, gpu.root_triangles);
  EXPECT_EQ(cpu.triangles_subdivided, gpu.triangles_subdivided);
  EXPECT_EQ(cpu.time_halvings, gpu.time_halvings);
  EXPECT_EQ(cpu.oversized_leaves, gpu.oversized_leaves);
  EXPECT_EQ(cpu.triangles_per_level, gpu.triangles_per_level);
  EXPECT_EQ(cpu.subdivided_per_level, gpu.subdivided_per_level);
  EXPECT_EQ(cpu.halved_per_level, gpu.halved_per_level);
  EXPECT_EQ(cpu.leaf_triangles, gpu.leaf_triangles);
  EXPECT_EQ(cpu.registrations, gpu.registrations);
  EXPECT_EQ(cpu.home_registrations, gpu.home_registrations);
  EXPECT_EQ(cpu.phantom_registrations, gpu.phantom_registrations);
  EXPECT_EQ(cpu.duplicate_registrations_removed, gpu.duplicate_registrations_removed);
  EXPECT_EQ(cpu.tests, gpu.tests);
  EXPECT_EQ(cpu.culled_by_boxes, gpu.culled_by_boxes);
  EXPECT_EQ(cpu.same_root_tests, gpu.same_root_tests);
  EXPECT_EQ(cpu.removed_by_time_slots, gpu.removed_by_time_slots);
  EXPECT_EQ(cpu.removed_by_control_bits, gpu.removed_by_control_bits);
  EXPECT_EQ(cpu.removed_by_extended_control_bits, gpu.removed_by_extended_control_bits);
  EXPECT_EQ(cpu.fallback_tests, gpu.fallback_tests);
  EXPECT_EQ(cpu.tests_after_control_bits, gpu.tests_after_control_bits);
  EXPECT_EQ(cpu.duplicate_root_pair_tests, gpu.duplicate_root_pair_tests);
  EXPECT_EQ(cpu.duplicate_culled_tests, gpu.duplicate_culled_tests);
  EXPECT_EQ(cpu.culled_by_dop, gpu.culled_by_dop);
  EXPECT_EQ(cpu.triangle_pairs, gpu.triangle_pairs);
  EXPECT_EQ(cpu.separated_triangle_pairs, gpu.separated_triangle_pairs);
  EXPECT_EQ(cpu.vf_before_culling, gpu.vf_before_culling);
  EXPECT_EQ(cpu.vf_after_culling, gpu.vf_after_culling);
  EXPECT_EQ(cpu.ee_before_culling, gpu.ee_before_culling);
  EXPECT_EQ(cpu.ee_after_culling, gpu.ee_after_culling);
  EXPECT_EQ(cpu.candidates, gpu.candidates);
}

/// CCD and static detection on CPU and GPU; everything must be identical.
/// Returns the number of CCD candidates (so callers can check the case is not trivial).
std::size_t expect_gpu_equals_cpu(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                  BroadPhaseMethod method, const BroadPhaseSettings& settings) {
  const bool subdivide = method != BroadPhaseMethod::kLargestTriangleGrid;
  VirtualSubdivisionGrid cpu(subdivide, method == BroadPhaseMethod::kAdaptiveGrid
                                            ? VirtualSubdivisionGrid::Cells::kAdaptive
                                            : VirtualSubdivisionGrid::Cells::kUniform);
  const std::unique_ptr<BroadPhase> gpu = make_cuda_broad_phase(method);
  cpu.build(scene, settings);
  gpu->build(scene, settings);

  std::vector<VertexFaceCandidate> vf_cpu, vf_gpu;
  std::vector<EdgeEdgeCandidate> ee_cpu, ee_gpu;
  cpu.detect_ccd(x_t0, x_t1, vf_cpu, ee_cpu);
  gpu->detect_ccd(x_t0, x_t1, vf_gpu, ee_gpu);
  EXPECT_EQ(vf_cpu, vf_gpu);
  EXPECT_EQ(ee_cpu, ee_gpu);
  expect_same_counts(cpu.stats(), gpu->stats());
  EXPECT_GT(gpu->stats().memory_bytes, 0u);
  const std::size_t ccd_candidates = vf_cpu.size() + ee_cpu.size();

  std::vector<TrianglePair> pairs_cpu, pairs_gpu;
  cpu.detect_static(x_t1, pairs_cpu);
  gpu->detect_static(x_t1, pairs_gpu);
  EXPECT_EQ(pairs_cpu, pairs_gpu);
  expect_same_counts(cpu.stats(), gpu->stats());

  // Buffers are reused: a second CCD call on the same object gives the same result.
  gpu->detect_ccd(x_t0, x_t1, vf_gpu, ee_gpu);
  EXPECT_EQ(vf_cpu, vf_gpu);
  EXPECT_EQ(ee_cpu, ee_gpu);
  return ccd_candidates;
}

std::string samples_dir() {
  const char* from_environment = std::getenv("SNAG_SAMPLES_DIR");
  if (from_environment != nullptr && *from_environment != '\0') return from_environment;
  return std::string(SNAG_SOURCE_DIR) + "/samples";
}

TEST(CudaBroadPhaseCellSize, ExactRadiusSumIgnoresOrder) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> radii(100000);
  for (double& r : radii) r = std::pow(10.0, -6 + 8 * u(rng));  // twelve decades
  const double size = virtual_subdivision_cell_size(radii, 1.2);
  double naive = 0;
  for (double r : radii) naive += r;
  EXPECT_NEAR(size, 3 * 1.2 * naive / radii.size(), 1e-12 * size);
  std::reverse(radii.begin(), radii.end());
  EXPECT_EQ(virtual_subdivision_cell_size(radii, 1.2), size);
  std::shuffle(radii.begin(), radii.end(), rng);
  EXPECT_EQ(virtual_subdivision_cell_size(radii, 1.2), size);
}

TEST(CudaBroadPhaseFactory, RejectsTheCpuOnlyMethodsNamingThem) {
  for (BroadPhaseMethod method :
       {BroadPhaseMethod::kBruteForce, BroadPhaseMethod::kBoxGrid, BroadPhaseMethod::kSweepAndPrune}) {
    try {
      make_cuda_broad_phase(method);
      ADD_FAILURE() << broad_phase_method_name(method) << " was accepted";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find(broad_phase_method_name(method)), std::string::npos) << e.what();
    }
  }
}

class CudaBroadPhaseTest : public test::GpuTest {};

TEST_F(CudaBroadPhaseTest, RejectsBadSettingsAndSizes) {
  const Soup soup = random_soup(1, 50, false);
  const auto gpu = make_cuda_broad_phase(BroadPhaseMethod::kVirtualSubdivisionGrid);
  std::vector<TrianglePair> pairs;
  EXPECT_THROW(gpu->detect_static(soup.x_t0, pairs), UsageError);
  BroadPhaseSettings bad;
  bad.lambda = 1.0;
  EXPECT_THROW(gpu->build(soup.scene, bad), UsageError);
  gpu->build(soup.scene, BroadPhaseSettings{});
  EXPECT_THROW(gpu->detect_static(std::vector<Vec3>(3), pairs), UsageError);
}

TEST_F(CudaBroadPhaseTest, MatchesCpuOnStaticUnevenSoups) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const Soup soup = random_soup(seed, 3000, false);
    SCOPED_TRACE(seed);
    expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kVirtualSubdivisionGrid, {});
    expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kLargestTriangleGrid, {});
    expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kAdaptiveGrid, {});
  }
}

TEST_F(CudaBroadPhaseTest, MatchesCpuWithFastMoversAndTimeHalving) {
  for (unsigned seed : {11u, 12u}) {
    const Soup soup = random_soup(seed, 4000, true);
    SCOPED_TRACE(seed);
    VirtualSubdivisionGrid probe(true);
    probe.build(soup.scene, {});
    std::vector<VertexFaceCandidate> vf;
    std::vector<EdgeEdgeCandidate> ee;
    probe.detect_ccd(soup.x_t0, soup.x_t1, vf, ee);
    ASSERT_GT(probe.stats().time_halvings, 0u) << "the case must exercise time halving";
    EXPECT_GT(expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kVirtualSubdivisionGrid, {}),
              0u);
    expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kLargestTriangleGrid, {});
    EXPECT_GT(expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kAdaptiveGrid, {}), 0u);
  }
}

// The triangle pairs' separation (BroadPhaseSettings::separate_triangles):
// on and off the GPU's candidates and counts are the CPU's, and on they are
// those of off less the feature pairs of the pairs it proves apart.
TEST_F(CudaBroadPhaseTest, MatchesCpuWithAndWithoutTheTriangleSeparation) {
  const Soup soup = random_soup(13, 4000, true);
  BroadPhaseSettings off;
  off.separate_triangles = false;
  const std::size_t with = expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1,
                                                 BroadPhaseMethod::kVirtualSubdivisionGrid, {});
  const std::size_t without = expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1,
                                                    BroadPhaseMethod::kVirtualSubdivisionGrid, off);
  EXPECT_GT(with, 0u);
  EXPECT_LT(with, without);
  const auto gpu = make_cuda_broad_phase(BroadPhaseMethod::kVirtualSubdivisionGrid);
  gpu->build(soup.scene, {});
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  gpu->detect_ccd(soup.x_t0, soup.x_t1, vf, ee);
  EXPECT_GT(gpu->stats().separated_triangle_pairs, 0u);
  gpu->build(soup.scene, off);
  std::vector<VertexFaceCandidate> vf_off;
  std::vector<EdgeEdgeCandidate> ee_off;
  gpu->detect_ccd(soup.x_t0, soup.x_t1, vf_off, ee_off);
  EXPECT_EQ(gpu->stats().separated_triangle_pairs, 0u);
  EXPECT_TRUE(std::includes(vf_off.begin(), vf_off.end(), vf.begin(), vf.end()));
  EXPECT_TRUE(std::includes(ee_off.begin(), ee_off.end(), ee.begin(), ee.end()));
}

// One broad phase over steps of one scene: each step's subdivision runs in
// the levels of the step before (their sizes with room to spare, read back
// once), and runs level by level again when that plan falls short. The
// motion is scaled: the same step again and a little less (the plan holds),
// three times as much (a level more, then the plan holds), less (a level
// outgrows its room), none (fewer levels, each within its room), and back.
// Every step's candidates and counts are the CPU's.
TEST_F(CudaBroadPhaseTest, StepsMatchCpuWhenTheirLevelsDifferFromTheStepBefore) {
  const Soup soup = random_soup(41, 3000, true);
  VirtualSubdivisionGrid cpu(true);
  const std::unique_ptr<BroadPhase> gpu = make_cuda_broad_phase(BroadPhaseMethod::kVirtualSubdivisionGrid);
  cpu.build(soup.scene, {});
  gpu->build(soup.scene, {});
  std::vector<std::size_t> level_counts;
  for (double scale : {1.0, 1.0, 0.9, 3.0, 3.0, 0.4, 0.0, 1.0}) {
    SCOPED_TRACE(scale);
    std::vector<Vec3> x_t1 = soup.x_t0;
    for (std::size_t v = 0; v < x_t1.size(); ++v) x_t1[v] = soup.x_t0[v] + scale * (soup.x_t1[v] - soup.x_t0[v]);
    std::vector<VertexFaceCandidate> vf_cpu, vf_gpu;
    std::vector<EdgeEdgeCandidate> ee_cpu, ee_gpu;
    cpu.detect_ccd(soup.x_t0, x_t1, vf_cpu, ee_cpu);
    gpu->detect_ccd(soup.x_t0, x_t1, vf_gpu, ee_gpu);
    EXPECT_EQ(vf_cpu, vf_gpu);
    EXPECT_EQ(ee_cpu, ee_gpu);
    expect_same_counts(cpu.stats(), gpu->stats());
    level_counts.push_back(gpu->stats().triangles_per_level.size());
  }
  // The steps differ in their levels (else the plan was never short).
  EXPECT_GT(level_counts[3], level_counts[2]);
  EXPECT_LT(level_counts[6], level_counts[5]);
  std::vector<TrianglePair> pairs_cpu, pairs_gpu;
  cpu.detect_static(soup.x_t1, pairs_cpu);
  gpu->detect_static(soup.x_t1, pairs_gpu);
  EXPECT_EQ(pairs_cpu, pairs_gpu);
  expect_same_counts(cpu.stats(), gpu->stats());
}

// The scene box, the largest radius and the radii's sum, reduced in the
// bounds kernels by atomics on order keys: a soup around the origin, with
// coordinates of both signs, +0 and -0, on both frames.
TEST_F(CudaBroadPhaseTest, MatchesCpuAroundTheOriginWithSignedZeros) {
  for (unsigned seed : {31u, 32u}) {
    Soup soup = random_soup(seed, 2000, true);
    SCOPED_TRACE(seed);
    for (std::vector<Vec3>* frame : {&soup.x_t0, &soup.x_t1}) {
      for (std::size_t v = 0; v < frame->size(); ++v) {
        Vec3& p = (*frame)[v];
        p = p - Vec3{5, 5, 5};
        if (v % 11 == 0) p.x = v % 22 == 0 ? 0.0 : -0.0;
        if (v % 13 == 0) p.z = -0.0;
      }
    }
    EXPECT_GT(expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kVirtualSubdivisionGrid, {}),
              0u);
    expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kLargestTriangleGrid, {});
  }
}

TEST_F(CudaBroadPhaseTest, MatchesCpuWithThicknessAndSafetyLimits) {
  const Soup soup = random_soup(21, 3000, true);
  BroadPhaseSettings settings;
  settings.thickness = 0.05;
  expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kVirtualSubdivisionGrid, settings);
  settings.count_culled_duplicates = true;
  expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kVirtualSubdivisionGrid, settings);
  expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kAdaptiveGrid, settings);
  settings.max_subdivision_levels = 1;
  settings.max_time_halvings = 1;
  settings.lambda = 1.05;
  expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kVirtualSubdivisionGrid, settings);
  settings.adaptive_cell_limit = 2;  // every cell of more than two leaves split, to the deepest level
  settings.adaptive_max_depth = 8;
  expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kAdaptiveGrid, settings);
}

TEST_F(CudaBroadPhaseTest, RejectsBadAdaptiveSettings) {
  const Soup soup = random_soup(1, 50, false);
  const auto gpu = make_cuda_broad_phase(BroadPhaseMethod::kAdaptiveGrid);
  BroadPhaseSettings bad;
  bad.adaptive_cell_limit = 1;
  EXPECT_THROW(gpu->build(soup.scene, bad), UsageError);
  bad = BroadPhaseSettings{};
  bad.adaptive_max_depth = kMaxAdaptiveDepth + 1;
  EXPECT_THROW(gpu->build(soup.scene, bad), UsageError);
}

// n triangles of one size crowded into a unit cube, drifting a little: cells
// of hundreds of leaves, so each cell's tests span many tiles
// (grid/pair_index.hpp), tiles cut by the chunks' row ranges included.
Soup crowded_soup(unsigned seed, int n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> where(0, 1), corner(-0.1, 0.1), drift(-0.02, 0.02);
  Soup soup;
  std::vector<Triangle> triangles;
  for (Index t = 0; t < n; ++t) {
    const Vec3 center{where(rng), where(rng), where(rng)};
    const Vec3 move{drift(rng), drift(rng), drift(rng)};
    for (int k = 0; k < 3; ++k) {
      soup.x_t0.push_back(center + Vec3{corner(rng), corner(rng), corner(rng)});
      soup.x_t1.push_back(soup.x_t0.back() + move);
    }
    triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  soup.scene = Scene({make_object("crowd", static_cast<Index>(soup.x_t0.size()), triangles)});
  return soup;
}

/// The GPU broad phase `method` in chunks of a few percent of the kept tests
/// (more than 10 of them) gives the CPU's CCD candidates vf, ee and counts `cpu`.
void expect_chunked_ccd_equals_cpu(const Soup& soup, BroadPhaseMethod method, const BroadPhaseStats& cpu,
                                   const std::vector<VertexFaceCandidate>& vf,
                                   const std::vector<EdgeEdgeCandidate>& ee) {
  auto chunked = CudaBroadPhase::create(method);
  chunked->build(soup.scene, {});
  chunked->set_chunk_rooms(cpu.triangle_pairs / 25 + 8, vf.size() + ee.size() + 16);
  std::vector<VertexFaceCandidate> vf_chunked;
  std::vector<EdgeEdgeCandidate> ee_chunked;
  chunked->detect_ccd(soup.x_t0, soup.x_t1, vf_chunked, ee_chunked);
  EXPECT_GT(chunked->last_chunks(), 10u);
  EXPECT_EQ(vf_chunked, vf);
  EXPECT_EQ(ee_chunked, ee);
  expect_same_counts(cpu, chunked->stats());
}

/// A device array's first n items appended to `to`.
template <class T>
void append_from_device(const T* from, std::size_t n, std::vector<T>& to) {
  const std::size_t first = to.size();
  to.resize(first + n);
  if (n > 0) ASSERT_EQ(cudaMemcpy(to.data() + first, from, n * sizeof(T), cudaMemcpyDeviceToHost), cudaSuccess);
}

// Unsorted candidates (detect_ccd_on_device with `sorted` false, as the CUDA
// back end asks for them, and sorts only the hits): every candidate of the
// sorted ones, each once, in the order of their triangle pairs, not sorted;
// in one part of the feature stage and in many.
TEST_F(CudaBroadPhaseTest, UnsortedCandidatesAreTheSortedOnesInTheOrderOfTheirPairs) {
  const Soup soup = random_soup(21, 4000, true);
  DeviceBuffer<Vec3> x_t0(0), x_t1(0);
  x_t0.upload(soup.x_t0);
  x_t1.upload(soup.x_t1);
  for (const std::size_t candidate_room : {std::size_t{0}, std::size_t{500}}) {
    const auto gpu = CudaBroadPhase::create(BroadPhaseMethod::kVirtualSubdivisionGrid);
    gpu->build(soup.scene, {});
    gpu->set_chunk_rooms(0, candidate_room);
    std::vector<VertexFaceCandidate> vf, vf_unsorted;
    std::vector<EdgeEdgeCandidate> ee, ee_unsorted;
    gpu->detect_ccd(soup.x_t0, soup.x_t1, vf, ee);
    ASSERT_GT(vf.size(), 100u);
    ASSERT_GT(ee.size(), 100u);
    gpu->detect_ccd_on_device(
        x_t0.data(), x_t1.data(), nullptr,
        [&](const DeviceCandidates& part) {
          append_from_device(part.vf, part.vf_count, vf_unsorted);
          append_from_device(part.ee, part.ee_count, ee_unsorted);
        },
        /*sorted=*/false);
    const std::string where = "candidate room " + std::to_string(candidate_room);
    if (candidate_room > 0) EXPECT_GT(gpu->last_feature_parts(), 10u) << where;
    EXPECT_FALSE(std::is_sorted(vf_unsorted.begin(), vf_unsorted.end())) << where;
    EXPECT_FALSE(std::is_sorted(ee_unsorted.begin(), ee_unsorted.end())) << where;
    std::sort(vf_unsorted.begin(), vf_unsorted.end());
    std::sort(ee_unsorted.begin(), ee_unsorted.end());
    EXPECT_EQ(vf_unsorted, vf) << where;
    EXPECT_EQ(ee_unsorted, ee) << where;
  }
}

/// The CCD query of a candidate (its points in the narrow phase's order).
test::EarlyExitQuery query_of(const Scene& scene, const Soup& soup, const VertexFaceCandidate& c) {
  const Triangle& f = scene.triangles()[c.face];
  const Vec3 *x0 = soup.x_t0.data(), *x1 = soup.x_t1.data();
  return {{x0[c.vertex], x0[f[0]], x0[f[1]], x0[f[2]], x1[c.vertex], x1[f[0]], x1[f[1]], x1[f[2]]}, false};
}
test::EarlyExitQuery query_of(const Scene& scene, const Soup& soup, const EdgeEdgeCandidate& c) {
  const Edge &a = scene.edges()[c.edge_a], &b = scene.edges()[c.edge_b];
  const Vec3 *x0 = soup.x_t0.data(), *x1 = soup.x_t1.data();
  return {{x0[a[0]], x0[a[1]], x0[b[0]], x0[b[1]], x1[a[0]], x1[a[1]], x1[b[0]], x1[b[1]]}, true};
}

/// Whether the host's CCD early exits decide a query kNo.
bool host_early_exits_rule_out(const test::EarlyExitQuery& q, const CcdSettings& settings) {
  const Vec3* p = q.points.data();
  CcdResult result;
  const bool decided = q.edge_edge
                           ? edge_edge_early_exit(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings, &result)
                           : vertex_face_early_exit(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings, &result);
  return decided && result.answer == CcdAnswer::kNo;
}

/// The candidates that the CCD early exits, contracted as the screen runs
/// them (contracted_early_exits.hpp), do not rule out; `host_differs`
/// counts the candidates on which the host's early exits decide otherwise.
template <class Candidate>
std::vector<Candidate> left_by_early_exits(const Scene& scene, const Soup& soup, const std::vector<Candidate>& all,
                                           const CcdSettings& settings, std::size_t& host_differs) {
  std::vector<test::EarlyExitQuery> queries;
  for (const Candidate& c : all) queries.push_back(query_of(scene, soup, c));
  const std::vector<bool> ruled_out = test::contracted_early_exits_rule_out(queries, settings);
  std::vector<Candidate> left;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (!ruled_out[i]) left.push_back(all[i]);
    if (ruled_out[i] != host_early_exits_rule_out(queries[i], settings)) ++host_differs;
  }
  return left;
}

// Screened candidates (detect_ccd_on_device with a screen, as the CUDA back
// end asks for them): exactly the candidates that the CCD early exits,
// contracted as the screen is built, do not rule out (those the host's
// early exits leave, but for a few decided otherwise at the margin of a
// rounding bound: tests/libcd_cuda/screen_contraction_test.cpp shows the
// contracted ones conservative), with the counts of the unscreened detection; at
// thickness 0 and above it, in one part of the feature stage and in many.
// With a threshold (screen_above), a detection in one part whose candidates
// of each kind are at most that many is not screened, and one with more of
// either kind, or in many parts, is; each part says which (screened).
// With and without the triangle pairs' separation: with it, many candidates
// the early exits would rule out are gone before the screen (on this soup
// about 70% of the vertex-face candidates are left, against under half
// without it).
TEST_F(CudaBroadPhaseTest, ScreenedCandidatesAreThoseTheEarlyExitsLeave) {
  const Soup soup = random_soup(21, 4000, true);
  DeviceBuffer<Vec3> x_t0(0), x_t1(0);
  x_t0.upload(soup.x_t0);
  x_t1.upload(soup.x_t1);
  for (const bool separate : {false, true}) {
    for (const double thickness : {0.0, 0.01}) {
      CcdSettings settings;
      settings.thickness = thickness;
      for (const std::size_t candidate_room : {std::size_t{0}, std::size_t{500}}) {
        const std::string where = std::string(separate ? "separated, " : "") + "thickness " +
                                  std::to_string(thickness) + ", candidate room " + std::to_string(candidate_room);
        const auto gpu = CudaBroadPhase::create(BroadPhaseMethod::kVirtualSubdivisionGrid);
        BroadPhaseSettings broad;
        broad.thickness = thickness;
        broad.separate_triangles = separate;
        gpu->build(soup.scene, broad);
        gpu->set_chunk_rooms(0, candidate_room);
        std::vector<VertexFaceCandidate> vf, vf_screened;
        std::vector<EdgeEdgeCandidate> ee, ee_screened;
        gpu->detect_ccd(soup.x_t0, soup.x_t1, vf, ee);
        const BroadPhaseStats unscreened = gpu->stats();
        std::size_t parts = 0, parts_screened = 0;  // the parts that say the screen ran
        auto detect_screened = [&](std::size_t screen_above) {
          vf_screened.clear();
          ee_screened.clear();
          parts = parts_screened = 0;
          gpu->detect_ccd_on_device(
              x_t0.data(), x_t1.data(), nullptr,
              [&](const DeviceCandidates& part) {
                append_from_device(part.vf, part.vf_count, vf_screened);
                append_from_device(part.ee, part.ee_count, ee_screened);
                ++parts;
                parts_screened += part.screened;
              },
              /*sorted=*/true, &settings, screen_above);
          std::sort(vf_screened.begin(), vf_screened.end());
          std::sort(ee_screened.begin(), ee_screened.end());
        };
        std::size_t host_differs = 0;
        const std::vector<VertexFaceCandidate> vf_left =
            left_by_early_exits(soup.scene, soup, vf, settings, host_differs);
        const std::vector<EdgeEdgeCandidate> ee_left =
            left_by_early_exits(soup.scene, soup, ee, settings, host_differs);
        EXPECT_LE(host_differs, (vf.size() + ee.size()) / 1000) << where;
        // The case must have candidates the early exits rule out and candidates they leave.
        ASSERT_GT(vf_left.size(), 10u) << where;
        ASSERT_GT(ee_left.size(), 10u) << where;
        ASSERT_LT(vf_left.size(), separate ? vf.size() * 9 / 10 : vf.size() / 2) << where;
        ASSERT_LT(ee_left.size(), separate ? ee.size() * 9 / 10 : ee.size() / 2) << where;
        const std::size_t most = std::max(vf.size(), ee.size());
        for (const std::size_t screen_above : {most, most - 1}) {
          detect_screened(screen_above);
          const bool screens = candidate_room > 0 || most > screen_above;
          EXPECT_EQ(vf_screened, screens ? vf_left : vf) << where << ", screen above " << screen_above;
          EXPECT_EQ(ee_screened, screens ? ee_left : ee) << where << ", screen above " << screen_above;
          EXPECT_EQ(parts_screened, screens ? parts : 0u) << where << ", screen above " << screen_above;
          EXPECT_EQ(gpu->stats().candidates, unscreened.candidates) << where << ", screen above " << screen_above;
        }
        detect_screened(0);
        EXPECT_EQ(vf_screened, vf_left) << where;
        EXPECT_EQ(ee_screened, ee_left) << where;
        EXPECT_EQ(parts_screened, parts) << where;
        if (candidate_room > 0) EXPECT_GT(gpu->last_feature_parts(), 10u) << where;
        const BroadPhaseStats& screened = gpu->stats();
        EXPECT_EQ(screened.vf_before_culling, unscreened.vf_before_culling) << where;
        EXPECT_EQ(screened.vf_after_culling, unscreened.vf_after_culling) << where;
        EXPECT_EQ(screened.ee_before_culling, unscreened.ee_before_culling) << where;
        EXPECT_EQ(screened.ee_after_culling, unscreened.ee_after_culling) << where;
        EXPECT_EQ(screened.candidates, unscreened.candidates) << where;
        EXPECT_EQ(screened.separated_triangle_pairs, unscreened.separated_triangle_pairs) << where;
        EXPECT_EQ(screened.separated_triangle_pairs > 0, separate) << where;
      }
    }
  }
}

TEST_F(CudaBroadPhaseTest, MatchesCpuWhereCellsHoldManyTiles) {
  const Soup soup = crowded_soup(31, 6000);
  VirtualSubdivisionGrid probe(true);
  probe.build(soup.scene, {});
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  probe.detect_ccd(soup.x_t0, soup.x_t1, vf, ee);
  const BroadPhaseStats& crowd = probe.stats();
  ASSERT_GT(crowd.registrations, 3 * kPairTileSide * crowd.cells_used) << "cells must span several tiles";
  expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kVirtualSubdivisionGrid, {});

  // Row ranges start and end inside tiles.
  expect_chunked_ccd_equals_cpu(soup, BroadPhaseMethod::kVirtualSubdivisionGrid, crowd, vf, ee);
}

TEST_F(CudaBroadPhaseTest, AdaptiveGridMatchesCpuWhereCellsAreCrowded) {
  const Soup soup = crowded_soup(31, 6000);
  VirtualSubdivisionGrid probe(true, VirtualSubdivisionGrid::Cells::kAdaptive);
  probe.build(soup.scene, {});
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  probe.detect_ccd(soup.x_t0, soup.x_t1, vf, ee);
  const BroadPhaseStats& crowd = probe.stats();
  ASSERT_GT(crowd.cells_subdivided, 100u) << "the case must split crowded cells";
  ASSERT_GE(crowd.deepest_level, 2);
  expect_gpu_equals_cpu(soup.scene, soup.x_t0, soup.x_t1, BroadPhaseMethod::kAdaptiveGrid, {});

  // Each pass skips the tiles that hold none of its root range's tests.
  expect_chunked_ccd_equals_cpu(soup, BroadPhaseMethod::kAdaptiveGrid, crowd, vf, ee);
}

/// The GPU's hierarchy of crowded cells against build_adaptive_cells: the same
/// test cells in the same order, the same members (each cell's stuck and
/// pushed ones by root on the GPU, stably: the CPU's by leaf id), the same counts.
void expect_same_hierarchy(const std::vector<Leaf>& leaves, const GridSpec& grid, int depth, std::size_t limit) {
  SCOPED_TRACE("depth " + std::to_string(depth) + ", cell limit " + std::to_string(limit));
  const AdaptiveCells cpu = build_adaptive_cells(leaves, grid, depth, limit);
  DeviceBuffer<Leaf> d_leaves(0);
  d_leaves.upload(leaves);
  DeviceAdaptiveCells gpu(nullptr);
  build_adaptive_cells_on_device(d_leaves.data(), leaves.size(), grid, depth, limit, gpu, nullptr);
  SNAG_CUDA_CHECK(cudaDeviceSynchronize());
  EXPECT_EQ(gpu.registrations, cpu.registrations);
  EXPECT_EQ(gpu.cells_subdivided, cpu.cells_subdivided);
  EXPECT_EQ(gpu.stuck_registrations, cpu.stuck_registrations);
  EXPECT_EQ(gpu.deepest_level, cpu.deepest_level);
  std::vector<FineBlock> blocks(leaves.size());
  gpu.blocks.download(blocks.data(), blocks.size());
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    ASSERT_TRUE(blocks[i].lo == cpu.blocks[i].lo && blocks[i].hi == cpu.blocks[i].hi) << "leaf " << i;
  }
  ASSERT_EQ(gpu.cell_count, cpu.cells.size());
  ASSERT_EQ(gpu.member_count, cpu.members.size());
  std::vector<TestCell> cells(gpu.cell_count);
  std::vector<AdaptiveMember> members(gpu.member_count);
  gpu.cells.download(cells.data(), cells.size());
  gpu.members.download(members.data(), members.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const TestCell &g = cells[c], &e = cpu.cells[c];
    ASSERT_TRUE(g.first == e.first && g.count == e.count && g.stuck == e.stuck && g.coord == e.coord &&
                g.level == e.level)
        << "test cell " << c << ": GPU (" << g.first << ", " << g.count << ", " << g.stuck << ", level " << g.level
        << "), CPU (" << e.first << ", " << e.count << ", " << e.stuck << ", level " << e.level << ")";
  }
  std::vector<std::uint32_t> expected = cpu.members;
  for (const TestCell& cell : cpu.cells) {
    auto by_root = [&](std::uint32_t x, std::uint32_t y) { return leaves[x].triangle.root < leaves[y].triangle.root; };
    const auto begin = expected.begin() + static_cast<std::ptrdiff_t>(cell.first);
    std::stable_sort(begin, begin + cell.stuck, by_root);
    std::stable_sort(begin + cell.stuck, begin + cell.count, by_root);
  }
  for (std::size_t m = 0; m < members.size(); ++m) {
    const Leaf& leaf = leaves[expected[m]];
    ASSERT_EQ(members[m].leaf, expected[m]) << "member " << m;
    ASSERT_EQ(members[m].root, leaf.triangle.root) << "member " << m;
    ASSERT_TRUE(members[m].slot_depth == leaf.triangle.slot_depth && members[m].slot_index == leaf.triangle.slot_index &&
                members[m].block.lo == cpu.blocks[expected[m]].lo)
        << "member " << m;
  }
}

TEST_F(CudaBroadPhaseTest, AdaptiveHierarchyIsTheCpusCellByCell) {
  const Soup crowd = crowded_soup(41, 3000);
  const Soup uneven = random_soup(42, 3000, true);
  for (const Soup* soup : {&crowd, &uneven}) {
    VirtualSubdivisionGrid cpu(true);
    cpu.build(soup->scene, {});
    std::vector<VertexFaceCandidate> vf;
    std::vector<EdgeEdgeCandidate> ee;
    cpu.detect_ccd(soup->x_t0, soup->x_t1, vf, ee);
    for (const auto& [depth, limit] : std::vector<std::pair<int, std::size_t>>{
             {4, 64}, {0, 64}, {8, 2}, {2, 1000000}, {3, 16}}) {
      expect_same_hierarchy(cpu.leaves(), cpu.grid(), depth, limit);
    }
  }
}

TEST_F(CudaBroadPhaseTest, MatchesCpuOnSamples) {
  io::CacheOptions options;
  const std::string dir = samples_dir() + "/cloth_ball/";
  options.inputs.push_back({dir + "cloth.pc2", dir + "cloth_rest.obj", ""});
  options.inputs.push_back({dir + "body.pc2", dir + "body_rest.obj", ""});
  const auto source = io::open_cache(options);
  ASSERT_GE(source->frame_count(), 4u);
  std::vector<Vec3> x_t0, x_t1;
  std::size_t candidates = 0;
  const std::size_t last = source->frame_count() - 1;
  for (std::size_t f : {std::size_t(0), last / 3, 2 * last / 3, last - 1}) {
    SCOPED_TRACE(f);
    source->read_frame(f, x_t0);
    source->read_frame(f + 1, x_t1);
    candidates += expect_gpu_equals_cpu(source->scene(), x_t0, x_t1, BroadPhaseMethod::kVirtualSubdivisionGrid, {});
  }
  EXPECT_GT(candidates, 0u);
}

TEST_F(CudaBroadPhaseTest, MatchesCpuOnClothBall92To93) {
  const std::string dir = test::shared_data_dir() + "/meshes/";
  const test::PlyMesh m92 = test::read_binary_ply(dir + "cloth_ball92.ply");
  const test::PlyMesh m93 = test::read_binary_ply(dir + "cloth_ball93.ply");
  ASSERT_EQ(m92.positions.size(), m93.positions.size());
  const Scene scene({make_object("cloth_ball", static_cast<Index>(m92.positions.size()), m92.triangles)});
  EXPECT_GT(expect_gpu_equals_cpu(scene, m92.positions, m93.positions, BroadPhaseMethod::kVirtualSubdivisionGrid, {}),
            0u);
  BroadPhaseSettings thick;
  thick.thickness = 1e-3;
  expect_gpu_equals_cpu(scene, m92.positions, m93.positions, BroadPhaseMethod::kVirtualSubdivisionGrid, thick);
  expect_gpu_equals_cpu(scene, m92.positions, m93.positions, BroadPhaseMethod::kLargestTriangleGrid, {});
  EXPECT_GT(expect_gpu_equals_cpu(scene, m92.positions, m93.positions, BroadPhaseMethod::kAdaptiveGrid, {}), 0u);
}

}  // namespace
}  // namespace snag
