#include "report/json_text.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>

namespace snag::report {

namespace {

bool needs_escape(char c) { return c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20; }

}  // namespace

void JsonText::grow(std::size_t n) {
  // Doubled, so that a text written piece by piece is copied a few times in
  // all; the bytes past the text are never read.
  buffer_.resize(std::max(2 * buffer_.size(), size_ + n));
}

JsonText& JsonText::string(std::string_view s) {
  static const char* const hex = "0123456789abcdef";
  char* const start = room(2 + 6 * s.size());  // each character escaped as \u00XX at the most
  char* out = start;
  *out++ = '"';
  if (std::none_of(s.begin(), s.end(), needs_escape)) {
    if (!s.empty()) std::memcpy(out, s.data(), s.size());
    out += s.size();
  } else {
    for (const char c : s) {
      const auto u = static_cast<unsigned char>(c);
      if (!needs_escape(c)) {
        *out++ = c;
        continue;
      }
      *out++ = '\\';
      switch (c) {
        case '"': *out++ = '"'; break;
        case '\\': *out++ = '\\'; break;
        case '\n': *out++ = 'n'; break;
        case '\r': *out++ = 'r'; break;
        case '\t': *out++ = 't'; break;
        default:
          out = std::copy_n("u00", 3, out);
          *out++ = hex[u >> 4];
          *out++ = hex[u & 15];
      }
    }
  }
  *out++ = '"';
  size_ += static_cast<std::size_t>(out - start);
  return *this;
}

// The room each number takes at the most: the shortest text of a double
// that reads back to it is at most 24 characters (-2.2250738585072014e-308),
// a 64-bit count 20 digits and an int a sign and 10 digits.
JsonText& JsonText::number(double x) {
  if (!std::isfinite(x)) return null();
  constexpr std::size_t kRoom = 32;
  char* const out = room(kRoom);
  size_ += static_cast<std::size_t>(std::to_chars(out, out + kRoom, x).ptr - out);
  return *this;
}

JsonText& JsonText::number(std::size_t n) {
  constexpr std::size_t kRoom = 24;
  char* const out = room(kRoom);
  size_ += static_cast<std::size_t>(std::to_chars(out, out + kRoom, n).ptr - out);
  return *this;
}

JsonText& JsonText::number(int n) {
  constexpr std::size_t kRoom = 16;
  char* const out = room(kRoom);
  size_ += static_cast<std::size_t>(std::to_chars(out, out + kRoom, n).ptr - out);
  return *this;
}

JsonText& JsonText::vec3(const Vec3& p) {
  raw("[").number(p.x).raw(",").number(p.y).raw(",").number(p.z);
  return raw("]");
}

JsonText& JsonText::optional(std::size_t n, std::size_t none) { return n == none ? null() : number(n); }

}  // namespace snag::report
