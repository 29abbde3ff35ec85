#include "io/decimal.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace snag::io {
namespace {

/// parse_double and std::from_chars on `text`: the same end, error and
/// value, bit for bit (a value from_chars leaves alone stays as it was).
void expect_as_from_chars(const std::string& text) {
  double ours = 12345.0, theirs = 12345.0;
  const char* first = text.data();
  const char* last = first + text.size();
  const std::from_chars_result a = parse_double(first, last, ours);
  const std::from_chars_result b = std::from_chars(first, last, theirs);
  EXPECT_EQ(a.ptr - first, b.ptr - first) << '"' << text << '"';
  EXPECT_EQ(a.ec, b.ec) << '"' << text << '"';
  EXPECT_EQ(std::memcmp(&ours, &theirs, sizeof ours), 0) << '"' << text << "\": " << ours << " vs " << theirs;
}

TEST(Decimal, ReadsWhatFromCharsReadsOnHandPickedText) {
  for (const char* text : {"0",
                           "-0",
                           "0.0",
                           "-0.000000",
                           "1",
                           "1.",
                           "1.5",
                           ".5",
                           "-.5",
                           "+1",
                           "-",
                           "",
                           ".",
                           "-.",
                           "1e5",
                           "1E-3",
                           "1.5e",
                           "2.5.1",
                           "1..2",
                           "12 34",
                           "7\n",
                           "3x",
                           "0x1p3",
                           "inf",
                           "-nan",
                           "infinity",
                           "9007199254740992",
                           "9007199254740993",
                           "9007199254740993.0",
                           "0.9007199254740993",
                           "1234567890123456789",
                           "12345678901234567890",
                           "0.1234567890123456789",
                           "0.00000000000000000001",
                           "0.1",
                           "0.2",
                           "0.3",
                           "1.00000000000000011102230246251565404236316680908203125",
                           "4503599627370497.5",
                           "-123.456789 ",
                           "5e-324",
                           "1e400",
                           "00000000000000000001.5",
                           "1.0000000000000000000",
                           "999999999999999999.9"})
    expect_as_from_chars(text);
}

TEST(Decimal, ReadsWhatFromCharsReadsOnPrintedDoubles) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> scale(-30, 30), precision(0, 20);
  const char* formats[] = {"%.*f", "%.*g", "%.*e"};
  char text[512];
  for (int i = 0; i < 200000; ++i) {
    const double value = unit(random) * std::pow(10.0, scale(random));
    std::snprintf(text, sizeof text, formats[i % 3], precision(random), value);
    expect_as_from_chars(text);
    expect_as_from_chars(std::string(text) + " 1");
  }
}

TEST(Decimal, ReadsWhatFromCharsReadsOnRandomDigitsAndPoints) {
  std::mt19937_64 random(11);
  const std::string alphabet = "0123456789.-e+ ";
  std::uniform_int_distribution<std::size_t> pick(0, alphabet.size() - 1), length(0, 24);
  std::uniform_int_distribution<int> digit(0, 9);
  for (int i = 0; i < 200000; ++i) {
    std::string text;
    const std::size_t n = length(random);
    for (std::size_t k = 0; k < n; ++k)  // mostly digits
      text += k % 3 == 2 ? alphabet[pick(random)] : static_cast<char>('0' + digit(random));
    expect_as_from_chars(text);
  }
}

}  // namespace
}  // namespace snag::io
