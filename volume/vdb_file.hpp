// The .vdb files snag-volume writes: one per frame, its grids named.
#pragma once

#include <map>
#include <string>

#include "volume/region_measure.hpp"

namespace snag::volume {

/// The grids of one frame by name. Level sets of one object from several
/// regions join into one grid (their minimum: the object where any box saw it).
class FrameGrids {
 public:
  void add(const NamedGrid& grid);
  bool empty() const { return grids_.empty(); }
  std::size_t size() const { return grids_.size(); }
  /// Writes every grid to `path` (OpenVDB's file format, world units, grids
  /// in name order) with the frame index as file metadata "snag_frame".
  /// Throws std::runtime_error (OpenVDB's IoError) when the file cannot be written.
  void write(const std::string& path, std::size_t frame) const;
  void clear() { grids_.clear(); }

 private:
  std::map<std::string, openvdb::FloatGrid::Ptr> grids_;
};

/// "DIR/STEM_0027.vdb": the file of cache frame `frame`.
std::string vdb_path(const std::string& directory, const std::string& stem, std::size_t frame);

}  // namespace snag::volume
