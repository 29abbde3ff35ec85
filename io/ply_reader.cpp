// Stanford PLY reader (Turk, "The PLY Polygon File Format", 1994), hand-written
// for speed and exact values: binary data is read in place from the mapped
// file, ASCII numbers with std::from_chars.
#include "io/ply_reader.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "io/mapped_file.hpp"
#include "io/reader_support.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {

namespace {

enum class Type { int8, uint8, int16, uint16, int32, uint32, float32, float64 };
enum class Format { ascii, binary_little_endian, binary_big_endian };

std::size_t size_of(Type type) {
  switch (type) {
    case Type::int8: case Type::uint8: return 1;
    case Type::int16: case Type::uint16: return 2;
    case Type::int32: case Type::uint32: case Type::float32: return 4;
    case Type::float64: return 8;
  }
  return 1;
}

bool parse_type(std::string_view name, Type& type) {
  struct Named { const char* name; Type type; };
  static const Named names[] = {
      {"char", Type::int8},     {"int8", Type::int8},       {"uchar", Type::uint8},     {"uint8", Type::uint8},
      {"short", Type::int16},   {"int16", Type::int16},     {"ushort", Type::uint16},   {"uint16", Type::uint16},
      {"int", Type::int32},     {"int32", Type::int32},     {"uint", Type::uint32},     {"uint32", Type::uint32},
      {"float", Type::float32}, {"float32", Type::float32}, {"double", Type::float64}, {"float64", Type::float64}};
  for (const Named& named : names) {
    if (name == named.name) {
      type = named.type;
      return true;
    }
  }
  return false;
}

struct Property {
  std::string name;
  Type type = Type::float32;  ///< scalar type, or the list's item type
  bool is_list = false;
  Type count_type = Type::uint8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
  /// Fewest bytes one instance can take in a binary file (lists empty).
  std::size_t min_binary_size() const {
    std::size_t size = 0;
    for (const Property& p : properties) size += p.is_list ? size_of(p.count_type) : size_of(p.type);
    return size;
  }
};

struct Header {
  Format format = Format::ascii;
  std::vector<Element> elements;
  std::size_t body_offset = 0;
  std::size_t body_line = 0;  ///< line number of the first body line (ASCII)
};

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t at = 0;
  while (at < line.size()) {
    while (at < line.size() && (line[at] == ' ' || line[at] == '\t' || line[at] == '\r')) ++at;
    std::size_t start = at;
    while (at < line.size() && line[at] != ' ' && line[at] != '\t' && line[at] != '\r') ++at;
    if (at > start) words.push_back(line.substr(start, at - start));
  }
  return words;
}

Header parse_header(std::string_view bytes, const std::string& file) {
  Header header;
  std::size_t at = 0, line = 0;
  bool saw_format = false;
  for (;;) {
    ++line;
    if (at >= bytes.size()) throw InputError({file, line}, "header ends without end_header");
    std::size_t newline = bytes.find('\n', at);
    if (newline == std::string_view::npos) throw InputError({file, line}, "header ends without end_header");
    const std::vector<std::string_view> words = split_words(bytes.substr(at, newline - at));
    at = newline + 1;
    auto fail = [&](const std::string& message) -> void { throw InputError({file, line}, message); };
    if (line == 1) {
      if (words.size() != 1 || words[0] != "ply") fail("not a PLY file (no 'ply' magic line)");
      continue;
    }
    if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
    if (words[0] == "end_header") break;
    if (words[0] == "format") {
      if (words.size() < 2) fail("bad format line");
      if (words[1] == "ascii") header.format = Format::ascii;
      else if (words[1] == "binary_little_endian") header.format = Format::binary_little_endian;
      else if (words[1] == "binary_big_endian") header.format = Format::binary_big_endian;
      else fail("unknown PLY format '" + std::string(words[1]) + "'");
      saw_format = true;
    } else if (words[0] == "element") {
      if (words.size() != 3) fail("bad element line (expected 'element NAME COUNT')");
      Element element;
      element.name = std::string(words[1]);
      auto [end, error] = std::from_chars(words[2].data(), words[2].data() + words[2].size(), element.count);
      if (error != std::errc() || end != words[2].data() + words[2].size()) fail("bad element count '" + std::string(words[2]) + "'");
      header.elements.push_back(std::move(element));
    } else if (words[0] == "property") {
      if (header.elements.empty()) fail("property before any element");
      Property property;
      if (words.size() == 5 && words[1] == "list") {
        property.is_list = true;
        if (!parse_type(words[2], property.count_type) || !parse_type(words[3], property.type)) fail("unknown property type");
        if (property.count_type == Type::float32 || property.count_type == Type::float64) fail("list count type must be an integer");
        property.name = std::string(words[4]);
      } else if (words.size() == 3) {
        if (!parse_type(words[1], property.type)) fail("unknown property type '" + std::string(words[1]) + "'");
        property.name = std::string(words[2]);
      } else {
        fail("bad property line");
      }
      header.elements.back().properties.push_back(std::move(property));
    } else {
      fail("unknown header keyword '" + std::string(words[0]) + "'");
    }
  }
  if (!saw_format) throw InputError({file}, "header has no format line");
  header.body_offset = at;
  header.body_line = line + 1;
  return header;
}

int coordinate_of(const std::string& name) {
  if (name == "x") return 0;
  if (name == "y") return 1;
  if (name == "z") return 2;
  return -1;
}
bool is_index_list(const Property& p) {
  return p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index");
}

// ---- binary -----------------------------------------------------------------

// The value of type T stored at `at` in the file's byte order.
template <typename T>
T load_binary(const unsigned char* at, bool big_endian) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, at, sizeof(T));
  if (big_endian) {
    for (std::size_t k = 0; k < sizeof(T) / 2; ++k) std::swap(raw[k], raw[sizeof(T) - 1 - k]);
  }
  T value;
  std::memcpy(&value, raw, sizeof(T));
  return value;
}

struct BinaryReader {
  const unsigned char* base;
  std::size_t size;
  std::size_t at;
  bool big_endian;
  const std::string& file;

  [[noreturn]] void fail(std::size_t byte, const std::string& message) const {
    InputLocation where{file};
    where.byte = byte;
    throw InputError(where, message);
  }
  void need(std::size_t bytes) const {
    if (bytes > size - at) fail(at, "truncated: the file ends inside the data");
  }
  template <typename T>
  T load(std::size_t offset) const {
    return load_binary<T>(base + offset, big_endian);
  }
  double real(Type type, std::size_t offset) const {
    switch (type) {
      case Type::int8: return load<std::int8_t>(offset);
      case Type::uint8: return load<std::uint8_t>(offset);
      case Type::int16: return load<std::int16_t>(offset);
      case Type::uint16: return load<std::uint16_t>(offset);
      case Type::int32: return load<std::int32_t>(offset);
      case Type::uint32: return load<std::uint32_t>(offset);
      case Type::float32: return load<float>(offset);
      case Type::float64: return load<double>(offset);
    }
    return 0;
  }
  long long integer(Type type, std::size_t offset) const {
    switch (type) {
      case Type::int8: return load<std::int8_t>(offset);
      case Type::uint8: return load<std::uint8_t>(offset);
      case Type::int16: return load<std::int16_t>(offset);
      case Type::uint16: return load<std::uint16_t>(offset);
      case Type::int32: return load<std::int32_t>(offset);
      case Type::uint32: return load<std::uint32_t>(offset);
      case Type::float32: { const float v = load<float>(offset); return std::isfinite(v) && std::fabs(v) < 9e18f ? static_cast<long long>(v) : -1; }
      case Type::float64: { const double v = load<double>(offset); return std::isfinite(v) && std::fabs(v) < 9e18 ? static_cast<long long>(v) : -1; }
    }
    return 0;
  }
};

// ---- ASCII ------------------------------------------------------------------

struct AsciiReader {
  const char* cursor;
  const char* end;
  std::size_t line;
  const std::string& file;

  [[noreturn]] void fail(const std::string& message) const { throw InputError({file, line}, message); }
  std::string_view token() {
    while (cursor < end && (*cursor == ' ' || *cursor == '\t' || *cursor == '\r' || *cursor == '\n')) {
      if (*cursor == '\n') ++line;
      ++cursor;
    }
    if (cursor == end) fail("truncated: the file ends inside the data");
    const char* start = cursor;
    while (cursor < end && *cursor != ' ' && *cursor != '\t' && *cursor != '\r' && *cursor != '\n') ++cursor;
    return {start, static_cast<std::size_t>(cursor - start)};
  }
  double real(Type type) {
    std::string_view word = token();
    const char* first = word.data();
    const char* last = first + word.size();
    if (first < last && *first == '+') ++first;
    if (type == Type::float32) {
      float value = 0;
      auto [next, error] = std::from_chars(first, last, value);
      if (error != std::errc() || next != last) fail("expected a number, found '" + std::string(word) + "'");
      return value;
    }
    if (type == Type::float64) {
      double value = 0;
      auto [next, error] = std::from_chars(first, last, value);
      if (error != std::errc() || next != last) fail("expected a number, found '" + std::string(word) + "'");
      return value;
    }
    return static_cast<double>(integer_from(word));
  }
  long long integer_from(std::string_view word) {
    const char* first = word.data();
    const char* last = first + word.size();
    if (first < last && *first == '+') ++first;
    long long value = 0;
    auto [next, error] = std::from_chars(first, last, value);
    if (error != std::errc() || next != last) fail("expected an integer, found '" + std::string(word) + "'");
    return value;
  }
  long long integer() { return integer_from(token()); }
};

void add_polygon(const long long* ids, std::size_t n, std::vector<Triangle>& triangles) {
  for (std::size_t k = 1; k + 1 < n; ++k) {
    triangles.push_back({static_cast<Index>(ids[0]), static_cast<Index>(ids[k]), static_cast<Index>(ids[k + 1])});
  }
}

}  // namespace

MeshData parse_ply(std::string_view bytes, const std::string& file) {
  const Header header = parse_header(bytes, file);
  const Element* vertex_element = nullptr;
  const Element* face_element = nullptr;
  for (const Element& element : header.elements) {
    if (element.name == "vertex" && !vertex_element) vertex_element = &element;
    if (element.name == "face" && !face_element) face_element = &element;
  }
  if (!vertex_element) throw InputError({file}, "no vertex element");
  int coordinate_property[3] = {-1, -1, -1};
  for (std::size_t k = 0; k < vertex_element->properties.size(); ++k) {
    const int axis = coordinate_of(vertex_element->properties[k].name);
    if (axis >= 0 && !vertex_element->properties[k].is_list) coordinate_property[axis] = static_cast<int>(k);
  }
  if (coordinate_property[0] < 0 || coordinate_property[1] < 0 || coordinate_property[2] < 0) {
    throw InputError({file}, "vertex element lacks an x, y or z property");
  }
  if (!face_element || face_element->count == 0) throw InputError({file}, "no faces: the mesh is empty");
  int index_property = -1;
  for (std::size_t k = 0; k < face_element->properties.size(); ++k) {
    if (is_index_list(face_element->properties[k])) index_property = static_cast<int>(k);
  }
  if (index_property < 0) throw InputError({file}, "face element has no vertex_indices list");
  const std::uint64_t vertex_count = vertex_element->count;

  // Check every element's count against the bytes left before allocating.
  const std::size_t body_size = bytes.size() - header.body_offset;
  {
    std::size_t needed = 0;
    for (const Element& element : header.elements) {
      const std::size_t each = header.format == Format::ascii ? 2 * element.properties.size() : element.min_binary_size();
      if (each == 0) continue;
      if (element.count > (body_size - std::min(needed, body_size)) / each) {
        InputLocation where{file};
        if (header.format != Format::ascii) where.byte = header.body_offset;
        throw InputError(where, "header says " + with_thousands(element.count) + " " + element.name +
                                    " elements but the file holds at most " +
                                    with_thousands((body_size - std::min(needed, body_size)) / each));
      }
      needed += static_cast<std::size_t>(element.count) * each;
    }
  }

  if (vertex_count >= static_cast<Index>(-1)) throw InputError({file}, "too many vertices");
  MeshData mesh;
  mesh.positions.resize(static_cast<std::size_t>(vertex_count));
  std::vector<Triangle> triangles;
  triangles.reserve(static_cast<std::size_t>(face_element->count));
  std::vector<long long> polygon;
  auto check_index = [&](long long id, std::uint64_t face, auto&& fail) {
    if (id < 0 || static_cast<std::uint64_t>(id) >= vertex_count) {
      fail("face " + std::to_string(face) + ": vertex index " + std::to_string(id) + " out of range (the file has " +
           with_thousands(vertex_count) + " vertices)");
    }
  };
  auto check_polygon_size = [&](long long n, std::uint64_t face, auto&& fail) {
    if (n < 3) fail("face " + std::to_string(face) + " has " + std::to_string(n) + " vertices and cannot be triangulated");
  };

  if (header.format == Format::ascii) {
    AsciiReader reader{bytes.data() + header.body_offset, bytes.data() + bytes.size(), header.body_line, file};
    auto fail = [&](const std::string& message) { reader.fail(message); };
    for (const Element& element : header.elements) {
      const bool is_vertex = &element == vertex_element, is_face = &element == face_element;
      if (element.properties.empty()) continue;
      for (std::uint64_t i = 0; i < element.count; ++i) {
        for (std::size_t k = 0; k < element.properties.size(); ++k) {
          const Property& property = element.properties[k];
          if (property.is_list) {
            const long long n = reader.integer();
            if (n < 0) reader.fail("negative list length");
            if (is_face && static_cast<int>(k) == index_property) {
              check_polygon_size(n, i, fail);
              polygon.clear();
              for (long long j = 0; j < n; ++j) {
                const long long id = reader.integer();
                check_index(id, i, fail);
                polygon.push_back(id);
              }
              add_polygon(polygon.data(), polygon.size(), triangles);
            } else {
              for (long long j = 0; j < n; ++j) reader.token();
            }
          } else if (is_vertex && (static_cast<int>(k) == coordinate_property[0] || static_cast<int>(k) == coordinate_property[1] ||
                                   static_cast<int>(k) == coordinate_property[2])) {
            const double value = reader.real(property.type);
            if (!std::isfinite(value)) reader.fail("vertex " + std::to_string(i) + ": coordinate is not finite (NaN or Inf)");
            const int axis = coordinate_of(property.name);
            (axis == 0 ? mesh.positions[i].x : axis == 1 ? mesh.positions[i].y : mesh.positions[i].z) = value;
          } else {
            reader.token();
          }
        }
      }
    }
  } else {
    BinaryReader reader{reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), header.body_offset,
                        header.format == Format::binary_big_endian, file};
    for (const Element& element : header.elements) {
      const bool is_vertex = &element == vertex_element, is_face = &element == face_element;
      bool fixed_size = true;
      for (const Property& p : element.properties) fixed_size = fixed_size && !p.is_list;
      if (fixed_size) {
        const std::size_t stride = element.min_binary_size();
        reader.need(stride * static_cast<std::size_t>(element.count));  // checked above against overflow
        if (is_vertex) {
          std::size_t offset[3] = {0, 0, 0};
          Type type[3] = {Type::float32, Type::float32, Type::float32};
          std::size_t at = 0;
          for (std::size_t k = 0; k < element.properties.size(); ++k) {
            for (int axis = 0; axis < 3; ++axis) {
              if (static_cast<int>(k) == coordinate_property[axis]) {
                offset[axis] = at;
                type[axis] = element.properties[k].type;
              }
            }
            at += size_of(element.properties[k].type);
          }
          const bool plain_floats = !reader.big_endian && type[0] == Type::float32 && type[1] == Type::float32 &&
                                    type[2] == Type::float32;
          for (std::size_t i = 0; i < vertex_count; ++i) {
            const std::size_t base = reader.at + i * stride;
            Vec3& p = mesh.positions[i];
            if (plain_floats) {
              float x, y, z;
              std::memcpy(&x, reader.base + base + offset[0], 4);
              std::memcpy(&y, reader.base + base + offset[1], 4);
              std::memcpy(&z, reader.base + base + offset[2], 4);
              p = Vec3{x, y, z};
            } else {
              p.x = reader.real(type[0], base + offset[0]);
              p.y = reader.real(type[1], base + offset[1]);
              p.z = reader.real(type[2], base + offset[2]);
            }
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
              reader.fail(base, "vertex " + std::to_string(i) + ": coordinate is not finite (NaN or Inf)");
            }
          }
        }
        reader.at += stride * static_cast<std::size_t>(element.count);
        continue;
      }
      const bool plain_face_list = is_face && element.properties.size() == 1 && size_of(element.properties[0].count_type) == 1 &&
                                   (element.properties[0].type == Type::int32 || element.properties[0].type == Type::uint32);
      std::uint64_t first_general = 0;
      if (plain_face_list) {
        // The common layout (one uchar count, int indices, mostly triangles)
        // in a tight loop; anything else falls through to the general walk.
        for (; first_general < element.count; ++first_general) {
          if (reader.size - reader.at < 13 || reader.base[reader.at] != 3) break;
          Triangle t;
          bool in_range = true;
          for (int c = 0; c < 3; ++c) {
            const long long id = reader.integer(element.properties[0].type, reader.at + 1 + 4 * c);
            in_range = in_range && id >= 0 && static_cast<std::uint64_t>(id) < vertex_count;
            t[c] = static_cast<Index>(id);
          }
          if (!in_range) break;  // reported by the general walk below
          triangles.push_back(t);
          reader.at += 13;
        }
      }
      for (std::uint64_t i = first_general; i < element.count; ++i) {
        const std::size_t instance_start = reader.at;
        auto fail = [&](const std::string& message) { reader.fail(instance_start, message); };
        for (std::size_t k = 0; k < element.properties.size(); ++k) {
          const Property& property = element.properties[k];
          if (!property.is_list) {
            reader.need(size_of(property.type));
            if (is_vertex) {
              const int axis = coordinate_of(property.name);
              if (axis >= 0 && static_cast<int>(k) == coordinate_property[axis]) {
                const double value = reader.real(property.type, reader.at);
                if (!std::isfinite(value)) fail("vertex " + std::to_string(i) + ": coordinate is not finite (NaN or Inf)");
                (axis == 0 ? mesh.positions[i].x : axis == 1 ? mesh.positions[i].y : mesh.positions[i].z) = value;
              }
            }
            reader.at += size_of(property.type);
            continue;
          }
          reader.need(size_of(property.count_type));
          const long long n = reader.integer(property.count_type, reader.at);
          reader.at += size_of(property.count_type);
          if (n < 0) fail("negative list length");
          const std::size_t item = size_of(property.type);
          if (static_cast<unsigned long long>(n) > (reader.size - reader.at) / item) {
            reader.fail(reader.at, "truncated: the file ends inside the data");
          }
          if (is_face && static_cast<int>(k) == index_property) {
            check_polygon_size(n, i, fail);
            const long long first = reader.integer(property.type, reader.at);
            check_index(first, i, fail);
            long long previous = reader.integer(property.type, reader.at + item);
            check_index(previous, i, fail);
            for (long long j = 2; j < n; ++j) {
              const long long id = reader.integer(property.type, reader.at + static_cast<std::size_t>(j) * item);
              check_index(id, i, fail);
              triangles.push_back({static_cast<Index>(first), static_cast<Index>(previous), static_cast<Index>(id)});
              previous = id;
            }
          }
          reader.at += static_cast<std::size_t>(n) * item;
        }
      }
    }
  }
  if (triangles.empty()) throw InputError({file}, "no faces: the mesh is empty");
  mesh.objects.push_back(whole_file_object(file_stem(file), std::move(triangles), mesh.positions.size()));
  return mesh;
}

MeshData read_ply(const std::string& path) {
  MappedFile map(path);
  return parse_ply(map.bytes(), path);
}

std::optional<PlyFrameLayout> PlyFrameLayout::of(std::string_view bytes, const std::string& file) {
  const Header header = parse_header(bytes, file);
  if (header.format == Format::ascii || header.elements.empty() || header.elements[0].name != "vertex") return {};
  const Element& vertices = header.elements[0];
  PlyFrameLayout layout;
  bool found[3] = {false, false, false};
  std::size_t at = 0;
  for (const Property& property : vertices.properties) {
    if (property.is_list) return {};
    const int axis = coordinate_of(property.name);
    if (axis >= 0) {  // parse_ply reads the last property of each name
      if (property.type != Type::float32 && property.type != Type::float64) return {};
      found[axis] = true;
      layout.offset_[axis] = at;
      layout.doubles_[axis] = property.type == Type::float64;
    }
    at += size_of(property.type);
  }
  if (!found[0] || !found[1] || !found[2]) return {};
  if (vertices.count > (bytes.size() - header.body_offset) / at) return {};  // more than the file holds
  layout.count_ = static_cast<std::size_t>(vertices.count);
  layout.stride_ = at;
  const std::size_t block_end = header.body_offset + layout.count_ * layout.stride_;
  layout.head_ = std::string(bytes.substr(0, header.body_offset));
  layout.tail_ = std::string(bytes.substr(block_end));
  layout.big_endian_ = header.format == Format::binary_big_endian;
  return layout;
}

bool PlyFrameLayout::read_positions(std::string_view bytes, std::vector<Vec3>& positions) const {
  if (bytes.size() != head_.size() + count_ * stride_ + tail_.size()) return false;
  if (std::memcmp(bytes.data(), head_.data(), head_.size()) != 0) return false;
  const char* tail = bytes.data() + head_.size() + count_ * stride_;
  if (std::memcmp(tail, tail_.data(), tail_.size()) != 0) return false;
  const auto* block = reinterpret_cast<const unsigned char*>(bytes.data()) + head_.size();
  positions.resize(count_);
  bool finite = true;
  for (std::size_t i = 0; i < count_; ++i) {
    const unsigned char* vertex = block + i * stride_;
    double p[3];
    for (int axis = 0; axis < 3; ++axis) {
      p[axis] = doubles_[axis] ? load_binary<double>(vertex + offset_[axis], big_endian_)
                               : load_binary<float>(vertex + offset_[axis], big_endian_);
    }
    positions[i] = {p[0], p[1], p[2]};
    finite = finite && std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
  }
  return finite;
}

}  // namespace snag::io
