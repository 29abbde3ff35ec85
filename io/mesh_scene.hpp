// From a mesh file's data to scene objects and frame positions.
#pragma once

#include <string>
#include <vector>

#include "io/mesh_data.hpp"
#include "libcd/scene/object.hpp"

namespace snag::io {

/// Scene objects for a mesh's objects. Names: `name_override` when set (with
/// "/<object name>" appended when the mesh has several objects); else the
/// objects' own names, where an object named after `source_file`'s stem (the
/// readers' default) is called `default_name` instead.
std::vector<Object> make_scene_objects(const MeshData& mesh, const std::string& source_file,
                                       const std::string& default_name, const std::string& name_override);

/// Writes each object's vertex positions, objects concatenated, to `out`:
/// out[k] = file_positions[vertices[k]] object by object.
void gather_object_positions(const std::vector<MeshObject>& objects, const Vec3* file_positions, Vec3* out);

/// Total vertex count of the objects (the scene's vertex count).
std::size_t object_vertex_total(const std::vector<MeshObject>& objects);

/// True when the objects list every file vertex once, in order (PLY, STL,
/// single-object OBJ using all vertices): frame positions need no gather.
bool objects_cover_file_in_order(const std::vector<MeshObject>& objects, std::size_t file_vertex_count);

/// Makes names unique in order: a repeated name gets "_2", "_3" ... (the
/// first free one), so the same inputs always get the same names.
void make_names_unique(std::vector<std::string>& names);

}  // namespace snag::io
