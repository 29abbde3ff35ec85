// Stanford PLY reader: ASCII, binary little-endian and binary big-endian.
#pragma once

#include <string>
#include <string_view>

#include "io/mesh_data.hpp"

namespace snag::io {

/// Parses a PLY file held in memory.
/// - `vertex` element: x, y, z may be any scalar type (float and double
///   usual), in any order, among any other properties. float32 values are
///   widened to double exactly; in ASCII files a `float` property is rounded
///   to float32 first, so ASCII and binary files of the same data agree.
/// - `face` element: a list property `vertex_indices` (or `vertex_index`) with
///   any integer count type (uchar, int ...) and index type (int, uint ...);
///   polygons are fan-triangulated from their first vertex (convex assumption).
/// - Other elements and properties are skipped.
/// One object named after `file`'s stem, holding every file vertex.
/// Throws InputError (line for ASCII, byte offset for binary) for a bad
/// header, counts that disagree with the file size (checked before any
/// allocation), truncated data, NaN/Inf coordinates, indices out of range,
/// faces of fewer than 3 vertices and meshes without faces.
MeshData parse_ply(std::string_view bytes, const std::string& file);

/// Reads a PLY file (memory-mapped). Throws InputError.
MeshData read_ply(const std::string& path);

}  // namespace snag::io
