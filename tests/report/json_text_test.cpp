// JsonText writes keys and strings in one copy; these tests hold its text to
// a character-by-character escape written straight from RFC 8259 section 7.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>

#include "report/json_text.hpp"

namespace snag::report {
namespace {

std::string reference_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"') {
      out += "\\\"";
    } else if (c == '\\') {
      out += "\\\\";
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else if (u < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", u);
      out += buffer;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

TEST(JsonText, StringsMatchACharacterByCharacterEscape) {
  std::mt19937 random(14);
  // Plain text, quotes, backslashes, control characters and UTF-8 bytes.
  const std::string alphabet = std::string("abcXYZ019 _-./\"\\\n\r\t\x01\x1f\x7f") + "\xc3\xa9";
  for (int round = 0; round < 2000; ++round) {
    std::string s;
    const int length = static_cast<int>(random() % 100);  // past the 62 characters written in one copy
    const bool plain = round % 2 == 0;  // half without anything to escape: the one-copy path
    for (int k = 0; k < length; ++k) {
      const char c = alphabet[random() % alphabet.size()];
      if (plain && (c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20)) continue;
      s += c;
    }
    JsonText text;
    text.raw("[").string(s).raw(",").string(s).raw("]");
    EXPECT_EQ(text.text(), "[" + reference_string(s) + "," + reference_string(s) + "]") << "round " << round;
  }
}

TEST(JsonText, KeysWithAndWithoutTheComma) {
  JsonText text;
  text.raw("{").key("record", true).string("event").key("frame").number(std::size_t{12}).key("").null().raw("}");
  EXPECT_EQ(text.text(), R"({"record":"event","frame":12,"":null})");
  const std::string long_name(70, 'k');  // longer than one copy takes
  JsonText more;
  more.key(long_name, true).null().key(long_name).null();
  EXPECT_EQ(more.text(), "\"" + long_name + "\":null,\"" + long_name + "\":null");
}

}  // namespace
}  // namespace snag::report
