#include "io/reader_support.hpp"

#include <algorithm>
#include <numeric>

namespace snag::io {

std::string file_stem(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::size_t dot = name.find_last_of('.');
  if (dot != std::string::npos && dot > 0) name.resize(dot);
  return name;
}

std::string lower_extension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string extension = path.substr(dot + 1);
  for (char& c : extension) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return extension;
}

std::string with_thousands(std::size_t value) {
  std::string digits = std::to_string(value);
  std::string text;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) text += ',';
    text += digits[i];
  }
  return text;
}

static bool is_digit(char c) { return c >= '0' && c <= '9'; }

bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (is_digit(a[i]) && is_digit(b[j])) {
      std::size_t i_end = i, j_end = j;
      while (i_end < a.size() && is_digit(a[i_end])) ++i_end;
      while (j_end < b.size() && is_digit(b[j_end])) ++j_end;
      // Compare the digit runs as numbers without converting: skip leading
      // zeros, then the longer run is larger, then the first differing digit.
      std::size_t i_lead = i, j_lead = j;
      while (i_lead + 1 < i_end && a[i_lead] == '0') ++i_lead;
      while (j_lead + 1 < j_end && b[j_lead] == '0') ++j_lead;
      const std::size_t i_len = i_end - i_lead, j_len = j_end - j_lead;
      if (i_len != j_len) return i_len < j_len;
      const int order = a.compare(i_lead, i_len, b, j_lead, j_len);
      if (order != 0) return order < 0;
      i = i_end;
      j = j_end;
    } else {
      if (a[i] != b[j]) return static_cast<unsigned char>(a[i]) < static_cast<unsigned char>(b[j]);
      ++i;
      ++j;
    }
  }
  if ((a.size() - i) != (b.size() - j)) return (a.size() - i) < (b.size() - j);
  return a < b;
}

MeshObject compact_object(std::string name, const std::vector<Triangle>& file_triangles,
                          std::size_t file_vertex_count, std::vector<Index>& scratch) {
  MeshObject object;
  object.name = std::move(name);
  if (file_triangles.empty()) return object;
  if (scratch.size() < file_vertex_count) scratch.resize(file_vertex_count);
  Index lowest = file_triangles[0][0], highest = lowest;
  for (const Triangle& t : file_triangles) {
    for (Index v : t) {
      lowest = std::min(lowest, v);
      highest = std::max(highest, v);
    }
  }
  // Mark used vertices. A sweep over [lowest, highest] is linear when the
  // object's vertices are dense in that range (as exporters write them);
  // otherwise sort the used ids.
  const std::size_t range = static_cast<std::size_t>(highest - lowest) + 1;
  constexpr Index unused = static_cast<Index>(-1);
  if (range <= 8 * file_triangles.size() + 64) {
    std::fill(scratch.begin() + lowest, scratch.begin() + lowest + range, unused);
    for (const Triangle& t : file_triangles) {
      for (Index v : t) scratch[v] = 0;
    }
    for (std::size_t v = lowest; v <= highest; ++v) {
      if (scratch[v] != unused) {
        scratch[v] = static_cast<Index>(object.vertices.size());
        object.vertices.push_back(static_cast<Index>(v));
      }
    }
  } else {
    object.vertices.reserve(file_triangles.size() * 3);
    for (const Triangle& t : file_triangles) object.vertices.insert(object.vertices.end(), t.begin(), t.end());
    std::sort(object.vertices.begin(), object.vertices.end());
    object.vertices.erase(std::unique(object.vertices.begin(), object.vertices.end()), object.vertices.end());
    for (std::size_t k = 0; k < object.vertices.size(); ++k) scratch[object.vertices[k]] = static_cast<Index>(k);
  }
  object.triangles.reserve(file_triangles.size());
  for (const Triangle& t : file_triangles) object.triangles.push_back({scratch[t[0]], scratch[t[1]], scratch[t[2]]});
  return object;
}

MeshObject whole_file_object(std::string name, std::vector<Triangle> triangles, std::size_t file_vertex_count) {
  MeshObject object;
  object.name = std::move(name);
  object.vertices.resize(file_vertex_count);
  std::iota(object.vertices.begin(), object.vertices.end(), Index{0});
  object.triangles = std::move(triangles);
  return object;
}

}  // namespace snag::io
