// Wavefront OBJ reader: positions and faces, objects from `o` (or, in files
// without any `o`, from `g`) lines, as Blender and other tools write them.
#pragma once

#include <string>
#include <string_view>
#include <vector>

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

/// What a later frame of an OBJ sequence must share with the first for its
/// vertices alone to be read: every line parse_obj may read but the vertex
/// lines (faces, objects, groups, unknown keywords), byte for byte, in the
/// same order, with the vertex lines at the same places among them. The lines
/// it skips whatever they hold (blank lines, comments, and `vn`, `vt` and
/// other words that begin with `v`: the normals change from frame to frame)
/// may differ. A frame that shares them parses to the first frame's objects,
/// and only its vertices need reading.
class ObjFrameLayout {
 public:
  /// The layout of `text`, a file parse_obj accepts.
  explicit ObjFrameLayout(std::string_view text);

  /// Reads the vertices of `text` (another frame) into `positions` in file
  /// order, as parse_obj gives them, and returns true, when the file shares
  /// the first frame's layout. Returns false, `positions` in any state, for
  /// any other file and for a vertex that parse_obj refuses (it then says
  /// where).
  bool read_positions(std::string_view text, std::vector<Vec3>& positions) const;

 private:
  /// A run of kept lines, then a run of vertex lines (either may be empty).
  struct Piece {
    std::size_t kept_bytes = 0;
    std::size_t vertices = 0;
  };
  std::string kept_;           ///< the kept lines, whole, with their newlines
  std::vector<Piece> pieces_;  ///< how the kept lines and the vertex lines alternate
  std::size_t count_ = 0;      ///< vertex lines
};

}  // namespace snag::io
