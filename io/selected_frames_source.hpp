// A frame selection (first, last, step) applied to a cache.
#pragma once

#include <memory>

#include "io/open_cache.hpp"
#include "libcd/scene/frame_source.hpp"

namespace snag::io {

class SelectedFramesSource : public FrameSource {
 public:
  /// Frames first, first + step, ... up to min(last, frame_count - 1) of `source`.
  /// Throws UsageError when the selection starts past the last frame.
  SelectedFramesSource(std::unique_ptr<FrameSource> source, const FrameSelection& selection);

  const Scene& scene() const override { return source_->scene(); }
  std::size_t frame_count() const override { return count_; }
  double frame_time(std::size_t i) const override { return source_->frame_time(source_index(i)); }
  std::size_t frame_index(std::size_t i) const override { return source_->frame_index(source_index(i)); }
  void read_frame(std::size_t i, std::vector<Vec3>& positions) const override {
    source_->read_frame(source_index(i), positions);
  }
  std::string description() const override;

 private:
  std::size_t source_index(std::size_t i) const { return selection_.first + i * selection_.step; }
  std::unique_ptr<FrameSource> source_;
  FrameSelection selection_;
  std::size_t count_ = 0;
};

}  // namespace snag::io
