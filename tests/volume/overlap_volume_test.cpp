// overlap_volume() against closed forms (boxes: a box; two spheres: the lens
// of the sphere caps) and against CGAL's exact corefinement of the same
// meshes, at several overlaps down to a sliver.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <string>

#include "volume/overlap_volume.hpp"
#include "volume/region_measure.hpp"
#include "volume/testing/exact_overlap.hpp"
#include "volume/testing/shapes.hpp"

namespace {

using namespace snag::volume;
using snag::Vec3;
namespace vt = snag::volume::testing;

// The lens two spheres of radii r1 and r2, centres d apart, share.
double lens_volume(double r1, double r2, double d) {
  return M_PI * std::pow(r1 + r2 - d, 2) * (d * d + 2 * d * r2 - 3 * r2 * r2 + 2 * d * r1 + 6 * r1 * r2 - 3 * r1 * r1) /
         (12 * d);
}

// The region the scan would report: the faces that cross, approximated here by
// the box where the two meshes' boxes meet.
Box crossing_box(const TriangleMesh& a, const TriangleMesh& b) { return intersection(mesh_box(a), mesh_box(b)); }

// The tolerance this method reaches on an overlap `voxels_across` voxels thick:
// 1% from 12 voxels across; the smeared surface of thinner overlaps costs up to 2.5%.
double tolerance(double exact, double voxels_across) { return (voxels_across >= 12 ? 0.01 : 0.025) * exact; }

class OverlapVolumeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { openvdb::initialize(); }
};

TEST_F(OverlapVolumeTest, TwoBoxesAtSeveralOverlapsDownToASliver) {
  const TriangleMesh a = vt::box_mesh({0, 0, 0}, {1, 1, 1});
  for (double overlap : {0.6, 0.3, 0.1}) {
    const TriangleMesh b = vt::box_mesh({1 - overlap, 0.2, 0.1}, {2 - overlap, 1.3, 0.8});
    const double exact = overlap * 0.8 * 0.7;
    EXPECT_DOUBLE_EQ(vt::exact_overlap_volume(a, b), exact) << "the oracle agrees with the closed form";
    // At least 4 voxels across the thinnest side.
    const double h = std::min(0.05, overlap / 4);
    const OverlapVolume measured = overlap_volume(a, b, crossing_box(a, b), h);
    EXPECT_NEAR(measured.volume, exact, tolerance(exact, overlap / h)) << "overlap " << overlap;
  }
}

TEST_F(OverlapVolumeTest, TwoSpheresAgainstTheLensAndCgal) {
  const double r = 1;
  const TriangleMesh a = vt::icosphere({0, 0, 0}, r, 4);
  for (double d : {1.0, 1.5, 1.8}) {
    const TriangleMesh b = vt::icosphere({d, 0.05, -0.03}, r, 4);
    const double exact = vt::exact_overlap_volume(a, b);
    const double lens = lens_volume(r, r, std::sqrt(d * d + 0.05 * 0.05 + 0.03 * 0.03));
    EXPECT_NEAR(exact, lens, 0.03 * lens) << "the meshes are close to the spheres";
    const OverlapVolume measured = overlap_volume(a, b, crossing_box(a, b), 0.025);
    EXPECT_NEAR(measured.volume, exact, tolerance(exact, (2 * r - d) / 0.025)) << "d " << d;
  }
}

TEST_F(OverlapVolumeTest, ABoxAndASphereAgainstCgal) {
  const TriangleMesh box = vt::box_mesh({0.4, -0.5, -0.6}, {1.6, 0.7, 0.5});
  const TriangleMesh sphere = vt::icosphere({0, 0, 0}, 1, 4);
  const double exact = vt::exact_overlap_volume(box, sphere);
  const OverlapVolume measured = overlap_volume(box, sphere, crossing_box(box, sphere), 0.025);
  EXPECT_NEAR(measured.volume, exact, 0.01 * exact);
}

TEST_F(OverlapVolumeTest, TheBunnyAgainstAMovedCopyOfItselfAgainstCgal) {
  // A real mesh (5,002 faces) at the default voxel size of its region.
  const TriangleMesh bunny = vt::read_first_object(std::string(SNAG_SHARED_DATA_DIR) + "/meshes/bunny.ply");
  const double size = longest_side(mesh_box(bunny));
  const TriangleMesh moved = vt::moved(bunny, {0.3 * size, 0.05 * size, 0.02 * size});
  const double exact = vt::exact_overlap_volume(bunny, moved);
  const Box region = crossing_box(bunny, moved);
  RegionSide a, b;
  a.mesh = &bunny;
  b.mesh = &moved;
  a.faces = faces_near(bunny, region);
  b.faces = faces_near(moved, region);
  const OverlapVolume measured = overlap_volume(bunny, moved, region, region_voxel_size(a, b, false, region));
  EXPECT_NEAR(measured.volume, exact, 0.01 * exact);
}

TEST_F(OverlapVolumeTest, GrowsFromASmallRegionToTheWholeLens) {
  // The region's faces lie on the intersection circle; the lens reaches 0.25 beyond it on each side.
  const TriangleMesh a = vt::icosphere({0, 0, 0}, 1, 4);
  const TriangleMesh b = vt::icosphere({1.5, 0, 0}, 1, 4);
  const Box ring{{0.7, -0.67, -0.67}, {0.8, 0.67, 0.67}};
  const OverlapVolume measured = overlap_volume(a, b, ring, 0.025);
  const double exact = vt::exact_overlap_volume(a, b);
  EXPECT_NEAR(measured.volume, exact, 0.01 * exact);
  ASSERT_TRUE(measured.overlap);
  EXPECT_EQ(measured.overlap->getGridClass(), openvdb::GRID_LEVEL_SET);
}

TEST_F(OverlapVolumeTest, CountsOnlyThePieceOfItsRegion) {
  // Two boxes overlapping a long bar at both ends: two pieces, one per region.
  const TriangleMesh bar = vt::box_mesh({0, 0, 0}, {4, 1, 1});
  const TriangleMesh ends =
      vt::joined(vt::box_mesh({-0.5, 0.2, 0.2}, {0.5, 0.8, 0.8}), vt::box_mesh({3.7, 0.1, 0.1}, {4.5, 0.9, 0.9}));
  const OverlapVolume left = overlap_volume(bar, ends, {{0, 0.2, 0.2}, {0.5, 0.8, 0.8}}, 0.05);
  EXPECT_NEAR(left.volume, 0.5 * 0.6 * 0.6, tolerance(0.18, 10)) << "not both pieces (0.372)";
  const OverlapVolume right = overlap_volume(bar, ends, {{3.7, 0.1, 0.1}, {4, 0.9, 0.9}}, 0.05);
  EXPECT_NEAR(right.volume, 0.3 * 0.8 * 0.8, tolerance(0.192, 6));
}

TEST_F(OverlapVolumeTest, MeshesThatDoNotOverlapHaveNoVolume) {
  const TriangleMesh a = vt::box_mesh({0, 0, 0}, {1, 1, 1});
  const TriangleMesh b = vt::box_mesh({2, 0, 0}, {3, 1, 1});
  EXPECT_EQ(overlap_volume(a, b, {{1, 0, 0}, {2, 1, 1}}, 0.1).volume, 0);
}

}  // namespace
