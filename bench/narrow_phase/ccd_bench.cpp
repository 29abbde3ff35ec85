// Queries per second of the conservative CCD kernels, on one thread: over the
// reference query set (Wang et al. 2021, ../shared/data/ccd-queries/), over
// the real candidates of a cloth step (../shared/data/meshes/cloth_ball92.ply
// -> cloth_ball93.ply through the virtual subdivision grid broad phase), and
// over random near-contact pairs (a vertex or an edge steered to pass a small
// gap off the other primitive at one instant; their straight paths usually
// cross it at another). The counters report the mix of answers.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "io/ccd_query_csv.hpp"
#include "io/ply_reader.hpp"
#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"

namespace snag {
namespace {

using Points = std::array<Vec3, 8>;

CcdResult run(bool is_edge_edge, const Points& x, const CcdSettings& settings) {
  return is_edge_edge ? edge_edge_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings)
                      : vertex_face_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], settings);
}

const std::vector<io::CcdQuery>& query_set() {
  static const std::vector<io::CcdQuery> queries =
      io::read_ccd_query_tree(std::string(SNAG_SHARED_DATA_DIR) + "/ccd-queries");
  return queries;
}

void query_set_bench(benchmark::State& state, bool is_edge_edge) {
  std::vector<Points> points;
  for (const io::CcdQuery& q : query_set()) {
    if (q.is_edge_edge == is_edge_edge) points.push_back(q.points);
  }
  const CcdSettings settings;
  for (auto _ : state) {
    for (const Points& x : points) benchmark::DoNotOptimize(run(is_edge_edge, x, settings));
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * points.size()));
}

void count_answer(const CcdResult& r, int64_t counts[3]) {
  counts[0] += r.answer == CcdAnswer::kNo;
  counts[1] += r.answer == CcdAnswer::kYes;
  counts[2] += r.answer == CcdAnswer::kUncertain;
}

void report_answers(benchmark::State& state, const int64_t counts[3]) {
  const double total = static_cast<double>(counts[0] + counts[1] + counts[2]);
  state.counters["no"] = counts[0] / total;
  state.counters["yes"] = counts[1] / total;
  state.counters["uncertain"] = counts[2] / total;
}

// The vertex-face and edge-edge candidates of one real cloth step, as the
// CPU back end would test them.
struct RealCandidates {
  std::vector<Points> vertex_face, edge_edge;
};

const RealCandidates& real_candidates() {
  static const RealCandidates candidates = [] {
    const std::string meshes = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/";
    const io::MeshData frame_t0 = io::read_ply(meshes + "cloth_ball92.ply");
    const io::MeshData frame_t1 = io::read_ply(meshes + "cloth_ball93.ply");
    std::vector<Triangle> triangles;
    for (const io::MeshObject& object : frame_t0.objects) {
      for (const Triangle& f : object.triangles) {
        triangles.push_back({object.vertices[f[0]], object.vertices[f[1]], object.vertices[f[2]]});
      }
    }
    const Scene scene({make_object("cloth", static_cast<Index>(frame_t0.positions.size()), triangles)});
    BroadPhaseSettings settings;
    settings.threads = 1;
    const auto broad = make_broad_phase(BroadPhaseMethod::kVirtualSubdivisionGrid);
    broad->build(scene, settings);
    std::vector<VertexFaceCandidate> vf;
    std::vector<EdgeEdgeCandidate> ee;
    const std::vector<Vec3>& x_t0 = frame_t0.positions;
    const std::vector<Vec3>& x_t1 = frame_t1.positions;
    broad->detect_ccd(x_t0, x_t1, vf, ee);
    RealCandidates out;
    for (const VertexFaceCandidate& c : vf) {
      const Triangle& f = scene.triangles()[c.face];
      out.vertex_face.push_back({x_t0[c.vertex], x_t0[f[0]], x_t0[f[1]], x_t0[f[2]], x_t1[c.vertex], x_t1[f[0]],
                                 x_t1[f[1]], x_t1[f[2]]});
    }
    for (const EdgeEdgeCandidate& c : ee) {
      const Edge& a = scene.edges()[c.edge_a];
      const Edge& b = scene.edges()[c.edge_b];
      out.edge_edge.push_back({x_t0[a[0]], x_t0[a[1]], x_t0[b[0]], x_t0[b[1]], x_t1[a[0]], x_t1[a[1]], x_t1[b[0]],
                               x_t1[b[1]]});
    }
    return out;
  }();
  return candidates;
}

void real_candidates_bench(benchmark::State& state, bool is_edge_edge) {
  const std::vector<Points>& points = is_edge_edge ? real_candidates().edge_edge : real_candidates().vertex_face;
  const CcdSettings settings;
  int64_t counts[3] = {0, 0, 0};
  for (auto _ : state) {
    for (const Points& x : points) count_answer(run(is_edge_edge, x, settings), counts);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * points.size()));
  state.counters["candidates"] = static_cast<double>(points.size());
  report_answers(state, counts);
}

// Random pairs that come within `gap` of touching: a random primitive, and the
// other moved so that, at a random time, the closest feature sits `gap` off
// the first along its normal.
std::vector<Points> near_contactes(bool is_edge_edge, double gap, int count) {
  std::mt19937_64 rng(is_edge_edge ? 2 : 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0), coordinate(-1.0, 1.0);
  std::vector<Points> out;
  while (static_cast<int>(out.size()) < count) {
    Points x;
    for (Vec3& p : x) p = {coordinate(rng), coordinate(rng), coordinate(rng)};
    const double t = unit(rng);
    const auto at = [t](const Vec3& x_t0, const Vec3& x_t1) { return (1 - t) * x_t0 + t * x_t1; };
    Vec3 target, normal, moving;
    if (is_edge_edge) {
      const Vec3 a0 = at(x[0], x[4]), a1 = at(x[1], x[5]), b0 = at(x[2], x[6]), b1 = at(x[3], x[7]);
      const double u = unit(rng), v = unit(rng);
      normal = cross(a1 - a0, b1 - b0);
      target = (1 - u) * a0 + u * a1;
      moving = (1 - v) * b0 + v * b1;
    } else {
      const Vec3 a = at(x[1], x[5]), b = at(x[2], x[6]), c = at(x[3], x[7]);
      double u = unit(rng), v = unit(rng);
      if (u + v > 1) u = 1 - u, v = 1 - v;
      normal = cross(b - a, c - a);
      target = (1 - u - v) * a + u * b + v * c;
      moving = at(x[0], x[4]);
    }
    const double length = std::sqrt(squared_norm(normal));
    if (length < 1e-3 || t < 1e-3) continue;
    const Vec3 shift = (target + (gap / length) * normal - moving) / t;
    if (is_edge_edge) {
      x[6] = x[6] + shift;
      x[7] = x[7] + shift;
    } else {
      x[4] = x[4] + shift;
    }
    out.push_back(x);
  }
  return out;
}

void near_contact_bench(benchmark::State& state, bool is_edge_edge) {
  const double gap = std::ldexp(1.0, -static_cast<int>(state.range(0)));
  const std::vector<Points> points = near_contactes(is_edge_edge, gap, 1000);
  const CcdSettings settings;
  int64_t counts[3] = {0, 0, 0};
  for (auto _ : state) {
    for (const Points& x : points) count_answer(run(is_edge_edge, x, settings), counts);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * points.size()));
  report_answers(state, counts);
}

BENCHMARK_CAPTURE(query_set_bench, vertex_face, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(query_set_bench, edge_edge, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(real_candidates_bench, vertex_face, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(real_candidates_bench, edge_edge, true)->Unit(benchmark::kMillisecond);
// Gap 2^-10 and 2^-30 (scene size about 1).
BENCHMARK_CAPTURE(near_contact_bench, vertex_face, false)->Arg(10)->Arg(30)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(near_contact_bench, edge_edge, true)->Arg(10)->Arg(30)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace snag

BENCHMARK_MAIN();
