// libFuzzer entry point: the streaming report reader on arbitrary bytes, read
// to the end. InputError is the expected answer to bad bytes; any other
// exception, crash, hang or sanitizer report is a bug.
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "libcd/core/error.hpp"
#include "report/report_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The reader takes a path: the bytes go to an anonymous in-memory file.
  const int fd = memfd_create("fuzz-report", 0);
  if (fd < 0) return 0;
  std::size_t written = 0;
  while (written < size) {
    const ssize_t n = ::write(fd, data + written, size - written);
    if (n <= 0) break;
    written += static_cast<std::size_t>(n);
  }
  try {
    snag::report::ReportReader reader("/proc/self/fd/" + std::to_string(fd));
    while (reader.next() != snag::report::ReportReader::Record::kEnd) {
    }
  } catch (const snag::InputError&) {
  }
  ::close(fd);
  return 0;
}
