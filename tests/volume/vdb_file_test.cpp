// The .vdb files of a frame read back with OpenVDB's own reader: the named
// grids, their class, the frame metadata, world units (the overlap's volume
// measured again from the file), and one object's level sets from two regions
// joined into one grid.
#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetMeasure.h>
#include <unistd.h>

#include <filesystem>

#include "volume/overlap_volume.hpp"
#include "volume/testing/shapes.hpp"
#include "volume/vdb_file.hpp"

namespace {

using namespace snag::volume;
namespace vt = snag::volume::testing;

TEST(VdbFile, ReadsBackWithOpenVdbsReader) {
  openvdb::initialize();
  const TriangleMesh a = vt::box_mesh({0, 0, 0}, {1, 1, 1});
  const TriangleMesh b = vt::box_mesh({0.5, 0.25, 0.25}, {1.5, 0.75, 0.75});
  const TriangleMesh c = vt::box_mesh({-0.5, 0.25, 0.25}, {0.25, 0.75, 0.75});
  const OverlapVolume ab = overlap_volume(a, b, {{0.5, 0.25, 0.25}, {1, 0.75, 0.75}}, 0.05);
  const OverlapVolume ac = overlap_volume(a, c, {{0, 0.25, 0.25}, {0.25, 0.75, 0.75}}, 0.05);
  FrameGrids grids;
  grids.add({"a", ab.level_set_a});
  grids.add({"b", ab.level_set_b});
  grids.add({"region_3_overlap", ab.overlap});
  grids.add({"a", ac.level_set_a});
  EXPECT_EQ(grids.size(), 3u);

  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("snag_vdb_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = vdb_path(dir.string(), "shot", 27);
  EXPECT_EQ(path, dir.string() + "/shot_0027.vdb");
  grids.write(path, 27);

  openvdb::io::File file(path);
  file.open();
  openvdb::GridPtrVecPtr read = file.getGrids();
  const openvdb::MetaMap::Ptr meta = file.getMetadata();
  file.close();
  std::filesystem::remove_all(dir);

  ASSERT_EQ(read->size(), 3u);
  std::vector<std::string> names;
  for (const openvdb::GridBase::Ptr& grid : *read) names.push_back(grid->getName());
  EXPECT_EQ(names, (std::vector<std::string>{"a", "b", "region_3_overlap"}));
  EXPECT_EQ(meta->metaValue<openvdb::Int64>("snag_frame"), 27);
  for (const openvdb::GridBase::Ptr& grid : *read) {
    EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET) << grid->getName();
    EXPECT_DOUBLE_EQ(grid->voxelSize()[0], 0.05);
  }
  const auto overlap = openvdb::gridPtrCast<openvdb::FloatGrid>((*read)[2]);
  ASSERT_TRUE(overlap);
  EXPECT_NEAR(openvdb::tools::levelSetVolume(*overlap), ab.volume, 1e-9) << "world units";
  EXPECT_NEAR(ab.volume, 0.125, 0.025 * 0.125);
  // Object a's grid holds both boxes' level sets: negative deep inside a near b and near c.
  const auto a_grid = openvdb::gridPtrCast<openvdb::FloatGrid>((*read)[0]);
  auto accessor = a_grid->getConstAccessor();
  EXPECT_LT(accessor.getValue(openvdb::Coord(18, 10, 10)), 0);  // (0.9, 0.5, 0.5), near b
  EXPECT_LT(accessor.getValue(openvdb::Coord(2, 10, 10)), 0);   // (0.1, 0.5, 0.5), near c
}

}  // namespace
