// Overlap volumes of closed pairs: snag::volume at its default voxel size
// against CGAL's corefine_and_compute_intersection + volume (exact
// construction kernel) on the same meshes, both timed in this run; then the
// relative error and time over voxel sizes (the convergence table).
// Pairs: icospheres at several overlaps down to a sliver, a box and a sphere,
// the Stanford bunny (../shared/data/meshes/bunny.ply) against a moved copy of
// itself, and the sample's ball (samples/cloth_ball/body_rest.obj) against a
// moved copy.
//   bench_volume [--quick]    (--quick: the small pairs only)
#include <openvdb/openvdb.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <functional>
#include <string>
#include <vector>

#include "volume/overlap_volume.hpp"
#include "volume/region_measure.hpp"
#include "volume/testing/exact_overlap.hpp"
#include "volume/testing/shapes.hpp"

namespace {

using namespace snag::volume;
namespace vt = snag::volume::testing;
using snag::Vec3;

struct Pair {
  std::string name;
  TriangleMesh a, b;
};

double seconds(const std::function<void()>& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The region a scan would report: the faces in the box where the meshes' boxes meet.
Box region_of(const Pair& pair) { return intersection(mesh_box(pair.a), mesh_box(pair.b)); }

double default_voxel_size(const Pair& pair) {
  const Box region = region_of(pair);
  RegionSide a, b;
  a.mesh = &pair.a;
  b.mesh = &pair.b;
  a.faces = faces_near(pair.a, region);
  b.faces = faces_near(pair.b, region);
  return region_voxel_size(a, b, false, region);
}

}  // namespace

int run(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  std::vector<Pair> pairs;
  const TriangleMesh sphere = vt::icosphere({0, 0, 0}, 1, 4);
  for (double d : {1.0, 1.5, 1.9}) {
    pairs.push_back({"spheres d=" + std::to_string(d).substr(0, 3), sphere, vt::icosphere({d, 0.05, -0.03}, 1, 4)});
  }
  pairs.push_back({"box / sphere", vt::box_mesh({0.4, -0.5, -0.6}, {1.6, 0.7, 0.5}), sphere});
  if (!quick) {
    const TriangleMesh bunny = vt::read_first_object(std::string(SNAG_SHARED_DATA_DIR) + "/meshes/bunny.ply");
    const Box box = mesh_box(bunny);
    const double size = longest_side(box);
    pairs.push_back({"bunny / moved bunny", bunny, vt::moved(bunny, {0.3 * size, 0.05 * size, 0.02 * size})});
    const TriangleMesh ball = vt::read_first_object(std::string(SNAG_SOURCE_DIR) + "/samples/cloth_ball/body_rest.obj");
    pairs.push_back({"ball / moved ball", ball, vt::moved(ball, {0.4, 0.1, 0.05})});
  }

  std::printf("%-22s %8s %12s %10s %12s %10s %8s %10s %8s\n", "pair", "faces", "CGAL volume", "CGAL s", "volume",
              "voxel", "error %", "s", "speed-up");
  for (const Pair& pair : pairs) {
    double exact = 0, measured = 0;
    const double cgal_s = seconds([&] { exact = vt::exact_overlap_volume(pair.a, pair.b); });
    const double h = default_voxel_size(pair);
    OverlapVolume result;
    const double ours_s = seconds([&] { result = overlap_volume(pair.a, pair.b, region_of(pair), h); });
    measured = result.volume;
    std::printf("%-22s %8zu %12.6g %10.3f %12.6g %10.4g %8.3f %10.3f %8.1f\n", pair.name.c_str(),
                pair.a.triangles.size() + pair.b.triangles.size(), exact, cgal_s, measured, result.voxel_size,
                100 * (measured - exact) / exact, ours_s, cgal_s / ours_s);
  }

  std::printf("\nconvergence: relative error and time over voxel sizes (region's longest side / N)\n");
  std::printf("%-22s %6s %10s %10s %10s\n", "pair", "N", "voxel", "error %", "s");
  for (const Pair& pair : pairs) {
    if (pair.name != "spheres d=1.5" && pair.name != "spheres d=1.9" && pair.name != "bunny / moved bunny") continue;
    const double exact = vt::exact_overlap_volume(pair.a, pair.b);
    const double side = longest_side(region_of(pair));
    for (int n : {8, 16, 32, 64, 128}) {
      OverlapVolume result;
      const double s = seconds([&] { result = overlap_volume(pair.a, pair.b, region_of(pair), side / n); });
      std::printf("%-22s %6d %10.4g %10.3f %10.3f\n", pair.name.c_str(), n, result.voxel_size,
                  100 * (result.volume - exact) / exact, s);
    }
  }
  return 0;
}

int main(int argc, char** argv) {
  openvdb::initialize();
  try {
    return run(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "bench_volume: error: %s\n", error.what());
    return 2;
  }
}
