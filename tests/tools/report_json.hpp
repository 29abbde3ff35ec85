// Tests read a whole (small) JSON Lines report into one nlohmann::json
// document, independently of the report library's reader: "header", "frames",
// "events", "regions", "tracks" (arrays of the records, "record" key kept) and
// "trailer", plus the header's "version", "objects", "settings", "certified"
// and the trailer's "summary" at the top level.
#pragma once

#include <fstream>
#include <sstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace snag::test {

inline nlohmann::json parse_report_lines(std::istream& in, const std::string& what) {
  using nlohmann::json;
  json report = {{"frames", json::array()}, {"events", json::array()}, {"regions", json::array()},
                 {"tracks", json::array()}};
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    json record = json::parse(line);
    const std::string kind = record.at("record").get<std::string>();
    if (kind == "header") {
      report["header"] = record;
    } else if (kind == "frame") {
      report["frames"].push_back(record);
    } else if (kind == "event") {
      report["events"].push_back(record);
    } else if (kind == "region") {
      report["regions"].push_back(record);
    } else if (kind == "track") {
      report["tracks"].push_back(record);
    } else if (kind == "trailer") {
      report["trailer"] = record;
    } else {
      throw std::runtime_error(what + ":" + std::to_string(number) + ": unknown record " + kind);
    }
  }
  if (!report.contains("header") || !report.contains("trailer")) {
    throw std::runtime_error(what + ": no header or no trailer");
  }
  for (const char* key : {"version", "objects", "settings", "certified"}) report[key] = report["header"][key];
  report["summary"] = report["trailer"]["summary"];
  return report;
}

inline nlohmann::json load_report(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  return parse_report_lines(in, path);
}

inline nlohmann::json parse_report_text(const std::string& text) {
  std::istringstream in(text);
  return parse_report_lines(in, "report");
}

}  // namespace snag::test
