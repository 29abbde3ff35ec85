// Wavefront OBJ reader: positions and faces, objects from `o` (or, in files
// without any `o`, from `g`) lines, as Blender and other tools write them.
#pragma once

#include <string>
#include <string_view>

#include "io/mesh_data.hpp"

namespace snag::io {

/// Parses OBJ text held in memory.
/// - `v x y z [w]`: a vertex, kept exactly as written (correctly rounded to
///   double; no welding, no un-welding). Extra components are ignored.
/// - `f a b c ...` with `v`, `v/vt`, `v//vn` or `v/vt/vn` entries, 1-based or
///   negative (relative to the vertices read so far). Polygons of more than 3
///   vertices are fan-triangulated from their first vertex, which is right
///   for convex (and star-shaped from that vertex) polygons, the usual case.
/// - `o NAME` starts a named object. When the file has no `o` line, `g NAME`
///   does instead (when it has both, `g` groups, which Blender writes per
///   material, stay inside their object). Faces before any name go to an
///   object named after `file`'s stem. Repeated names continue one object.
///   Objects without faces are dropped. Each object's vertices are the file
///   vertices its faces use, in file order.
/// - `vt`, `vn`, `l`, `s`, `usemtl`, `mtllib`, comments and unknown keywords
///   are ignored.
/// `file` names the source in errors. Throws InputError (with the line) for
/// malformed numbers, NaN/Inf coordinates, index 0 or out of range, faces of
/// fewer than 3 vertices, and a file without triangles.
MeshData parse_obj(std::string_view text, const std::string& file);

/// Reads an OBJ file (memory-mapped). Throws InputError.
MeshData read_obj(const std::string& path);

}  // namespace snag::io
