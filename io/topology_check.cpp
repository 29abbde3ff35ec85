#include "io/topology_check.hpp"

#include "io/reader_support.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {

static std::string triangle_text(const Triangle& t) {
  return "(" + std::to_string(t[0]) + "," + std::to_string(t[1]) + "," + std::to_string(t[2]) + ")";
}

void check_same_topology(const MeshData& reference, const std::string& reference_file, const MeshData& frame,
                         const std::string& frame_file, std::size_t frame_index) {
  InputLocation where{frame_file};
  where.frame = frame_index;
  auto counts = [](std::size_t got, std::size_t expected, const char* what) {
    return with_thousands(got) + " " + what + ", expected " + with_thousands(expected);
  };
  if (frame.positions.size() != reference.positions.size()) {
    throw InputError(where, counts(frame.positions.size(), reference.positions.size(), "vertices"));
  }
  if (frame.objects.size() != reference.objects.size()) {
    throw InputError(where, counts(frame.objects.size(), reference.objects.size(), "objects"));
  }
  const bool several = reference.objects.size() > 1;
  for (std::size_t o = 0; o < reference.objects.size(); ++o) {
    const MeshObject& expected = reference.objects[o];
    const MeshObject& got = frame.objects[o];
    const bool default_names = expected.name == file_stem(reference_file) && got.name == file_stem(frame_file);
    if (got.name != expected.name && !default_names) {
      throw InputError(where, "object " + std::to_string(o) + " is '" + got.name + "', expected '" + expected.name + "'");
    }
    const std::string prefix = several ? "object '" + expected.name + "': " : "";
    if (got.vertices.size() != expected.vertices.size()) {
      throw InputError(where, prefix + counts(got.vertices.size(), expected.vertices.size(), "vertices"));
    }
    for (std::size_t k = 0; k < expected.vertices.size(); ++k) {
      if (got.vertices[k] != expected.vertices[k]) {
        throw InputError(where, prefix + "vertex " + std::to_string(k) + " is file vertex " + std::to_string(got.vertices[k]) +
                                    ", expected " + std::to_string(expected.vertices[k]));
      }
    }
    if (got.triangles.size() != expected.triangles.size()) {
      throw InputError(where, prefix + counts(got.triangles.size(), expected.triangles.size(), "triangles"));
    }
    for (std::size_t f = 0; f < expected.triangles.size(); ++f) {
      if (got.triangles[f] != expected.triangles[f]) {
        throw InputError(where, prefix + "triangle " + std::to_string(f) + " is " + triangle_text(got.triangles[f]) +
                                    ", expected " + triangle_text(expected.triangles[f]));
      }
    }
  }
}

}  // namespace snag::io
