#include "bench/pipeline/bench_scene.hpp"

#include <stdexcept>

#include "io/mesh_file.hpp"
#include "io/open_cache.hpp"

namespace snag::bench {

namespace {

/// All of a file's triangles with file vertex ids.
std::vector<Triangle> file_triangles(const io::MeshData& mesh) {
  std::vector<Triangle> triangles;
  for (const io::MeshObject& object : mesh.objects)
    for (const Triangle& local : object.triangles)
      triangles.push_back({object.vertices[local[0]], object.vertices[local[1]], object.vertices[local[2]]});
  return triangles;
}

}  // namespace

BenchScene load_mesh_pair(const std::string& name, const std::string& t0_path, const std::string& t1_path) {
  io::MeshData t0 = io::read_mesh_file(t0_path);
  io::MeshData t1 = io::read_mesh_file(t1_path);
  std::vector<Triangle> triangles = file_triangles(t0);
  if (t0.positions.size() != t1.positions.size() || triangles != file_triangles(t1))
    throw std::runtime_error(t0_path + " and " + t1_path + " differ in topology");
  BenchScene bench;
  bench.name = name;
  bench.scene = Scene({make_object(name, static_cast<Index>(t0.positions.size()), std::move(triangles))});
  bench.frames.push_back(std::move(t0.positions));
  bench.frames.push_back(std::move(t1.positions));
  return bench;
}

BenchScene load_sample(const std::string& name, const std::string& sample_dir, const io::FrameSelection& frames) {
  io::CacheOptions options;
  options.inputs.push_back({sample_dir + "/cloth.pc2", sample_dir + "/cloth_rest.obj", "cloth", {}});
  options.inputs.push_back({sample_dir + "/body.pc2", sample_dir + "/body_rest.obj", "body", {}});
  options.frames = frames;
  const auto source = io::open_cache(options);
  BenchScene bench;
  bench.name = name;
  bench.scene = source->scene();
  bench.frames.resize(source->frame_count());
  for (std::size_t f = 0; f < bench.frames.size(); ++f) source->read_frame(f, bench.frames[f]);
  return bench;
}

}  // namespace snag::bench
