#include "io/mesh_sequence_source.hpp"

#include "io/mapped_file.hpp"
#include "io/mesh_file.hpp"
#include "io/mesh_scene.hpp"
#include "io/reader_support.hpp"
#include "io/topology_check.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {

/// "cloth_0001" -> "cloth": a sequence's name from its first file.
static std::string sequence_name(const std::string& first_file) {
  std::string name = file_stem(first_file);
  while (!name.empty() && ((name.back() >= '0' && name.back() <= '9') || name.back() == '_' || name.back() == '.' ||
                           name.back() == '-')) {
    name.pop_back();
  }
  return name.empty() ? file_stem(first_file) : name;
}

MeshSequenceSource::MeshSequenceSource(std::vector<FrameFile> files, const std::string& name_override,
                                       std::string description)
    : files_(std::move(files)), description_(std::move(description)) {
  if (files_.empty()) throw InputError({description_}, "no frames");
  reference_ = read_mesh_file(files_[0].path);
  if (files_.size() > 1 && objects_cover_file_in_order(reference_.objects, reference_.positions.size())) {
    const std::string extension = lower_extension(files_[0].path);
    if (extension == "ply") ply_layout_ = PlyFrameLayout::of(MappedFile(files_[0].path).bytes(), files_[0].path);
    if (extension == "obj") obj_layout_.emplace(MappedFile(files_[0].path).bytes());
  }
  const std::string default_name = files_.size() == 1 ? file_stem(files_[0].path) : sequence_name(files_[0].path);
  scene_ = Scene(make_scene_objects(reference_, files_[0].path, default_name, name_override));
}

void MeshSequenceSource::read_frame(std::size_t i, std::vector<Vec3>& positions) const {
  positions.resize(scene_.vertex_count());
  if (i == 0) {  // read for the topology already
    gather_object_positions(reference_.objects, reference_.positions.data(), positions.data());
    return;
  }
  if (ply_layout_ || obj_layout_) {
    const MappedFile file(files_[i].path);
    if (ply_layout_ && ply_layout_->read_positions(file.bytes(), positions)) return;
    if (obj_layout_ && obj_layout_->read_positions(file.bytes(), positions)) return;
  }
  const MeshData frame = read_mesh_file(files_[i].path);
  check_same_topology(reference_, files_[0].path, frame, files_[i].path, i);
  gather_object_positions(frame.objects, frame.positions.data(), positions.data());
}

}  // namespace snag::io
