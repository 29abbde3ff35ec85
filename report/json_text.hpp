// A small append-only JSON text builder for the report writer: numbers with
// std::to_chars (shortest text that reads back to the same double), strings
// escaped, no tree in memory. The caller writes keys and separators in order.
//
// Millions of event lines go through it, a few dozen pieces each, so that a
// piece must cost a few instructions: each is written straight into room
// kept at the text's end (one bound check, a copy of its known size), not
// appended to a std::string (a call and its checks per piece: about half
// the CPU time of listing cloth_ball's events, in a profile of the sink).
#pragma once

#include <cstddef>
#include <cstring>
#include <string>
#include <string_view>

#include "libcd/geometry/vec3.hpp"

namespace snag::report {

class JsonText {
 public:
  std::string_view text() const { return {buffer_.data(), size_}; }
  /// Empties the text; its room is kept.
  void clear() { size_ = 0; }

  JsonText& raw(std::string_view s) {
    char* out = room(s.size());
    if (!s.empty()) std::memcpy(out, s.data(), s.size());  // a view of nothing may hold no pointer
    size_ += s.size();
    return *this;
  }
  /// ,"key": (the comma unless `first`). `name` is written as it is: a
  /// schema key, never text from a file.
  JsonText& key(std::string_view name, bool first = false) {
    char* const start = room(name.size() + 4);
    char* out = start;
    if (!first) *out++ = ',';
    *out++ = '"';
    std::memcpy(out, name.data(), name.size());
    out += name.size();
    *out++ = '"';
    *out++ = ':';
    size_ += static_cast<std::size_t>(out - start);
    return *this;
  }
  JsonText& string(std::string_view s);
  JsonText& number(double x);  ///< null when not finite
  JsonText& number(std::size_t n);
  JsonText& number(unsigned n) { return number(static_cast<std::size_t>(n)); }
  JsonText& number(int n);
  JsonText& boolean(bool b) { return raw(b ? "true" : "false"); }
  JsonText& null() { return raw("null"); }
  JsonText& vec3(const Vec3& p);  ///< [x,y,z]
  /// `n` when it is not `none`, else null.
  JsonText& optional(std::size_t n, std::size_t none);

 private:
  /// At least `n` bytes of room after the text, where the caller writes
  /// before it moves size_ past what it wrote.
  char* room(std::size_t n) {
    if (buffer_.size() - size_ < n) grow(n);
    return buffer_.data() + size_;
  }
  void grow(std::size_t n);

  std::string buffer_;    ///< the text, then room: its size is the room's end
  std::size_t size_ = 0;  ///< the text's length
};

}  // namespace snag::report
