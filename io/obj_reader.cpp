// Wavefront OBJ reader, hand-written for speed: one pass over the mapped text,
// correctly rounded doubles as std::from_chars reads them (parse_double).
#include "io/obj_reader.hpp"

#include <charconv>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "io/decimal.hpp"
#include "io/mapped_file.hpp"
#include "io/reader_support.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {

namespace {

struct ObjParser {
  const char* cursor;
  const char* end;
  const std::string& file;
  std::size_t line = 1;

  [[noreturn]] void fail(const std::string& message) const { throw InputError({file, line}, message); }

  static bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
  void skip_blanks() {
    while (cursor < end && is_blank(*cursor)) ++cursor;
  }
  bool at_line_end() const { return cursor == end || *cursor == '\n'; }
  void skip_line() {
    if (cursor >= end || *cursor == '\n') return;
    const void* newline = std::memchr(cursor, '\n', static_cast<std::size_t>(end - cursor));
    cursor = newline ? static_cast<const char*>(newline) : end;
  }
  std::string rest_of_line() {
    skip_blanks();
    const char* start = cursor;
    skip_line();
    const char* stop = cursor;
    while (stop > start && is_blank(stop[-1])) --stop;
    return std::string(start, stop);
  }

  double number() {
    skip_blanks();
    if (cursor < end && *cursor == '+') ++cursor;
    double value = 0;
    auto [next, error] = parse_double(cursor, end, value);
    if (error == std::errc::result_out_of_range) fail("coordinate out of range");
    if (error != std::errc() || (next < end && !is_blank(*next) && *next != '\n')) fail("expected a number");
    if (!std::isfinite(value)) fail("coordinate is not finite (NaN or Inf)");
    cursor = next;
    return value;
  }

  /// Whether the word at the cursor is its one letter ("v", not "vn").
  bool one_letter_word() const {
    const char next = cursor + 1 < end ? cursor[1] : '\n';
    return is_blank(next) || next == '\n';
  }
  /// What a line is to parse_obj, read from the line's start: the cursor is
  /// left after its leading blanks.
  enum class Line { kSkipped, kVertex, kRead };
  Line line_kind() {
    skip_blanks();
    if (at_line_end() || *cursor == '#') return Line::kSkipped;
    if (*cursor != 'v') return Line::kRead;
    return one_letter_word() ? Line::kVertex : Line::kSkipped;  // vn, vt, vp, ...
  }
  /// Past the newline that ends the line (cursor at it or at the end).
  void next_line() {
    if (cursor < end) {
      ++cursor;
      ++line;
    }
  }

  /// One face entry ("7", "7/2", "7//3", "-1/2/3"): the vertex id, resolved
  /// against `vertex_count` vertices read so far; 0-based, unchecked above.
  long long face_vertex(std::size_t vertex_count) {
    long long value = 0;
    auto [next, error] = std::from_chars(cursor, end, value);
    if (error != std::errc()) fail("expected a vertex index in face");
    cursor = next;
    while (cursor < end && !is_blank(*cursor) && *cursor != '\n') ++cursor;  // skip /vt/vn
    if (value == 0) fail("vertex index 0 in face (OBJ indices start at 1)");
    if (value < 0) {
      if (static_cast<unsigned long long>(-(value + 1)) >= vertex_count) {
        fail("relative vertex index " + std::to_string(value) + " points before the first vertex");
      }
      return static_cast<long long>(vertex_count) + value;
    }
    return value - 1;
  }
};

struct ObjectBuild {
  std::string name;
  std::vector<Triangle> triangles;
};

bool has_o_lines(std::string_view text) {
  for (std::size_t at = 0; at < text.size();) {
    std::size_t start = at;
    while (start < text.size() && (text[start] == ' ' || text[start] == '\t')) ++start;
    if (start + 1 < text.size() && text[start] == 'o' && (text[start + 1] == ' ' || text[start + 1] == '\t')) return true;
    const std::size_t newline = text.find('\n', start);
    if (newline == std::string_view::npos) break;
    at = newline + 1;
  }
  return false;
}

}  // namespace

MeshData parse_obj(std::string_view text, const std::string& file) {
  ObjParser parser{text.data(), text.data() + text.size(), file};
  const bool objects_from_o = has_o_lines(text);

  MeshData mesh;
  std::vector<ObjectBuild> objects;
  std::unordered_map<std::string, std::size_t> object_by_name;
  std::size_t current = static_cast<std::size_t>(-1);
  auto select_object = [&](std::string name) {
    if (name.empty()) name = file_stem(file);
    auto [it, inserted] = object_by_name.emplace(name, objects.size());
    if (inserted) objects.push_back({std::move(name), {}});
    current = it->second;
  };

  long long highest_index = -1;
  std::size_t highest_index_line = 0;
  std::vector<long long> polygon;
  constexpr std::size_t max_vertices = static_cast<std::size_t>(static_cast<Index>(-1)) - 1;

  while (parser.cursor < parser.end) {
    const ObjParser::Line kind = parser.line_kind();
    if (kind == ObjParser::Line::kRead || kind == ObjParser::Line::kVertex) {
      const char c = *parser.cursor;
      const bool keyword_ends = parser.one_letter_word();
      if (kind == ObjParser::Line::kVertex) {
        ++parser.cursor;
        if (mesh.positions.size() >= max_vertices) parser.fail("too many vertices");
        Vec3 p;
        p.x = parser.number();
        p.y = parser.number();
        p.z = parser.number();
        mesh.positions.push_back(p);
      } else if (c == 'f' && keyword_ends) {
        ++parser.cursor;
        polygon.clear();
        for (;;) {
          parser.skip_blanks();
          if (parser.at_line_end() || *parser.cursor == '#') break;
          const long long v = parser.face_vertex(mesh.positions.size());
          if (v > highest_index) {
            highest_index = v;
            highest_index_line = parser.line;
          }
          polygon.push_back(v);
        }
        if (polygon.size() < 3) {
          parser.fail("face with " + std::to_string(polygon.size()) + " vertices cannot be triangulated");
        }
        if (current == static_cast<std::size_t>(-1)) select_object({});
        auto& triangles = objects[current].triangles;
        for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
          triangles.push_back({static_cast<Index>(polygon[0]), static_cast<Index>(polygon[k]),
                               static_cast<Index>(polygon[k + 1])});
        }
      } else if ((c == 'o' && keyword_ends) || (c == 'g' && keyword_ends && !objects_from_o)) {
        ++parser.cursor;
        select_object(parser.rest_of_line());
      }
    }
    parser.skip_line();
    parser.next_line();
  }

  if (highest_index >= static_cast<long long>(mesh.positions.size())) {
    parser.line = highest_index_line;
    parser.fail("vertex index " + std::to_string(highest_index + 1) + " out of range (the file has " +
                with_thousands(mesh.positions.size()) + " vertices)");
  }
  std::vector<Index> scratch;
  for (ObjectBuild& build : objects) {
    if (build.triangles.empty()) continue;
    mesh.objects.push_back(compact_object(std::move(build.name), build.triangles, mesh.positions.size(), scratch));
  }
  if (mesh.objects.empty()) throw InputError({file}, "no faces: the mesh is empty");
  return mesh;
}

MeshData read_obj(const std::string& path) {
  MappedFile map(path);
  return parse_obj(map.bytes(), path);
}

namespace {

const std::string kNoFile;

}  // namespace

ObjFrameLayout::ObjFrameLayout(std::string_view text) {
  ObjParser parser{text.data(), text.data() + text.size(), kNoFile};
  pieces_.emplace_back();
  while (parser.cursor < parser.end) {
    const char* line = parser.cursor;
    const ObjParser::Line kind = parser.line_kind();
    parser.skip_line();
    if (kind == ObjParser::Line::kVertex) {
      ++pieces_.back().vertices;
      ++count_;
    } else if (kind == ObjParser::Line::kRead) {
      if (pieces_.back().vertices > 0) pieces_.emplace_back();
      const char* line_end = parser.cursor + (parser.cursor < parser.end);
      kept_.append(line, line_end);
      pieces_.back().kept_bytes += static_cast<std::size_t>(line_end - line);
    }
    parser.next_line();
  }
}

bool ObjFrameLayout::read_positions(std::string_view text, std::vector<Vec3>& positions) const {
  ObjParser parser{text.data(), text.data() + text.size(), kNoFile};
  positions.resize(count_);
  const char* kept = kept_.data();
  std::size_t piece = 0, kept_left = pieces_[0].kept_bytes, vertices_left = pieces_[0].vertices, vertex = 0;
  try {
    while (parser.cursor < parser.end) {
      const char* line = parser.cursor;
      const ObjParser::Line kind = parser.line_kind();
      if (kind == ObjParser::Line::kVertex) {
        if (kept_left > 0 || vertices_left == 0) return false;
        --vertices_left;
        ++parser.cursor;
        Vec3& p = positions[vertex++];
        p.x = parser.number();
        p.y = parser.number();
        p.z = parser.number();
      } else if (kind == ObjParser::Line::kRead) {
        if (kept_left == 0) {  // the next piece's lines
          if (vertices_left > 0 || ++piece == pieces_.size()) return false;
          kept_left = pieces_[piece].kept_bytes;
          vertices_left = pieces_[piece].vertices;
        }
        // The piece's lines left, all at once: files alike have them
        // together (their faces, say). They end with a newline or the file.
        const auto text_left = static_cast<std::size_t>(parser.end - line);
        if (kept_left <= text_left && std::memcmp(line, kept, kept_left) == 0 &&
            (kept[kept_left - 1] == '\n' || kept_left == text_left)) {
          parser.cursor = line + kept_left;
          kept += kept_left;
          kept_left = 0;
          continue;
        }
        parser.skip_line();
        const auto length = static_cast<std::size_t>(parser.cursor - line) + (parser.cursor < parser.end);
        if (length > kept_left || std::memcmp(kept, line, length) != 0) return false;
        kept += length;
        kept_left -= length;
        parser.next_line();
        continue;
      }
      parser.skip_line();
      parser.next_line();
    }
  } catch (const InputError&) {
    return false;  // parse_obj says where
  }
  return piece + 1 == pieces_.size() && kept_left == 0 && vertices_left == 0;
}

}  // namespace snag::io
