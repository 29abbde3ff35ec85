// The CPU back end's options change counts, never events: the box grid with
// the 2D filter (the default) against the virtual subdivision grid without
// it (the CUDA back end's configuration), on a real cloth step and on
// intersecting random soups, for every thread count.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "bench/broad_phase/binary_ply.hpp"
#include "libcd/cpu/cpu_backend.hpp"

namespace snag {
namespace {

bool same_events(const std::vector<Event>& a, const std::vector<Event>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].type != b[i].type || a[i].a != b[i].a || a[i].b != b[i].b || a[i].toi_lo != b[i].toi_lo ||
        a[i].toi_hi != b[i].toi_hi || a[i].certainty != b[i].certainty)
      return false;
  }
  return true;
}

/// Events of both configurations and of the default with 1 and 2 threads.
void expect_same_events(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                        const std::string& what, std::size_t& collisions, std::size_t& intersections) {
  CpuBackendOptions gpu_like;
  gpu_like.broad_phase = BroadPhaseMethod::kVirtualSubdivisionGrid;
  gpu_like.frame_static_test = false;
  std::vector<std::vector<Event>> ccd, dcd;
  for (int k = 0; k < 3; ++k) {
    auto backend = make_cpu_backend(k == 2 ? gpu_like : CpuBackendOptions{});
    BackendSettings settings;
    settings.threads = k == 0 ? 1 : 2;
    backend->bind(scene, settings);
    ccd.emplace_back();
    dcd.emplace_back();
    backend->collisions(x_t0, x_t1, ccd.back());
    backend->intersections(x_t1, dcd.back());
  }
  EXPECT_TRUE(same_events(ccd[0], ccd[1])) << what << ": collisions differ between 1 and 2 threads";
  EXPECT_TRUE(same_events(dcd[0], dcd[1])) << what << ": intersections differ between 1 and 2 threads";
  EXPECT_TRUE(same_events(ccd[1], ccd[2])) << what << ": collisions differ from the VSS grid's";
  EXPECT_TRUE(same_events(dcd[1], dcd[2])) << what << ": intersections differ from the unfiltered test's";
  collisions += ccd[1].size();
  intersections += dcd[1].size();
}

TEST(CpuBackend, OptionsChangeNoEventOnTheThickClothStep) {
  const std::string dir = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/thick-cloth/";
  bench::PlyMesh t0 = bench::read_binary_ply(dir + "t0.ply");
  bench::PlyMesh t1 = bench::read_binary_ply(dir + "t1.ply");
  const Scene scene({make_object("cloth", static_cast<Index>(t0.vertices.size()), t0.triangles)});
  std::size_t collisions = 0, intersections = 0;
  expect_same_events(scene, t0.vertices, t1.vertices, "thick cloth", collisions, intersections);
}

TEST(CpuBackend, OptionsChangeNoEventOnIntersectingSoups) {
  std::size_t collisions = 0, intersections = 0;
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Vec3> x_t0, x_t1;
    std::vector<Triangle> tris;
    for (Index k = 0; k < 600; ++k) {
      const Vec3 c{u(rng), u(rng), u(rng)};
      for (int i = 0; i < 3; ++i) {
        const Vec3 p = c + Vec3{0.1 * (u(rng) - 0.5), 0.1 * (u(rng) - 0.5), 0.1 * (u(rng) - 0.5)};
        x_t0.push_back(p);
        x_t1.push_back(p + Vec3{0.05 * (u(rng) - 0.5), 0.05 * (u(rng) - 0.5), 0.05 * (u(rng) - 0.5)});
      }
      // Every third triangle shares a vertex with the one before: fans.
      tris.push_back({3 * k, 3 * k + 1, k % 3 == 1 ? 3 * k - 1 : 3 * k + 2});
    }
    const Scene scene({make_object("soup", static_cast<Index>(x_t0.size()), tris)});
    expect_same_events(scene, x_t0, x_t1, "soup " + std::to_string(seed), collisions, intersections);
  }
  EXPECT_GT(collisions, 0u);
  EXPECT_GT(intersections, 0u);
}

// Sheets from smooth (most neighbour pairs left out by the vertex fans) to
// crumpled (neighbours that intersect, fans that fold), folded over onto
// themselves at the end frame: the same intersections as pair by pair.
TEST(CpuBackend, OptionsChangeNoEventOnCrumpledSheets) {
  std::size_t collisions = 0, intersections = 0;
  for (const double bump : {0.05, 0.6, 2.0}) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    const Index side = 30;
    std::vector<Vec3> x_t0, x_t1;
    std::vector<Triangle> tris;
    for (Index j = 0; j < side; ++j) {
      for (Index i = 0; i < side; ++i) {
        const Vec3 p{double(i) + 0.4 * u(rng), double(j) + 0.4 * u(rng), bump * u(rng)};
        x_t0.push_back(p);
        // Folded about x = 15 back over the sheet, 0.3 above it.
        x_t1.push_back(p.x < 15 ? p : Vec3{30 - p.x, p.y, 0.3 + bump * u(rng)});
      }
    }
    for (Index j = 0; j + 1 < side; ++j) {
      for (Index i = 0; i + 1 < side; ++i) {
        const Index v = j * side + i;
        tris.push_back({v, v + 1, v + side + 1});
        tris.push_back({v, v + side + 1, v + side});
      }
    }
    const Scene scene({make_object("sheet", static_cast<Index>(x_t0.size()), tris)});
    expect_same_events(scene, x_t0, x_t1, "sheet, bump " + std::to_string(bump), collisions, intersections);
    std::vector<Event> flat_events;
    auto backend = make_cpu_backend();
    backend->bind(scene, BackendSettings{});
    backend->intersections(x_t0, flat_events);
    if (bump == 0.05) {
      EXPECT_TRUE(flat_events.empty());
      EXPECT_GT(backend->stats().static_broad.left_out_apart, 5 * backend->stats().narrow.triangle_tests);
    }
  }
  EXPECT_GT(intersections, 0u);
}

}  // namespace
}  // namespace snag
