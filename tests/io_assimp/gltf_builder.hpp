// Writes small glTF 2.0 files for tests: one binary buffer embedded as a
// base64 data URI, accessors added one call each, the JSON document built by
// the test.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace snag::test {

class GltfBuilder {
 public:
  GltfBuilder();
  /// Adds float VEC3 data (3 floats per element); returns the accessor index.
  int add_vec3(const std::vector<float>& xyz, bool with_bounds = true);
  /// Adds float VEC4 data; returns the accessor index.
  int add_vec4(const std::vector<float>& xyzw);
  /// Adds float SCALAR data (key times or weights); returns the accessor index.
  int add_scalars(const std::vector<float>& values, bool with_bounds = false);
  /// Adds unsigned short SCALAR indices; returns the accessor index.
  int add_indices(const std::vector<std::uint16_t>& ids);
  /// Adds unsigned short VEC4 joint ids; returns the accessor index.
  int add_joints(const std::vector<std::uint16_t>& ids);
  /// Adds float MAT4 data (column-major, 16 floats per matrix); returns the accessor index.
  int add_mat4(const std::vector<float>& matrices);

  /// The document: fill "meshes", "nodes", "scenes", "animations", "skins".
  nlohmann::json& doc() { return doc_; }
  /// Finishes the buffer and writes the .gltf to `path`.
  void write(const std::string& path);

 private:
  int add(const void* data, std::size_t bytes, int component_type, const char* type, std::size_t count);
  std::vector<unsigned char> bytes_;
  nlohmann::json doc_;
};

/// A fresh empty directory `name` under the build tree, private to the running
/// test (its suite and name), so tests run in parallel never share one.
std::string scratch_dir(const std::string& name);

}  // namespace snag::test
