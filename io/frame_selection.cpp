#include <cerrno>
#include <cstdlib>
#include <string>

#include "io/open_cache.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {

static std::size_t parse_index(const std::string& text, const std::string& whole) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) {
    throw UsageError("bad frame selection '" + whole + "': expected A, A:, A:B or A:B:STEP with whole numbers");
  }
  errno = 0;
  unsigned long long value = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE) throw UsageError("bad frame selection '" + whole + "': number too large");
  return static_cast<std::size_t>(value);
}

FrameSelection parse_frame_selection(const std::string& text) {
  FrameSelection selection;
  std::size_t first_colon = text.find(':');
  if (first_colon == std::string::npos) {
    selection.first = selection.last = parse_index(text, text);
    return selection;
  }
  selection.first = parse_index(text.substr(0, first_colon), text);
  std::string rest = text.substr(first_colon + 1);
  std::size_t second_colon = rest.find(':');
  std::string last = second_colon == std::string::npos ? rest : rest.substr(0, second_colon);
  if (!last.empty()) selection.last = parse_index(last, text);
  if (second_colon != std::string::npos) {
    selection.step = parse_index(rest.substr(second_colon + 1), text);
    if (selection.step == 0) throw UsageError("bad frame selection '" + text + "': step must be at least 1");
  }
  if (selection.last < selection.first) {
    throw UsageError("bad frame selection '" + text + "': last frame is before the first");
  }
  return selection;
}

}  // namespace snag::io
