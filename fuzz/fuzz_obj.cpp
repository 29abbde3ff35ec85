// libFuzzer entry point: the OBJ parser on arbitrary bytes. InputError is the
// expected answer to bad bytes; any other exception, crash or sanitizer
// report is a bug. The bytes are also read as two frames, split at the first
// "\n%%\n": when the layout of the first (ObjFrameLayout) reads the second,
// the parser must accept the second with the first's objects and the same
// positions, or the fuzzer traps; the layout must read a file it was made
// from.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "fuzz/fuzz_mesh_parser.hpp"
#include "io/obj_reader.hpp"

namespace {

std::optional<snag::io::MeshData> parsed(std::string_view bytes) {
  try {
    return snag::io::parse_obj(bytes, "fuzz.obj");
  } catch (const snag::InputError&) {
    return std::nullopt;
  }
}

bool same_objects(const snag::io::MeshData& a, const snag::io::MeshData& b) {
  if (a.objects.size() != b.objects.size()) return false;
  for (std::size_t k = 0; k < a.objects.size(); ++k) {
    if (a.objects[k].name != b.objects[k].name || a.objects[k].vertices != b.objects[k].vertices ||
        a.objects[k].triangles != b.objects[k].triangles)
      return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  snag::fuzz::fuzz_mesh_parser(data, size,
                               [](std::string_view bytes) { return snag::io::parse_obj(bytes, "fuzz.obj"); });
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const std::size_t split = bytes.find("\n%%\n");
  const std::string_view first = bytes.substr(0, split);
  const std::optional<snag::io::MeshData> reference = parsed(first);
  if (!reference) return 0;
  const snag::io::ObjFrameLayout layout(first);
  std::vector<snag::Vec3> positions;
  if (!layout.read_positions(first, positions) || positions != reference->positions) __builtin_trap();
  if (split == std::string_view::npos) return 0;
  const std::string_view second = bytes.substr(split + 4);
  if (!layout.read_positions(second, positions)) return 0;
  const std::optional<snag::io::MeshData> frame = parsed(second);
  if (!frame || positions != frame->positions || !same_objects(*frame, *reference)) __builtin_trap();
  return 0;
}
