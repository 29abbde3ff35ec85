// libFuzzer entry point: the STL parser on arbitrary bytes. InputError is the
// expected answer to bad bytes; any other exception, crash or sanitizer
// report is a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "io/stl_reader.hpp"
#include "libcd/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const snag::io::MeshData mesh = snag::io::parse_stl(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.stl");
    for (const snag::io::MeshObject& object : mesh.objects) {
      for (snag::Index v : object.vertices) {
        if (v >= mesh.positions.size()) __builtin_trap();
      }
      for (const snag::Triangle& t : object.triangles) {
        for (snag::Index v : t) {
          if (v >= object.vertices.size()) __builtin_trap();
        }
      }
    }
  } catch (const snag::InputError&) {
  }
  return 0;
}
