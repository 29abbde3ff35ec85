// Stanford PLY reader: ASCII, binary little-endian and binary big-endian.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

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

/// What the first frame of a sequence of binary PLY files fixes when its
/// first element is its vertices, of a fixed size, with float or double x, y
/// and z: every byte outside the vertex element's coordinates' block (the
/// header, the faces). A later frame with exactly those bytes has the first
/// frame's topology, so that only its coordinates need reading: no parse of
/// its faces and no compare of its triangles, a memcmp instead.
class PlyFrameLayout {
 public:
  /// The layout of `bytes`, a PLY file that parse_ply accepts; nullopt for
  /// an ASCII file or one whose vertices are not first, of a fixed size, or
  /// with coordinates of another type.
  static std::optional<PlyFrameLayout> of(std::string_view bytes, const std::string& file);

  /// Reads the x, y, z of every vertex of `bytes` (another frame) into
  /// `positions` in file order, as parse_ply gives them, and returns true,
  /// when its bytes outside the vertex block are exactly the first frame's.
  /// Returns false, `positions` in any state, for any other file and for a
  /// coordinate that is not finite (parse_ply then says which).
  bool read_positions(std::string_view bytes, std::vector<Vec3>& positions) const;

 private:
  PlyFrameLayout() = default;
  std::string head_;  ///< the header, up to the vertex block
  std::string tail_;  ///< every byte after the vertex block
  std::size_t count_ = 0, stride_ = 0;
  std::size_t offset_[3] = {0, 0, 0};  ///< of x, y, z in a vertex
  bool doubles_[3] = {false, false, false};
  bool big_endian_ = false;
};

}  // namespace snag::io
