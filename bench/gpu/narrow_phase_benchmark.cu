#include "bench/gpu/narrow_phase_benchmark.hpp"

#include <algorithm>

#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/cuda/narrow_phase.cuh"

namespace snag {

namespace {

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace

NarrowPhaseBenchmark benchmark_narrow_phase(const Scene& scene, const std::vector<Vec3>& x_t0,
                                            const std::vector<Vec3>& x_t1, const CcdSettings& settings, int warmup,
                                            int runs) {
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  std::vector<TrianglePair> pairs;
  auto broad = make_broad_phase(BroadPhaseMethod::kVirtualSubdivisionGrid);
  BroadPhaseSettings broad_settings;
  broad_settings.thickness = settings.thickness;
  broad->build(scene, broad_settings);
  broad->detect_ccd(x_t0, x_t1, vf, ee);
  broad_settings.thickness = 0;
  broad->build(scene, broad_settings);
  broad->detect_static(x_t1, pairs);

  DeviceBuffer<Vec3> d_x_t0, d_x_t1;
  DeviceBuffer<Triangle> d_triangles;
  DeviceBuffer<Edge> d_edges;
  DeviceBuffer<VertexFaceCandidate> d_vf;
  DeviceBuffer<EdgeEdgeCandidate> d_ee;
  DeviceBuffer<TrianglePair> d_pairs;
  d_x_t0.upload(x_t0);
  d_x_t1.upload(x_t1);
  d_triangles.upload(scene.triangles());
  d_edges.upload(scene.edges());
  d_vf.upload(vf);
  d_ee.upload(ee);
  d_pairs.upload(pairs);
  SNAG_CUDA_CHECK(cudaStreamSynchronize(nullptr));

  CudaNarrowPhase narrow(nullptr);
  NarrowPhaseBenchmark result;
  result.vf_candidates = vf.size();
  result.ee_candidates = ee.size();
  result.triangle_pairs = pairs.size();
  std::vector<double> two_pass, one_pass, screen_only, static_ms;
  for (int run = 0; run < warmup + runs; ++run) {
    for (const CcdPasses passes : {CcdPasses::kScreenThenSearch, CcdPasses::kSinglePass, CcdPasses::kScreenOnly}) {
      std::vector<CcdHit> hits;
      narrow.reset_timings();
      narrow.vertex_face(d_x_t0.data(), d_x_t1.data(), d_triangles.data(), d_vf.data(), vf.size(), settings, passes,
                         hits);
      narrow.edge_edge(d_x_t0.data(), d_x_t1.data(), d_edges.data(), d_ee.data(), ee.size(), settings, passes, hits);
      const NarrowPhaseTimings& t = narrow.timings();
      const double ms = t.screen_ms + t.search_ms + t.compact_ms;
      if (run < warmup) continue;
      if (passes == CcdPasses::kScreenThenSearch) {
        two_pass.push_back(ms);
        result.searched = t.searched;
      } else if (passes == CcdPasses::kSinglePass) {
        one_pass.push_back(ms);
      } else {
        screen_only.push_back(ms);
        result.left_undecided = 0;
        for (const CcdHit& hit : hits) result.left_undecided += hit.result.answer == CcdAnswer::kUncertain;
      }
    }
    std::vector<std::uint32_t> hits;
    TrianglePairCounts counters;
    narrow.reset_timings();
    narrow.triangle_pairs(d_x_t1.data(), d_triangles.data(), d_pairs.data(), pairs.size(), hits, counters);
    if (run >= warmup) static_ms.push_back(narrow.timings().static_ms + narrow.timings().compact_ms);
  }
  result.two_pass_ms = median(two_pass);
  result.one_pass_ms = median(one_pass);
  result.screen_only_ms = median(screen_only);
  result.static_ms = median(static_ms);
  if (result.two_pass_ms > 0)
    result.ccd_tests_per_second = 1e3 * static_cast<double>(vf.size() + ee.size()) / result.two_pass_ms;
  if (result.static_ms > 0)
    result.static_tests_per_second = 1e3 * static_cast<double>(pairs.size()) / result.static_ms;
  return result;
}

}  // namespace snag
