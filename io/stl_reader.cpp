// STL reader: binary (80-byte header, uint32 count, 50 bytes per triangle,
// little-endian float32) and ASCII, with exact welding of equal corners.
#include "io/stl_reader.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <unordered_map>

#include "io/mapped_file.hpp"
#include "io/reader_support.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {

namespace {

struct PositionKey {
  double x, y, z;
  bool operator==(const PositionKey& other) const { return x == other.x && y == other.y && z == other.z; }
};

struct PositionHash {
  static std::uint64_t bits(double value) {
    if (value == 0) value = 0;  // -0 and +0 weld together
    std::uint64_t b;
    std::memcpy(&b, &value, sizeof b);
    return b;
  }
  std::size_t operator()(const PositionKey& key) const {
    std::uint64_t h = bits(key.x) * 0x9E3779B97F4A7C15ull;
    h ^= bits(key.y) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
    h ^= bits(key.z) + 0x94D049BB133111EBull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

class Welder {
 public:
  explicit Welder(std::size_t corner_count) { ids_.reserve(corner_count); }
  Index add(const Vec3& p) {
    auto [it, inserted] = ids_.emplace(PositionKey{p.x, p.y, p.z}, static_cast<Index>(positions.size()));
    if (inserted) positions.push_back(p);
    return it->second;
  }
  std::vector<Vec3> positions;

 private:
  std::unordered_map<PositionKey, Index, PositionHash> ids_;
};

bool finite(const Vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

MeshData parse_binary(std::string_view bytes, std::size_t triangle_count, const std::string& file) {
  Welder welder(triangle_count * 3);
  std::vector<Triangle> triangles;
  triangles.reserve(triangle_count);
  for (std::size_t f = 0; f < triangle_count; ++f) {
    const std::size_t record = 84 + 50 * f;
    Triangle t{};
    for (int c = 0; c < 3; ++c) {
      float xyz[3];
      std::memcpy(xyz, bytes.data() + record + 12 + 12 * c, sizeof xyz);  // little-endian hosts only
      const Vec3 p{xyz[0], xyz[1], xyz[2]};
      if (!finite(p)) {
        InputLocation where{file};
        where.byte = record;
        throw InputError(where, "triangle " + std::to_string(f) + ": coordinate is not finite (NaN or Inf)");
      }
      t[c] = welder.add(p);
    }
    triangles.push_back(t);
  }
  MeshData mesh;
  mesh.positions = std::move(welder.positions);
  mesh.objects.push_back(whole_file_object(file_stem(file), std::move(triangles), mesh.positions.size()));
  return mesh;
}

struct AsciiStl {
  const char* cursor;
  const char* end;
  std::size_t line = 1;
  const std::string& file;

  [[noreturn]] void fail(const std::string& message) const { throw InputError({file, line}, message); }
  /// The next word, or an empty view at the end of the file.
  std::string_view word() {
    while (cursor < end && (*cursor == ' ' || *cursor == '\t' || *cursor == '\r' || *cursor == '\n')) {
      if (*cursor == '\n') ++line;
      ++cursor;
    }
    const char* start = cursor;
    while (cursor < end && *cursor != ' ' && *cursor != '\t' && *cursor != '\r' && *cursor != '\n') ++cursor;
    return {start, static_cast<std::size_t>(cursor - start)};
  }
  double number() {
    std::string_view text = word();
    const char* first = text.data();
    const char* last = first + text.size();
    if (first < last && *first == '+') ++first;
    double value = 0;
    auto [next, error] = std::from_chars(first, last, value);
    if (error != std::errc() || next != last || text.empty()) fail("expected a number, found '" + std::string(text) + "'");
    if (!std::isfinite(value)) fail("coordinate is not finite (NaN or Inf)");
    return value;
  }
  void expect(std::string_view keyword) {
    std::string_view text = word();
    if (text != keyword) fail("expected '" + std::string(keyword) + "', found '" + std::string(text) + "'");
  }
  void skip_line() {
    while (cursor < end && *cursor != '\n') ++cursor;
  }
};

MeshData parse_ascii(std::string_view bytes, const std::string& file) {
  AsciiStl parser{bytes.data(), bytes.data() + bytes.size(), 1, file};
  parser.expect("solid");
  parser.skip_line();  // the solid's name
  Welder welder(bytes.size() / 64);
  std::vector<Triangle> triangles;
  std::vector<Index> polygon;
  for (;;) {
    std::string_view keyword = parser.word();
    if (keyword.empty()) parser.fail("file ends without 'endsolid'");
    if (keyword == "endsolid") break;
    if (keyword != "facet") parser.fail("expected 'facet' or 'endsolid', found '" + std::string(keyword) + "'");
    parser.skip_line();  // normal: recomputed from the corners when needed
    parser.expect("outer");
    parser.expect("loop");
    polygon.clear();
    for (;;) {
      keyword = parser.word();
      if (keyword == "endloop") break;
      if (keyword != "vertex") parser.fail("expected 'vertex' or 'endloop', found '" + std::string(keyword) + "'");
      Vec3 p;
      p.x = parser.number();
      p.y = parser.number();
      p.z = parser.number();
      polygon.push_back(welder.add(p));
    }
    if (polygon.size() < 3) parser.fail("facet with " + std::to_string(polygon.size()) + " vertices cannot be triangulated");
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
    parser.expect("endfacet");
  }
  if (triangles.empty()) throw InputError({file}, "no facets: the mesh is empty");
  MeshData mesh;
  mesh.positions = std::move(welder.positions);
  mesh.objects.push_back(whole_file_object(file_stem(file), std::move(triangles), mesh.positions.size()));
  return mesh;
}

}  // namespace

MeshData parse_stl(std::string_view bytes, const std::string& file) {
  if (bytes.size() >= 84) {
    std::uint32_t count;
    std::memcpy(&count, bytes.data() + 80, sizeof count);
    if (bytes.size() == 84 + 50 * static_cast<std::uint64_t>(count)) {
      if (count == 0) throw InputError({file}, "no triangles: the mesh is empty");
      return parse_binary(bytes, count, file);
    }
  }
  if (bytes.substr(0, 5) == "solid") return parse_ascii(bytes, file);
  InputLocation where{file};
  where.byte = 80;
  if (bytes.size() < 84) throw InputError(where, "truncated: too short for a binary STL and not ASCII STL");
  std::uint32_t count;
  std::memcpy(&count, bytes.data() + 80, sizeof count);
  throw InputError(where, "binary STL header says " + with_thousands(count) + " triangles (" +
                              with_thousands(84 + 50 * static_cast<std::uint64_t>(count)) + " bytes) but the file has " +
                              with_thousands(bytes.size()) + " bytes");
}

MeshData read_stl(const std::string& path) {
  MappedFile map(path);
  return parse_stl(map.bytes(), path);
}

}  // namespace snag::io
