// Formats read through assimp (glTF 2.0, FBX, Collada, and the rest of what
// assimp imports). Available when SNAG_HAVE_ASSIMP is 1 (config.hpp).
#pragma once

#include <memory>
#include <string>

#include "io/mesh_data.hpp"
#include "io/open_cache.hpp"

namespace snag::io {

/// True for extensions (lower case, without the dot) that are read through
/// assimp rather than snag's own parsers: "gltf", "glb", "fbx", "dae", ...
bool is_assimp_extension(const std::string& extension);

/// True for files that carry their own animation (glTF, GLB, FBX, Collada)
/// and so become a whole cache on their own.
bool is_animated_extension(const std::string& extension);

/// Reads one static mesh file (one frame of a sequence) through assimp, with
/// node transforms applied at the rest pose. Throws InputError.
MeshData read_mesh_with_assimp(const std::string& path);

/// Opens one animated file as a cache: node transforms, morph targets and
/// skinning are evaluated by snag at each sampled time (assimp only loads the
/// data). Each mesh node becomes a named object. Sampling follows
/// options.sample_rate / start_time / end_time. Throws InputError.
std::unique_ptr<FrameSource> open_animated_file(const InputSpec& input, const CacheOptions& options);

}  // namespace snag::io
