// select_view: what the 3D view draws within a size budget. Oracles: the
// region faces and the faces near a region are always drawn; what is left out
// lies away from every region; the bytes stay under the budget.
#include "exporters/html_decimation.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "tests/html/html_fixtures.hpp"

namespace snag::test {
namespace {

using exporters::select_view;
using exporters::view_bytes;
using exporters::ViewRegion;

constexpr std::size_t kGrid = 200;  // 80,000 triangles, 40,401 vertices

std::vector<ViewRegion> region_at(std::size_t i, std::size_t j, std::size_t frames) {
  std::vector<ViewRegion> regions;
  const double s = 1.0 / double(kGrid);
  for (std::size_t f = 0; f < frames; ++f)
    regions.push_back({f, {{double(i) * s, double(j) * s, 0}, {double(i + 1) * s, double(j + 1) * s, 0.05}},
                       {quad_faces(kGrid, i, j)}});
  return regions;
}

bool drawn(const exporters::ViewSelection& selection, std::size_t face) {
  return std::binary_search(selection.faces[0].begin(), selection.faces[0].end(), static_cast<std::uint32_t>(face));
}

TEST(HtmlDecimation, KeepsEverythingWithinBudget) {
  const exporters::HtmlScene scene = grid_scene(kGrid, 3);
  const auto selection = select_view(scene, region_at(10, 10, 3), std::size_t{64} << 20);
  EXPECT_EQ(selection.frames, 3u);
  EXPECT_FALSE(selection.decimated);
  EXPECT_EQ(selection.faces[0].size(), 2 * kGrid * kGrid);
}

TEST(HtmlDecimation, SamplesFacesAwayFromRegionsAndKeepsThoseNear) {
  const exporters::HtmlScene scene = grid_scene(kGrid, 4);
  const std::size_t budget = 2u << 20;  // the whole grid takes about 1.3 MB of triangles + 0.65 MB a frame
  const auto selection = select_view(scene, region_at(50, 60, 4), budget);
  ASSERT_EQ(selection.frames, 4u);
  EXPECT_TRUE(selection.decimated);
  EXPECT_LE(view_bytes(scene, selection.faces, selection.frames), budget);
  EXPECT_LT(selection.faces[0].size(), 2 * kGrid * kGrid);
  // The margin is at least 5 % of the frame's diagonal (about 0.07, 14 quads): every face within 10 quads is drawn.
  for (std::size_t i = 40; i <= 60; ++i)
    for (std::size_t j = 50; j <= 70; ++j)
      for (std::size_t f : quad_faces(kGrid, i, j)) ASSERT_TRUE(drawn(selection, f)) << "quad " << i << ", " << j;
  // Far away, some faces are left out but some are drawn, as context.
  std::size_t far_drawn = 0, far = 0;
  for (std::size_t i = 150; i < kGrid; ++i)
    for (std::size_t j = 150; j < kGrid; ++j)
      for (std::size_t f : quad_faces(kGrid, i, j)) {
        ++far;
        far_drawn += drawn(selection, f);
      }
  EXPECT_GT(far_drawn, 0u);
  EXPECT_LT(far_drawn, far);
}

TEST(HtmlDecimation, DropsTheLastFramesWhenTheRegionsAloneDoNotFit) {
  exporters::HtmlScene scene = grid_scene(kGrid, 8);
  // Regions over the whole grid in every frame: nothing is far, so frames must go.
  std::vector<ViewRegion> regions;
  for (std::size_t f = 0; f < 8; ++f) regions.push_back({f, {{0, 0, 0}, {1, 1, 1}}, {std::vector<std::size_t>{0, 1}}});
  const std::size_t budget = 4u << 20;
  const auto selection = select_view(scene, regions, budget);
  EXPECT_GE(selection.frames, 1u);
  EXPECT_LT(selection.frames, 8u);
  EXPECT_LE(view_bytes(scene, selection.faces, selection.frames), budget);
  EXPECT_TRUE(drawn(selection, 0));
  EXPECT_TRUE(drawn(selection, 1));
}

TEST(HtmlDecimation, KeepsRegionFacesEvenOverBudget) {
  const exporters::HtmlScene scene = grid_scene(kGrid, 2);
  const auto selection = select_view(scene, region_at(100, 100, 2), 64);
  EXPECT_EQ(selection.frames, 1u);
  for (std::size_t f : quad_faces(kGrid, 100, 100)) EXPECT_TRUE(drawn(selection, f));
}

}  // namespace
}  // namespace snag::test
