// A report's cache, opened again for its positions: the 3D view of the HTML
// page and the marked meshes draw the scanned objects at chosen frames. The
// cache is opened with the report's own frame selection and weld
// (header.settings.frames and .weld), so that frame indices and vertex ids
// are those of the report, and its objects are checked against the header's.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "exporters/digest.hpp"
#include "io/open_cache.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/frame_source.hpp"

namespace snag::exporters {

class FramePositions {
 public:
  /// Opens the cache that `options.inputs` name (with their topology meshes,
  /// names and animation sampling) for the report `digest`; the options'
  /// frames and weld are replaced by the report's. Throws UsageError when
  /// there are no inputs, InputError for a bad cache (as io::open_cache does)
  /// and InputError naming the report when the cache's objects (names in
  /// order, vertex and triangle counts) or frame count differ from the
  /// header's.
  FramePositions(const ReportDigest& digest, io::CacheOptions options);
  ~FramePositions();
  FramePositions(const FramePositions&) = delete;
  FramePositions& operator=(const FramePositions&) = delete;

  /// The objects and their triangles; global vertex ids index the positions below.
  const Scene& scene() const;
  /// Whether the report scanned cache frame `frame` (a cache frame index).
  bool has_frame(std::size_t frame) const;
  /// Global vertex positions (#V, scene units) at cache frame index `frame`.
  /// Throws UsageError naming the report when it did not scan that frame.
  std::vector<Vec3> positions(std::size_t frame) const;
  /// positions() of each of `frames`, by cache frame index.
  std::map<std::size_t, std::vector<Vec3>> positions(const std::set<std::size_t>& frames) const;

 private:
  std::string report_path_;
  std::unique_ptr<FrameSource> source_;
  std::map<std::size_t, std::size_t> position_of_index_;  // cache frame index -> position in the source
};

}  // namespace snag::exporters
