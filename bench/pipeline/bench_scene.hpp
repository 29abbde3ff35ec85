// The scenes the pipeline benchmark runs on: a topology and every frame's
// positions, held in memory so that each measurement reads nothing.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "io/open_cache.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/scene.hpp"

namespace snag::bench {

struct BenchScene {
  std::string name;
  Scene scene;
  std::vector<std::vector<Vec3>> frames;  ///< #frames lists of #V global positions; steps are consecutive pairs
  std::size_t steps() const { return frames.empty() ? 0 : frames.size() - 1; }
};

/// Two per-frame meshes of the same topology (any format io::read_mesh_file
/// reads) as one object. Throws InputError for bad files and
/// std::runtime_error when the two frames differ in topology.
BenchScene load_mesh_pair(const std::string& name, const std::string& t0_path, const std::string& t1_path);

/// A cache laid out as the bundled sample (cloth.pc2, cloth_rest.obj,
/// body.pc2, body_rest.obj in `sample_dir`; scripts/bake_cloth_cache.py writes
/// the same) through io::open_cache, named `name`: the frames `frames`
/// selects. Throws InputError for bad files.
BenchScene load_sample(const std::string& name, const std::string& sample_dir, const io::FrameSelection& frames);

}  // namespace snag::bench
