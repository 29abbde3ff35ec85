// JsonText writes each piece straight into room at its text's end; these
// tests hold its strings to a character-by-character escape written straight
// from RFC 8259 section 7, and its numbers to std::to_chars.
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
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
    const int length = static_cast<int>(random() % 100);  // short and long names
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
  const std::string long_name(70, 'k');
  JsonText more;
  more.key(long_name, true).null().key(long_name).null();
  EXPECT_EQ(more.text(), "\"" + long_name + "\":null,\"" + long_name + "\":null");
}

// Every piece written straight into the room at the text's end, across the
// text's growth, against the same pieces appended to a std::string: doubles
// of every exponent and sign (the longest shortest text, 24 characters,
// among them), counts and ints.
TEST(JsonText, NumbersMatchToCharsAcrossGrowth) {
  std::mt19937_64 random(14);
  std::string expected;
  JsonText text;
  auto to_text = [](auto x) {
    char buffer[64];
    return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);
  };
  const double extremes[] = {-2.2250738585072014e-308, -1.7976931348623157e308, 4.9406564584124654e-324, -0.0, 0.1};
  for (const double x : extremes) {
    text.number(x).raw(",");
    expected += to_text(x) + ",";
  }
  for (int k = 0; k < 20000; ++k) {
    const std::uint64_t bits = random();
    double x;
    std::memcpy(&x, &bits, sizeof x);
    if (!std::isfinite(x)) {
      text.number(x);
      expected += "null";
    } else if (k % 3 == 0) {
      text.number(static_cast<std::size_t>(bits));
      expected += to_text(static_cast<std::size_t>(bits));
    } else if (k % 3 == 1) {
      text.number(static_cast<int>(bits));
      expected += to_text(static_cast<int>(bits));
    } else {
      text.vec3({x, -x, x * 0.5});
      expected += "[" + to_text(x) + "," + to_text(-x) + "," + to_text(x * 0.5) + "]";
    }
    text.key("k");
    expected += ",\"k\":";
  }
  EXPECT_EQ(text.text(), expected);
  text.clear();
  text.raw("{}");
  EXPECT_EQ(text.text(), "{}");
}

}  // namespace
}  // namespace snag::report
