// STL reader (ASCII and binary). STL stores each triangle's corners
// separately; exactly equal positions are welded into shared vertices.
#pragma once

#include <string>
#include <string_view>

#include "io/mesh_data.hpp"

namespace snag::io {

/// Parses an STL file held in memory. A file whose size is exactly
/// 84 + 50 × (triangle count in its header) is binary (even when it starts
/// with "solid", as some exporters write); otherwise it must be ASCII
/// ("solid ... facet ... outer loop / vertex x y z ×3 / endloop ... endsolid").
/// Corners with exactly equal coordinates (+0 and -0 equal) become one vertex,
/// numbered in order of first appearance, so the same triangles give the
/// same topology in every frame. One object named after `file`'s stem.
/// Throws InputError for truncated or malformed data, NaN/Inf coordinates,
/// and files without triangles.
MeshData parse_stl(std::string_view bytes, const std::string& file);

/// Reads an STL file (memory-mapped). Throws InputError.
MeshData read_stl(const std::string& path);

}  // namespace snag::io
