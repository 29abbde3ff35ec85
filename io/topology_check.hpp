// Topology consistency across the frames of a per-frame mesh sequence.
#pragma once

#include <cstddef>
#include <string>

#include "io/mesh_data.hpp"

namespace snag::io {

/// Checks that `frame` (read from `frame_file`, frame index `frame_index`) has
/// the topology of `reference` (frame 0, read from `reference_file`): file
/// vertex count, objects, each object's vertices and triangles. Objects
/// named after their file's stem (files without object names) match whatever
/// their names. Throws InputError naming the frame's file and index and the
/// first difference, e.g. "frame 12: 4,210 triangles, expected 4,212" or
/// "triangle 17 is (3,4,9), expected (3,4,8)".
void check_same_topology(const MeshData& reference, const std::string& reference_file, const MeshData& frame,
                         const std::string& frame_file, std::size_t frame_index);

}  // namespace snag::io
