#include "tools/common/stages_merge.hpp"

#include <algorithm>
#include <set>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace snag::tools {

using nlohmann::json;

namespace {

// Keys a scan keeps from its last step or frame, and keys that are peaks.
const std::set<std::string> kLastValue = {"cell_size", "grid"};
const std::set<std::string> kLargest = {"peak_memory_bytes", "subdivision_levels", "deepest_level"};

void add_into(json& total, const json& part) {
  if (total.is_object()) {
    for (auto& [key, value] : part.items()) {
      if (!total.contains(key)) {
        total[key] = value;
      } else if (kLastValue.count(key)) {
        total[key] = value;
      } else if (kLargest.count(key)) {
        total[key] = std::max(total[key].get<std::uint64_t>(), value.get<std::uint64_t>());
      } else {
        add_into(total[key], value);
      }
    }
  } else if (total.is_array()) {  // per-level counts: level by level
    for (std::size_t i = 0; i < part.size(); ++i) {
      if (i < total.size()) {
        add_into(total[i], part[i]);
      } else {
        total.push_back(part[i]);
      }
    }
  } else if (total.is_number_unsigned() && part.is_number_unsigned()) {
    total = total.get<std::uint64_t>() + part.get<std::uint64_t>();
  } else if (total.is_number() && part.is_number()) {
    total = total.get<double>() + part.get<double>();
  } else {
    throw std::invalid_argument("stage objects of different shapes");
  }
}

json merged(const std::vector<std::string>& ranges) {
  json total = json::object();
  for (const std::string& text : ranges) {
    const json part = json::parse(text);
    if (!part.is_object()) throw std::invalid_argument("a stage object is not an object");
    add_into(total, part);
  }
  return total;
}

}  // namespace

std::string merge_stages_json(const std::vector<std::string>& ranges) {
  json total = merged(ranges);
  if (total.contains("narrow_phase")) {
    json& n = total["narrow_phase"];
    // As scan_stats.cpp works it out from the summed counters.
    const std::size_t ccd_tests = n.value("vf_tests", std::size_t{0}) + n.value("ee_tests", std::size_t{0});
    const std::size_t exact = n.value("exact_queries", std::size_t{0});
    n["exact_fraction"] = ccd_tests == 0 ? 0.0 : static_cast<double>(exact) / ccd_tests;
  }
  return total.dump();
}

std::string merge_timing_json(const std::vector<std::string>& ranges, double total_seconds) {
  json total = merged(ranges);
  total["total"] = total_seconds;
  return total.dump();
}

}  // namespace snag::tools
