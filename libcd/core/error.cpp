#include "libcd/core/error.hpp"

namespace snag {

static std::string format_location(const InputLocation& where, const std::string& message) {
  std::string text = where.file.empty() ? std::string("<input>") : where.file;
  if (where.line != 0) {
    text += ":" + std::to_string(where.line);
  }
  text += ": ";
  if (where.frame != static_cast<std::size_t>(-1)) {
    text += "frame " + std::to_string(where.frame) + ": ";
  }
  if (where.byte != static_cast<std::size_t>(-1)) {
    text += "byte " + std::to_string(where.byte) + ": ";
  }
  return text + message;
}

InputError::InputError(InputLocation where, const std::string& message)
    : std::runtime_error(format_location(where, message)), where_(std::move(where)), message_(message) {}

}  // namespace snag
