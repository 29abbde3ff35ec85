// Several caches read as one: their objects side by side, frame by frame.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "libcd/scene/frame_source.hpp"

namespace snag::io {

class CompositeSource : public FrameSource {
 public:
  /// Concatenates the parts' objects in order, renaming repeated object names
  /// deterministically (make_names_unique). `labels` name the parts in errors
  /// (their input paths). Frame times come from the first part.
  /// Throws InputError naming two parts whose frame counts differ.
  CompositeSource(std::vector<std::unique_ptr<FrameSource>> parts, std::vector<std::string> labels);

  const Scene& scene() const override { return scene_; }
  std::size_t frame_count() const override { return parts_.front()->frame_count(); }
  double frame_time(std::size_t i) const override { return parts_.front()->frame_time(i); }
  std::size_t frame_index(std::size_t i) const override { return parts_.front()->frame_index(i); }
  void read_frame(std::size_t i, std::vector<Vec3>& positions) const override;
  std::string description() const override;

 private:
  std::vector<std::unique_ptr<FrameSource>> parts_;
  std::vector<std::size_t> first_vertex_;  ///< per part, its first global vertex
  Scene scene_;
};

}  // namespace snag::io
