#include "report/json_text.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace snag::report {

namespace {

bool needs_escape(char c) { return c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20; }

}  // namespace

// Millions of keys and strings go through here: a short one is put
// together on the stack and appended in one call rather than a call per
// piece or per character.
JsonText& JsonText::key(std::string_view name, bool first) {
  // keys are the schema's own names: nothing to escape
  char buffer[64];
  if (name.size() + 4 > sizeof buffer) {
    if (!first) text_.push_back(',');
    text_.push_back('"');
    text_.append(name);
    text_.append("\":");
    return *this;
  }
  char* out = buffer;
  if (!first) *out++ = ',';
  *out++ = '"';
  out = std::copy(name.begin(), name.end(), out);
  *out++ = '"';
  *out++ = ':';
  text_.append(buffer, static_cast<std::size_t>(out - buffer));
  return *this;
}

JsonText& JsonText::string(std::string_view s) {
  static const char* const hex = "0123456789abcdef";
  char buffer[64];
  if (s.size() + 2 <= sizeof buffer && std::none_of(s.begin(), s.end(), needs_escape)) {
    char* out = buffer;
    *out++ = '"';
    out = std::copy(s.begin(), s.end(), out);
    *out++ = '"';
    text_.append(buffer, static_cast<std::size_t>(out - buffer));
    return *this;
  }
  text_.push_back('"');
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    switch (c) {
      case '"': text_.append("\\\""); break;
      case '\\': text_.append("\\\\"); break;
      case '\n': text_.append("\\n"); break;
      case '\r': text_.append("\\r"); break;
      case '\t': text_.append("\\t"); break;
      default:
        if (u < 0x20) {
          text_.append("\\u00");
          text_.push_back(hex[u >> 4]);
          text_.push_back(hex[u & 15]);
        } else {
          text_.push_back(c);
        }
    }
  }
  text_.push_back('"');
  return *this;
}

JsonText& JsonText::number(double x) {
  if (!std::isfinite(x)) return null();
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  text_.append(buffer, static_cast<std::size_t>(result.ptr - buffer));
  return *this;
}

JsonText& JsonText::number(std::size_t n) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, n);
  text_.append(buffer, static_cast<std::size_t>(result.ptr - buffer));
  return *this;
}

JsonText& JsonText::number(int n) {
  char buffer[16];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, n);
  text_.append(buffer, static_cast<std::size_t>(result.ptr - buffer));
  return *this;
}

JsonText& JsonText::vec3(const Vec3& p) {
  text_.push_back('[');
  number(p.x);
  text_.push_back(',');
  number(p.y);
  text_.push_back(',');
  number(p.z);
  text_.push_back(']');
  return *this;
}

JsonText& JsonText::optional(std::size_t n, std::size_t none) { return n == none ? null() : number(n); }

}  // namespace snag::report
