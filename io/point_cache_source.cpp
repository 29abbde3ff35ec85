#include "io/point_cache_source.hpp"

#include "io/mdd_reader.hpp"
#include "io/mesh_file.hpp"
#include "io/mesh_scene.hpp"
#include "io/pc2_reader.hpp"
#include "io/reader_support.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {

PointCacheSource::PointCacheSource(const std::string& cache_path, const std::string& topology_path,
                                   const std::string& name_override)
    : file_(cache_path), topology_path_(topology_path) {
  const std::string extension = lower_extension(cache_path);
  if (extension == "pc2") {
    layout_ = parse_pc2_layout(file_.bytes(), cache_path);
  } else if (extension == "mdd") {
    layout_ = parse_mdd_layout(file_.bytes(), cache_path);
  } else {
    throw InputError({cache_path}, "unknown point cache format '." + extension + "' (expected .pc2 or .mdd)");
  }
  MeshData topology = read_mesh_file(topology_path);
  if (layout_.point_count != topology.positions.size()) {
    throw InputError({cache_path}, with_thousands(layout_.point_count) + " points, but the topology mesh " +
                                       topology_path + " has " + with_thousands(topology.positions.size()) + " vertices");
  }
  scene_ = Scene(make_scene_objects(topology, topology_path, file_stem(topology_path), name_override));
  direct_ = objects_cover_file_in_order(topology.objects, topology.positions.size());
  objects_ = std::move(topology.objects);
}

double PointCacheSource::frame_time(std::size_t i) const { return point_cache_frame_time(file_.bytes(), layout_, i); }

void PointCacheSource::read_frame(std::size_t i, std::vector<Vec3>& positions) const {
  positions.resize(scene_.vertex_count());
  const std::size_t frame_bytes = 12 * layout_.point_count;
  if (direct_) {
    read_point_cache_frame(file_.bytes(), layout_, i, positions.data(), file_.path());
  } else {
    std::vector<Vec3> points(layout_.point_count);
    read_point_cache_frame(file_.bytes(), layout_, i, points.data(), file_.path());
    gather_object_positions(objects_, points.data(), positions.data());
  }
  // Everything up to this frame's end, not this frame alone: the kernel maps
  // pages around each fault (fault-around), so pages of earlier frames come
  // back with the next frame's first fault; releasing from the first frame on
  // drops them again, and costs little where nothing is mapped.
  file_.release(layout_.first_frame_offset, (i + 1) * frame_bytes);
}

std::string PointCacheSource::description() const {
  const std::string kind = layout_.times_offset == static_cast<std::size_t>(-1) ? "PC2 " : "MDD ";
  return kind + file_.path() + " on " + topology_path_;
}

}  // namespace snag::io
