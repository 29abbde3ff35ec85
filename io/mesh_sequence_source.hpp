// A cache made of one mesh file per frame, all with the same topology.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/frame_files.hpp"
#include "io/mesh_data.hpp"
#include "io/obj_reader.hpp"
#include "io/ply_reader.hpp"
#include "libcd/scene/frame_source.hpp"

namespace snag::io {

class MeshSequenceSource : public FrameSource {
 public:
  /// Reads the first file for the topology; the others are read on demand.
  /// `name_override` names the objects (see make_scene_objects); `description`
  /// says what was opened ("OBJ sequence cache/cloth_%04d.obj").
  /// Throws InputError for an empty list or a bad first file.
  MeshSequenceSource(std::vector<FrameFile> files, const std::string& name_override, std::string description);

  const Scene& scene() const override { return scene_; }
  std::size_t frame_count() const override { return files_.size(); }
  double frame_time(std::size_t i) const override { return files_[i].number; }
  /// Parses file i only, checks its topology against frame 0 and gathers its
  /// objects' positions; frame 0's come from the read that gave the topology.
  /// A binary PLY file whose bytes but the coordinates are frame 0's (see
  /// PlyFrameLayout), or an OBJ file whose lines but the vertices' are
  /// (ObjFrameLayout), has only its coordinates read. Throws InputError.
  void read_frame(std::size_t i, std::vector<Vec3>& positions) const override;
  std::string description() const override { return description_; }

 private:
  std::vector<FrameFile> files_;
  MeshData reference_;  ///< frame 0: the topology, and the positions read_frame(0) gives
  /// Frame 0's bytes but its coordinates, for binary PLY files whose objects
  /// hold every vertex in file order (so that the scene's positions are the
  /// file's).
  std::optional<PlyFrameLayout> ply_layout_;
  std::optional<ObjFrameLayout> obj_layout_;  ///< the same for OBJ files
  Scene scene_;
  std::string description_;
};

}  // namespace snag::io
