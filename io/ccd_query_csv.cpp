#include "io/ccd_query_csv.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "libcd/core/error.hpp"

namespace snag::io {

namespace {

/// Parses an optionally signed decimal integer that fits in int64.
bool parse_int64(const std::string& text, std::int64_t& value) {
  std::size_t i = 0;
  bool negative = false;
  if (i < text.size() && (text[i] == '-' || text[i] == '+')) negative = text[i++] == '-';
  if (i == text.size()) return false;
  unsigned long long magnitude = 0;
  for (; i < text.size(); ++i) {
    if (text[i] < '0' || text[i] > '9') return false;
    const unsigned digit = static_cast<unsigned>(text[i] - '0');
    if (magnitude > (std::numeric_limits<unsigned long long>::max() - digit) / 10) return false;
    magnitude = magnitude * 10 + digit;
  }
  if (magnitude > static_cast<unsigned long long>(std::numeric_limits<std::int64_t>::max())) return false;
  value = negative ? -static_cast<std::int64_t>(magnitude) : static_cast<std::int64_t>(magnitude);
  return true;
}

/// Returns k when the decimal text is 2^k (any size), -1 otherwise.
int power_of_two_exponent(std::string digits) {
  if (digits.empty() || digits.size() > 400) return -1;
  for (char c : digits) {
    if (c < '0' || c > '9') return -1;
  }
  int exponent = 0;
  while (true) {
    digits.erase(0, std::min(digits.find_first_not_of('0'), digits.size()));
    if (digits.empty()) return -1;  // zero
    if (digits == "1") return exponent;
    if ((digits.back() - '0') % 2 != 0) return -1;
    std::string half;
    int carry = 0;
    for (char c : digits) {
      const int current = carry * 10 + (c - '0');
      half.push_back(static_cast<char>('0' + current / 2));
      carry = current % 2;
    }
    digits = half;
    ++exponent;
  }
}

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    std::string field = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    while (!field.empty() && (field.back() == ' ' || field.back() == '\t')) field.pop_back();
    while (!field.empty() && (field.front() == ' ' || field.front() == '\t')) field.erase(0, 1);
    fields.push_back(field);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return fields;
}

ExactCoordinate parse_coordinate(const std::string& numerator, const std::string& denominator,
                                 const InputLocation& where, double& value) {
  ExactCoordinate exact;
  exact.numerator_text = numerator;
  exact.denominator_text = denominator;
  if (!parse_int64(numerator, exact.numerator)) {
    throw InputError(where, "numerator '" + numerator + "' is not an integer that fits in 64 bits");
  }
  exact.denominator_log2 = power_of_two_exponent(denominator);
  if (exact.denominator_log2 < 0) {
    throw InputError(where, "denominator '" + denominator + "' is not a positive power of two");
  }
  const double numerator_value = static_cast<double>(exact.numerator);
  // Exact when the conversion round-trips (2^63 itself cannot occur: the
  // numerator is below it, and a double that rounds up to 2^63 fails here).
  if (!(std::fabs(numerator_value) < 0x1p63) || static_cast<std::int64_t>(numerator_value) != exact.numerator) {
    throw InputError(where, "numerator '" + numerator + "' is not exactly representable as a double");
  }
  value = std::ldexp(numerator_value, -exact.denominator_log2);
  if (exact.numerator != 0 && std::ldexp(value, exact.denominator_log2) != numerator_value) {
    throw InputError(where, "coordinate " + numerator + "/" + denominator +
                                " is not exactly representable as a double (underflow)");
  }
  return exact;
}

}  // namespace

std::vector<CcdQuery> read_ccd_query_csv(const std::string& path, bool is_edge_edge) {
  std::ifstream in(path);
  if (!in) throw InputError({path}, "cannot open the query file");
  std::vector<CcdQuery> queries;
  CcdQuery query;
  int row = 0;
  std::size_t line_number = 0;
  std::string line;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    const InputLocation where{path, line_number};
    const std::vector<std::string> fields = split_commas(line);
    if (fields.size() != 7) {
      throw InputError(where, "expected 7 columns (xnum,xden,ynum,yden,znum,zden,truth), found " +
                                  std::to_string(fields.size()));
    }
    if (row == 0) {
      query = CcdQuery{};
      query.is_edge_edge = is_edge_edge;
      query.file = path;
      query.line = line_number;
    }
    for (int axis = 0; axis < 3; ++axis) {
      double value = 0;
      query.exact[row][axis] = parse_coordinate(fields[2 * axis], fields[2 * axis + 1], where, value);
      query.points[row][axis] = value;
    }
    if (fields[6] != "0" && fields[6] != "1") {
      throw InputError(where, "truth column must be 0 or 1, found '" + fields[6] + "'");
    }
    const bool truth = fields[6] == "1";
    if (row == 0) {
      query.truth = truth;
    } else if (truth != query.truth) {
      throw InputError(where, "truth differs from the first row of its query (line " + std::to_string(query.line) +
                                  ")");
    }
    if (++row == 8) {
      queries.push_back(query);
      row = 0;
    }
  }
  if (in.bad()) throw InputError({path, line_number}, "read error");
  if (row != 0) {
    throw InputError({path, line_number}, "the last query has " + std::to_string(row) +
                                              " rows; every query has 8");
  }
  return queries;
}

std::vector<CcdQuery> read_ccd_query_tree(const std::string& root) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_directory(root, error)) throw InputError({root}, "not a folder of CCD queries");
  std::vector<fs::path> files;
  for (fs::recursive_directory_iterator it(root, error), end; !error && it != end; it.increment(error)) {
    if (!it->is_regular_file() || it->path().extension() != ".csv") continue;
    const std::string kind = it->path().parent_path().filename().string();
    if (kind == "vertex-face" || kind == "edge-edge") files.push_back(it->path());
  }
  if (error) throw InputError({root}, "cannot list the folder: " + error.message());
  std::sort(files.begin(), files.end());
  std::vector<CcdQuery> queries;
  for (const fs::path& file : files) {
    std::vector<CcdQuery> part =
        read_ccd_query_csv(file.string(), file.parent_path().filename().string() == "edge-edge");
    queries.insert(queries.end(), part.begin(), part.end());
  }
  return queries;
}

}  // namespace snag::io
