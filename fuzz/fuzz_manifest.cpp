// libFuzzer entry point: the scene manifest parser on arbitrary text.
// InputError is the expected answer to a bad manifest; any other exception,
// crash, hang or sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "libcd/core/error.hpp"
#include "tools/common/manifest.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)snag::tools::parse_manifest(text, "/fuzz/scene.yaml");
  } catch (const snag::InputError&) {
  }
  return 0;
}
