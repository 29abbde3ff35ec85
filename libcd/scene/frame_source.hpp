// A cache: a scene whose vertex positions change from frame to frame. Frames
// are read on demand so a scan holds a small window, never the whole cache.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/scene.hpp"

namespace snag {

class FrameSource {
 public:
  virtual ~FrameSource() = default;

  /// Objects and their topology (the same in every frame).
  virtual const Scene& scene() const = 0;
  /// Number of frames available.
  virtual std::size_t frame_count() const = 0;
  /// Time of frame i in the cache's own frame numbering (e.g. 1, 2, 3 ... or
  /// seconds × rate for animated files); used for reporting only.
  virtual double frame_time(std::size_t i) const { return static_cast<double>(i); }
  /// The cache's own 0-based index of frame i (differs from i when a frame
  /// selection is applied); reports name frames by it.
  virtual std::size_t frame_index(std::size_t i) const { return i; }
  /// Reads frame i's global vertex positions (scene().vertex_count() of them)
  /// into `positions`, resizing it. Throws InputError on bad data. Several
  /// threads may read frames at once (a scan reads up to two at a time).
  virtual void read_frame(std::size_t i, std::vector<Vec3>& positions) const = 0;
  /// A short human description of where the frames come from ("PC2 cloth.pc2").
  virtual std::string description() const = 0;
};

}  // namespace snag
