// A cache made of a topology mesh and a point cache (PC2 or MDD).
#pragma once

#include <string>
#include <vector>

#include "io/mapped_file.hpp"
#include "io/mesh_data.hpp"
#include "io/point_cache.hpp"
#include "libcd/scene/frame_source.hpp"

namespace snag::io {

class PointCacheSource : public FrameSource {
 public:
  /// Maps `cache_path` (.pc2 or .mdd, by extension), reads `topology_path` and
  /// checks the cache's point count against the topology's vertex count.
  /// Throws InputError naming the file at fault.
  PointCacheSource(const std::string& cache_path, const std::string& topology_path, const std::string& name_override);

  const Scene& scene() const override { return scene_; }
  std::size_t frame_count() const override { return layout_.frame_count; }
  double frame_time(std::size_t i) const override;
  /// Reads frame i from the mapped file. Throws InputError for NaN/Inf.
  void read_frame(std::size_t i, std::vector<Vec3>& positions) const override;
  std::string description() const override;

 private:
  MappedFile file_;
  PointCacheLayout layout_;
  std::string topology_path_;
  std::vector<MeshObject> objects_;
  bool direct_ = false;  ///< objects take every point in order: no gather needed
  Scene scene_;
};

}  // namespace snag::io
