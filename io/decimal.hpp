// Doubles from decimal text, as std::from_chars reads them, fast for what
// mesh exporters write ("-0.123456", "12.5"): a number of at most 19 digits
// with no exponent whose digits, as an integer m, are at most 2^53, with k of
// them after the point, is m / 10^k. Both are exact doubles, so the one
// correctly rounded division gives the correctly rounded value (Clinger, "How
// to read floating point numbers accurately", PLDI 1990), the value
// from_chars gives. Any other text goes to std::from_chars itself.
#pragma once

#include <charconv>
#include <cstdint>

namespace snag::io {

/// std::from_chars(first, last, value) for doubles (general format), with
/// the same value, end and error for every input.
inline std::from_chars_result parse_double(const char* first, const char* last, double& value) {
  static constexpr double kPowersOfTen[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,
                                            1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19};  // k <= 19
  const char* p = first;
  const bool negative = p < last && *p == '-';
  if (negative) ++p;
  std::uint64_t digits = 0;
  int count = 0, after_point = 0;
  auto take_digits = [&](int& counted) {
    while (p < last && static_cast<unsigned char>(*p - '0') < 10 && count < 19) {
      digits = digits * 10 + static_cast<unsigned>(*p - '0');
      ++count;
      ++counted;
      ++p;
    }
  };
  int before_point = 0;
  take_digits(before_point);
  if (p < last && *p == '.') {
    ++p;
    take_digits(after_point);
  }
  const bool more = p < last && (static_cast<unsigned char>(*p - '0') < 10 || *p == 'e' || *p == 'E' || *p == '.');
  // "1." and ".5" are left to from_chars, as are long, large or exponent forms.
  if (before_point == 0 || (after_point == 0 && p[-1] == '.') || more || digits > (std::uint64_t{1} << 53))
    return std::from_chars(first, last, value);
  const double magnitude = static_cast<double>(digits) / kPowersOfTen[after_point];
  value = negative ? -magnitude : magnitude;
  return {p, std::errc()};
}

}  // namespace snag::io
