// Meshes with the faces of each region marked, to open in Blender or
// MeshLab: one PLY per frame holding every object's triangles at that
// frame's positions, a colour per face (a distinct one per region, grey for
// faces in no region) and a per-face `region` property (-1 for none).
#pragma once

#include <array>
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "exporters/digest.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/scene.hpp"

namespace snag::exporters {

/// The colour of faces in no region.
constexpr std::array<unsigned char, 3> kUnmarkedColour{170, 170, 170};

/// A colour for region `id`: saturated, far from grey, and different for
/// neighbouring ids (hues spaced by the golden angle).
std::array<unsigned char, 3> region_colour(std::size_t id);

/// The region of each global face of `scene` (#F) at cache frame `frame`:
/// report::kNone for faces in no region; a face in several regions of the
/// frame (a collision and an intersection, or two object pairs) takes the
/// smallest id. Uses the digest's region face lists, which must have been
/// kept for `frame`.
std::vector<std::size_t> face_regions(const ReportDigest& digest, const Scene& scene, std::size_t frame);

/// Writes a binary little-endian PLY: element vertex (float x, y, z; #V
/// global positions in scene units), element face (list uchar int
/// vertex_indices, uchar red, green, blue, int region), faces in global order
/// (objects in order; comments give each object's face range). `face_region`
/// is #F as face_regions() gives it.
void write_marked_ply(std::ostream& out, const Scene& scene, const std::vector<Vec3>& positions,
                      const std::vector<std::size_t>& face_region, const std::string& comment);

/// "<report stem>_frame_<frame>.ply".
std::string marked_mesh_name(const ReportDigest& digest, std::size_t frame);

}  // namespace snag::exporters
