// libFuzzer entry point: the PLY parser on arbitrary bytes. InputError is the
// expected answer to bad bytes; any other exception, crash or sanitizer
// report is a bug. A file the parser reads whose layout lets a later frame be
// read from its coordinates alone (PlyFrameLayout) must read the same
// positions that way, or the fuzzer traps.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "fuzz/fuzz_mesh_parser.hpp"
#include "io/ply_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  snag::fuzz::fuzz_mesh_parser(data, size,
                               [](std::string_view bytes) { return snag::io::parse_ply(bytes, "fuzz.ply"); });
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const snag::io::MeshData mesh = snag::io::parse_ply(bytes, "fuzz.ply");
    const std::optional<snag::io::PlyFrameLayout> layout = snag::io::PlyFrameLayout::of(bytes, "fuzz.ply");
    std::vector<snag::Vec3> positions;
    if (layout && (!layout->read_positions(bytes, positions) || positions != mesh.positions)) __builtin_trap();
  } catch (const snag::InputError&) {
  }
  return 0;
}
