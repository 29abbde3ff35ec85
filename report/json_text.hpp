// A small append-only JSON text builder for the report writer: numbers with
// std::to_chars (shortest text that reads back to the same double), strings
// escaped, no tree in memory. The caller writes keys and separators in order.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "libcd/geometry/vec3.hpp"

namespace snag::report {

class JsonText {
 public:
  std::string& text() { return text_; }
  void clear() { text_.clear(); }

  JsonText& raw(std::string_view s) {
    text_.append(s);
    return *this;
  }
  /// ,"key": (the comma unless `first`). `name` is written as it is: a
  /// schema key, never text from a file.
  JsonText& key(std::string_view name, bool first = false);
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
  std::string text_;
};

}  // namespace snag::report
