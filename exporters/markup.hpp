// Escaping text for XML (JUnit) and HTML pages: the markup characters as
// entities, line breaks and tabs as character references (so that attribute
// values keep them), and the other control characters, which XML 1.0 cannot
// hold, as '?'.
#pragma once

#include <string>
#include <string_view>

namespace snag::exporters {

inline std::string markup_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      case '\n': out += "&#10;"; break;
      case '\t': out += "&#9;"; break;
      default: out += static_cast<unsigned char>(c) < 0x20 ? '?' : c;
    }
  }
  return out;
}

}  // namespace snag::exporters
