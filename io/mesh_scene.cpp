#include "io/mesh_scene.hpp"

#include <set>

#include "io/reader_support.hpp"

namespace snag::io {

std::vector<Object> make_scene_objects(const MeshData& mesh, const std::string& source_file,
                                       const std::string& default_name, const std::string& name_override) {
  const std::string stem = file_stem(source_file);
  std::vector<Object> objects;
  for (const MeshObject& object : mesh.objects) {
    std::string name = object.name == stem ? default_name : object.name;
    if (!name_override.empty()) name = mesh.objects.size() == 1 ? name_override : name_override + "/" + name;
    objects.push_back(make_object(std::move(name), static_cast<Index>(object.vertices.size()), object.triangles));
  }
  return objects;
}

void gather_object_positions(const std::vector<MeshObject>& objects, const Vec3* file_positions, Vec3* out) {
  for (const MeshObject& object : objects) {
    for (Index v : object.vertices) *out++ = file_positions[v];
  }
}

std::size_t object_vertex_total(const std::vector<MeshObject>& objects) {
  std::size_t total = 0;
  for (const MeshObject& object : objects) total += object.vertices.size();
  return total;
}

bool objects_cover_file_in_order(const std::vector<MeshObject>& objects, std::size_t file_vertex_count) {
  std::size_t next = 0;
  for (const MeshObject& object : objects) {
    for (Index v : object.vertices) {
      if (v != next) return false;
      ++next;
    }
  }
  return next == file_vertex_count;
}

void make_names_unique(std::vector<std::string>& names) {
  std::set<std::string> taken(names.begin(), names.end());
  std::set<std::string> seen;
  for (std::string& name : names) {
    if (seen.insert(name).second) continue;
    for (std::size_t suffix = 2;; ++suffix) {
      std::string candidate = name + "_" + std::to_string(suffix);
      if (!taken.count(candidate)) {
        name = candidate;
        taken.insert(candidate);
        seen.insert(candidate);
        break;
      }
    }
  }
}

}  // namespace snag::io
