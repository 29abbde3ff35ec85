#include "ply_mesh.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace snag::test {
namespace {

struct Property {
  std::string type;        // scalar type, or the item type of a list
  std::string count_type;  // list count type; empty for a scalar
  std::string name;
};

std::size_t type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  throw std::runtime_error("PLY: unknown type " + t);
}

class Reader {
 public:
  Reader(std::istream& in, bool big_endian, const std::string& path) : in_(in), big_(big_endian), path_(path) {}

  double read(const std::string& type) {
    unsigned char bytes[8];
    const std::size_t n = type_size(type);
    if (!in_.read(reinterpret_cast<char*>(bytes), static_cast<std::streamsize>(n)))
      throw std::runtime_error(path_ + ": truncated PLY body");
    if (big_) std::reverse(bytes, bytes + n);
    if (type == "float" || type == "float32") return load<float>(bytes);
    if (type == "double" || type == "float64") return load<double>(bytes);
    if (type == "uchar" || type == "uint8") return bytes[0];
    if (type == "char" || type == "int8") return load<std::int8_t>(bytes);
    if (type == "short" || type == "int16") return load<std::int16_t>(bytes);
    if (type == "ushort" || type == "uint16") return load<std::uint16_t>(bytes);
    if (type == "int" || type == "int32") return load<std::int32_t>(bytes);
    return load<std::uint32_t>(bytes);
  }

 private:
  template <class T>
  static double load(const unsigned char* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return static_cast<double>(value);
  }
  std::istream& in_;
  bool big_;
  const std::string& path_;
};

}  // namespace

PlyMesh read_binary_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::string line;
  bool big_endian = false;
  std::size_t vertex_count = 0, face_count = 0;
  std::vector<Property> vertex_properties, face_properties;
  std::vector<Property>* current = nullptr;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") {
      std::string format;
      words >> format;
      if (format == "binary_big_endian") big_endian = true;
      else if (format != "binary_little_endian") throw std::runtime_error(path + ": not a binary PLY");
    } else if (keyword == "element") {
      std::string name;
      std::size_t count = 0;
      words >> name >> count;
      if (name == "vertex") vertex_count = count, current = &vertex_properties;
      else if (name == "face") face_count = count, current = &face_properties;
      else throw std::runtime_error(path + ": unsupported PLY element " + name);
    } else if (keyword == "property") {
      Property p;
      words >> p.type;
      if (p.type == "list") words >> p.count_type >> p.type;
      words >> p.name;
      if (current == nullptr) throw std::runtime_error(path + ": PLY property before any element");
      current->push_back(p);
    } else if (keyword == "end_header") {
      break;
    }
  }
  Reader reader(in, big_endian, path);
  PlyMesh mesh;
  mesh.positions.resize(vertex_count);
  for (std::size_t v = 0; v < vertex_count; ++v) {
    for (const Property& p : vertex_properties) {
      const double value = reader.read(p.type);
      if (p.name == "x") mesh.positions[v].x = value;
      if (p.name == "y") mesh.positions[v].y = value;
      if (p.name == "z") mesh.positions[v].z = value;
    }
  }
  for (std::size_t f = 0; f < face_count; ++f) {
    for (const Property& p : face_properties) {
      if (p.count_type.empty()) {
        reader.read(p.type);
        continue;
      }
      const auto n = static_cast<std::size_t>(reader.read(p.count_type));
      std::vector<Index> ids(n);
      for (Index& id : ids) {
        const double value = reader.read(p.type);
        if (value < 0 || value >= static_cast<double>(vertex_count))
          throw std::runtime_error(path + ": PLY face refers to a missing vertex");
        id = static_cast<Index>(value);
      }
      for (std::size_t k = 2; k < n; ++k) mesh.triangles.push_back({ids[0], ids[k - 1], ids[k]});
    }
  }
  return mesh;
}

}  // namespace snag::test
