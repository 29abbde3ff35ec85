// The body shared by the fuzzers of the mesh parsers (OBJ, PLY, STL): parse
// arbitrary bytes; InputError is the expected answer to bad bytes; any other
// exception, a crash, a sanitizer report, or a parsed mesh whose ids point
// outside it (trap) is a bug.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "io/mesh_data.hpp"
#include "libcd/core/error.hpp"

namespace snag::fuzz {

template <typename Parse>
int fuzz_mesh_parser(const std::uint8_t* data, std::size_t size, Parse parse) {
  try {
    const io::MeshData mesh = parse(std::string_view(reinterpret_cast<const char*>(data), size));
    for (const io::MeshObject& object : mesh.objects) {
      for (Index v : object.vertices) {
        if (v >= mesh.positions.size()) __builtin_trap();
      }
      for (const Triangle& t : object.triangles) {
        for (Index v : t) {
          if (v >= object.vertices.size()) __builtin_trap();
        }
      }
    }
  } catch (const InputError&) {
  }
  return 0;
}

}  // namespace snag::fuzz
