#include "volume/vdb_file.hpp"

#include <openvdb/io/File.h>
#include <openvdb/tools/Composite.h>

#include <cstdio>

namespace snag::volume {

void FrameGrids::add(const NamedGrid& named) {
  auto found = grids_.find(named.name);
  if (found == grids_.end()) {
    openvdb::FloatGrid::Ptr copy = named.grid->deepCopy();
    copy->setName(named.name);
    grids_.emplace(named.name, copy);
    return;
  }
  openvdb::FloatGrid::Ptr other = named.grid->deepCopy();
  openvdb::tools::compMin(*found->second, *other);
}

void FrameGrids::write(const std::string& path, std::size_t frame) const {
  openvdb::GridPtrVec grids;
  for (const auto& [name, grid] : grids_) grids.push_back(grid);
  openvdb::MetaMap meta;
  meta.insertMeta("snag_frame", openvdb::Int64Metadata(static_cast<openvdb::Int64>(frame)));
  openvdb::io::File file(path);
  file.write(grids, meta);
  file.close();
}

std::string vdb_path(const std::string& directory, const std::string& stem, std::size_t frame) {
  char number[32];
  std::snprintf(number, sizeof number, "_%04zu.vdb", frame);
  return directory + "/" + stem + number;
}

}  // namespace snag::volume
