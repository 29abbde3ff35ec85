// A minimal binary PLY reader for the benchmark and the broad-phase tests
// only (the reference meshes of ../shared/data/meshes): vertex x, y, z as
// float or double, faces as a uchar/uint8 count and int/int32 ids, either
// byte order. The project's readers live in io/.
#pragma once

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag::bench {

struct PlyMesh {
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;
};

inline PlyMesh read_binary_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::string line, format;
  std::size_t vertex_count = 0, face_count = 0;
  bool vertex_double = false, in_vertex = false;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string w;
    words >> w;
    if (w == "format") words >> format;
    if (w == "element") {
      std::string kind;
      words >> kind;
      in_vertex = kind == "vertex";
      (in_vertex ? words >> vertex_count : words >> face_count);
    }
    if (w == "property" && in_vertex) {
      std::string type;
      words >> type;
      vertex_double = type == "double" || type == "float64";
    }
    if (w == "end_header") break;
  }
  if (format != "binary_little_endian" && format != "binary_big_endian") throw std::runtime_error(path + ": not binary PLY");
  const bool swap = format == "binary_big_endian";
  auto read = [&](void* out, std::size_t bytes) {
    char buffer[8];
    in.read(buffer, static_cast<std::streamsize>(bytes));
    if (!in) throw std::runtime_error(path + ": truncated");
    if (swap)
      for (std::size_t i = 0; i < bytes / 2; ++i) std::swap(buffer[i], buffer[bytes - 1 - i]);
    std::memcpy(out, buffer, bytes);
  };
  PlyMesh mesh;
  mesh.vertices.resize(vertex_count);
  for (Vec3& v : mesh.vertices) {
    for (int a = 0; a < 3; ++a) {
      if (vertex_double) {
        double d;
        read(&d, 8);
        v[a] = d;
      } else {
        float f;
        read(&f, 4);
        v[a] = f;
      }
    }
  }
  mesh.triangles.resize(face_count);
  for (Triangle& t : mesh.triangles) {
    std::uint8_t n;
    read(&n, 1);
    if (n != 3) throw std::runtime_error(path + ": only triangles are supported");
    for (int k = 0; k < 3; ++k) {
      std::int32_t id;
      read(&id, 4);
      if (id < 0 || static_cast<std::size_t>(id) >= vertex_count) throw std::runtime_error(path + ": bad vertex id");
      t[k] = static_cast<Index>(id);
    }
  }
  return mesh;
}

}  // namespace snag::bench
