// self_overlap_volume(): a closed mesh made of two overlapping closed parts
// (a box folded through another, two spheres) encloses their common space
// twice; its doubled volume is the closed form or CGAL's corefinement of the
// two parts.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include "volume/self_overlap_volume.hpp"
#include "volume/testing/exact_overlap.hpp"
#include "volume/testing/shapes.hpp"

namespace {

using namespace snag::volume;
using snag::Vec3;
namespace vt = snag::volume::testing;

class SelfOverlapVolumeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { openvdb::initialize(); }
};

TEST_F(SelfOverlapVolumeTest, TwoBoxesInOneMeshAtSeveralOverlaps) {
  for (double overlap : {0.5, 0.2}) {
    const TriangleMesh a = vt::box_mesh({0.013, 0.021, 0.007}, {1.013, 1.021, 1.007});
    const TriangleMesh b = vt::box_mesh({1.013 - overlap, 0.3, 0.2}, {2, 0.9, 1.4});
    const double exact = overlap * 0.6 * (1.007 - 0.2);
    const TriangleMesh folded = vt::joined(a, b);
    const double h = overlap / 8;
    const SelfOverlapVolume measured = self_overlap_volume(folded, intersection(mesh_box(a), mesh_box(b)), h);
    // Exact along x; across, the lines at voxel centres see each side of the
    // cross-section 0.6 x 0.807 within one voxel.
    const double bound = overlap * ((0.6 + h) * (0.807 + h) - 0.6 * 0.807);
    EXPECT_NEAR(measured.volume, exact, bound) << "overlap " << overlap;
    ASSERT_TRUE(measured.overlap);
    EXPECT_EQ(measured.overlap->getGridClass(), openvdb::GRID_FOG_VOLUME);
  }
}

TEST_F(SelfOverlapVolumeTest, TwoSpheresInOneMeshAgainstCgal) {
  const TriangleMesh a = vt::icosphere({0, 0, 0}, 1, 3);
  const TriangleMesh b = vt::icosphere({1.2, 0.1, 0}, 0.8, 3);
  const double exact = vt::exact_overlap_volume(a, b);
  const SelfOverlapVolume measured = self_overlap_volume(vt::joined(a, b), {{0.4, -0.7, -0.7}, {0.6, 0.7, 0.7}}, 0.025);
  EXPECT_NEAR(measured.volume, exact, 0.01 * exact);
}

TEST_F(SelfOverlapVolumeTest, AMeshThatDoesNotOverlapItselfHasNone) {
  const TriangleMesh two = vt::joined(vt::box_mesh({0, 0, 0}, {1, 1, 1}), vt::box_mesh({1.5, 0, 0}, {2, 1, 1}));
  EXPECT_EQ(self_overlap_volume(two, {{0.9, 0, 0}, {1.6, 1, 1}}, 0.05).volume, 0);
}

}  // namespace
