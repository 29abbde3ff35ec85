// One mesh file of any supported format, chosen by extension.
#pragma once

#include <string>

#include "io/mesh_data.hpp"

namespace snag::io {

/// True for extensions (lower case, no dot) snag parses itself: obj, ply, stl.
bool is_native_mesh_extension(const std::string& extension);
/// True for any mesh file a sequence may hold: the native ones, and assimp's
/// static formats when snag is built with assimp.
bool is_mesh_extension(const std::string& extension);

/// Reads one mesh file: OBJ, PLY and STL with snag's parsers, other formats
/// through assimp when built with it. Throws InputError for a missing file,
/// an unknown format (naming SNAG_WITH_ASSIMP where that would help) or bad data.
MeshData read_mesh_file(const std::string& path);

}  // namespace snag::io
