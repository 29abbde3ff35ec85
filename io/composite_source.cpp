#include "io/composite_source.hpp"

#include <algorithm>

#include "io/mesh_scene.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {

CompositeSource::CompositeSource(std::vector<std::unique_ptr<FrameSource>> parts, std::vector<std::string> labels)
    : parts_(std::move(parts)) {
  if (parts_.empty()) throw UsageError("no inputs");
  for (std::size_t p = 1; p < parts_.size(); ++p) {
    if (parts_[p]->frame_count() != parts_[0]->frame_count()) {
      throw InputError({labels[p]}, std::to_string(parts_[p]->frame_count()) + " frames, but " + labels[0] + " has " +
                                        std::to_string(parts_[0]->frame_count()) +
                                        " (all inputs need the same number of frames)");
    }
  }
  std::vector<Object> objects;
  std::size_t vertices = 0;
  for (const auto& part : parts_) {
    first_vertex_.push_back(vertices);
    vertices += part->scene().vertex_count();
    for (const Object& object : part->scene().objects()) objects.push_back(object);
  }
  std::vector<std::string> names;
  for (const Object& object : objects) names.push_back(object.name);
  make_names_unique(names);
  for (std::size_t o = 0; o < objects.size(); ++o) objects[o].name = names[o];
  scene_ = Scene(std::move(objects));
}

void CompositeSource::read_frame(std::size_t i, std::vector<Vec3>& positions) const {
  positions.resize(scene_.vertex_count());
  std::vector<Vec3> part_positions;
  for (std::size_t p = 0; p < parts_.size(); ++p) {
    parts_[p]->read_frame(i, part_positions);
    std::copy(part_positions.begin(), part_positions.end(), positions.begin() + static_cast<std::ptrdiff_t>(first_vertex_[p]));
  }
}

std::string CompositeSource::description() const {
  std::string text;
  for (const auto& part : parts_) text += (text.empty() ? "" : " + ") + part->description();
  return text;
}

}  // namespace snag::io
