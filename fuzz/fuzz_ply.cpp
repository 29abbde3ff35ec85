// libFuzzer entry point: the PLY parser on arbitrary bytes. InputError is the
// expected answer to bad bytes; any other exception, crash or sanitizer
// report is a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "io/ply_reader.hpp"
#include "fuzz/fuzz_mesh_parser.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return snag::fuzz::fuzz_mesh_parser(data, size,
                                      [](std::string_view bytes) { return snag::io::parse_ply(bytes, "fuzz.ply"); });
}
