#include "io/selected_frames_source.hpp"

#include <algorithm>

#include "libcd/core/error.hpp"

namespace snag::io {

SelectedFramesSource::SelectedFramesSource(std::unique_ptr<FrameSource> source, const FrameSelection& selection)
    : source_(std::move(source)), selection_(selection) {
  const std::size_t available = source_->frame_count();
  if (selection_.step == 0) throw UsageError("frame selection step must be at least 1");
  if (selection_.first >= available) {
    throw UsageError("frame selection starts at frame " + std::to_string(selection_.first) + " but " +
                     source_->description() + " has " + std::to_string(available) + " frames");
  }
  const std::size_t last = std::min(selection_.last, available - 1);
  count_ = (last - selection_.first) / selection_.step + 1;
}

std::string SelectedFramesSource::description() const {
  return source_->description() + " (frames " + std::to_string(selection_.first) + " to " +
         std::to_string(source_index(count_ - 1)) + " step " + std::to_string(selection_.step) + ")";
}

}  // namespace snag::io
