// Small helpers shared by the readers: file names, number formatting for
// messages, and turning a file's triangles into a named object.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "io/mesh_data.hpp"

namespace snag::io {

/// "dir/cloth_0001.obj" -> "cloth_0001".
std::string file_stem(const std::string& path);
/// "dir/a.OBJ" -> "obj" (lower case, no dot; empty when there is none).
std::string lower_extension(const std::string& path);
/// 4210 -> "4,210": counts in error messages.
std::string with_thousands(std::size_t value);
/// Natural order: digit runs compare as numbers ("f_9" < "f_10"); ties broken
/// by plain string order, so the order is total and deterministic.
bool natural_less(const std::string& a, const std::string& b);

/// Builds an object from triangles given in file vertex ids: its vertices are
/// the file vertices the triangles use, ascending (file order), and its
/// triangles are rewritten to local ids. `scratch` is a caller-owned buffer of
/// at least `file_vertex_count` entries, reused across calls.
MeshObject compact_object(std::string name, const std::vector<Triangle>& file_triangles,
                          std::size_t file_vertex_count, std::vector<Index>& scratch);

/// An object that keeps every file vertex (ids unchanged): PLY and STL files.
MeshObject whole_file_object(std::string name, std::vector<Triangle> triangles, std::size_t file_vertex_count);

}  // namespace snag::io
