// Typed exceptions. Bad input files throw InputError (the tools map it to exit
// code 2); caller bugs are asserts; anything else is an internal error (exit 3).
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace snag {

/// Where in an input a problem lies: the file, and a line (text formats),
/// a byte offset (binary formats) or a frame, where one is known.
struct InputLocation {
  std::string file;
  std::size_t line = 0;    ///< 1-based; 0 = not known
  std::size_t frame = static_cast<std::size_t>(-1);  ///< 0-based frame index; -1 = not known
  std::size_t byte = static_cast<std::size_t>(-1);   ///< byte offset; -1 = not known
};

/// Bad input: a file that is missing, unreadable, malformed or inconsistent.
/// what() is one line: "FILE:LINE: message", "FILE: frame N: message" or "FILE: message".
class InputError : public std::runtime_error {
 public:
  InputError(InputLocation where, const std::string& message);
  const InputLocation& where() const { return where_; }
  const std::string& message() const { return message_; }

 private:
  InputLocation where_;
  std::string message_;
};

/// Bad usage: an option or argument that cannot be honoured (exit code 2).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace snag
