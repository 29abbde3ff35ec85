#include "exporters/junit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "exporters/markup.hpp"
#include "report/summary.hpp"

namespace snag::exporters {

namespace {

constexpr std::size_t kMaxListedIds = 32;     // face ids listed per object in a failure
constexpr std::size_t kMaxListedTracks = 20;  // tracks listed in a pair's failure text

std::string xml_escape(const std::string& text) { return markup_escape(text); }

// Content text keeps its line breaks.
std::string xml_text(const std::string& text) {
  std::string out = xml_escape(text);
  for (std::size_t at = out.find("&#10;"); at != std::string::npos; at = out.find("&#10;", at + 1)) {
    out.replace(at, 5, "\n");
  }
  return out;
}

std::string number(double value) {
  if (!std::isfinite(value)) return "null";
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

std::string point(const Vec3& p) { return "(" + number(p.x) + ", " + number(p.y) + ", " + number(p.z) + ")"; }

std::string frames_text(std::size_t first, std::size_t last) {
  return first == last ? "frame " + std::to_string(first)
                       : "frames " + std::to_string(first) + "-" + std::to_string(last);
}

std::string ids_text(const std::vector<std::size_t>& ids) {
  std::string text;
  for (std::size_t i = 0; i < ids.size() && i < kMaxListedIds; ++i) text += (i ? " " : "") + std::to_string(ids[i]);
  if (ids.size() > kMaxListedIds) text += " ... (" + std::to_string(ids.size() - kMaxListedIds) + " more)";
  return text;
}

// "region 45 at frame 21: 105 faces around (x, y, z): cloth faces 1 2 3; body faces 7 8"
std::string region_text(const ReportDigest& digest, const report::RegionRecord& region) {
  std::string text = "region " + std::to_string(region.id) + " at frame " + std::to_string(region.frame) + ": " +
                     std::to_string(region.faces_a.size() + region.faces_b.size()) + " faces around " + point(region.centroid);
  const auto& objects = digest.header.objects;
  auto name = [&](std::size_t o) { return o < objects.size() ? objects[o].name : std::string("?"); };
  if (!region.faces_a.empty()) text += ": " + name(region.object_a) + " faces " + ids_text(region.faces_a);
  if (!region.faces_b.empty()) text += "; " + name(region.object_b) + " faces " + ids_text(region.faces_b);
  return text;
}

std::string track_text(const report::TrackRecord& t) {
  std::string text = "track " + std::to_string(t.id) + ": " + frames_text(t.first_frame, t.last_frame) + " (" +
                     std::to_string(t.frames) + "), " + std::to_string(t.events) + " events, up to " +
                     std::to_string(t.max_faces) + " faces (frame " + std::to_string(t.worst_frame) +
                     ") around " + point(t.centroid);
  if (t.kind == EventKind::kCollision) text += ", first contact at " + number(t.toi);
  return text;
}

bool same_pair(const report::PairSummary& p, EventKind kind, std::size_t a, std::size_t b) {
  return p.kind == kind && p.object_a == a && p.object_b == b;
}

// The tracks of one pair and kind that did not merge, largest (by events) first.
std::vector<const report::TrackRecord*> tracks_of(const ReportDigest& digest, const report::PairSummary& p) {
  std::vector<const report::TrackRecord*> tracks;
  for (const report::TrackRecord& t : digest.tracks) {
    if (t.merged_into == report::kNone && same_pair(p, t.kind, t.object_a, t.object_b)) tracks.push_back(&t);
  }
  std::stable_sort(tracks.begin(), tracks.end(),
                   [](const report::TrackRecord* x, const report::TrackRecord* y) { return x->events > y->events; });
  return tracks;
}

struct TestCase {
  std::string name;
  bool failed = false;
  std::string message, type, failure_text, out_text;
};

std::string counts_text(const report::PairSummary& p) {
  std::string text = std::to_string(p.events) + " " + report::kind_name(p.kind) + "s in " +
                     std::to_string(p.frames) + " frames";
  if (p.events > 0) {
    text += " (worst " + std::to_string(p.worst_frame) + ": " + std::to_string(p.worst_frame_events) + " events)";
  }
  text += ", " + std::to_string(p.regions) + " regions, " + std::to_string(p.tracks) + " tracks";
  if (p.allowed > 0) text += "; " + std::to_string(p.allowed) + " allowed";
  return text;
}

// Output for a case that passes: what the rules allowed, or what was found under the thresholds.
std::string passing_text(const report::PairSummary& p) {
  if (p.events > 0) return counts_text(p) + "; not over the report's thresholds";
  if (p.allowed > 0) return std::to_string(p.allowed) + " events allowed by the rules";
  return "";
}

TestCase pair_case(const ReportDigest& digest, const report::PairSummary& p) {
  TestCase c;
  c.name = pair_label(digest.header, p.object_a, p.object_b) + " " + report::kind_name(p.kind);
  c.failed = pair_fails(digest.trailer, p);
  if (!c.failed) {
    c.out_text = passing_text(p);
    return c;
  }
  const std::vector<const report::TrackRecord*> tracks = tracks_of(digest, p);
  const report::RegionRecord* largest = nullptr;
  for (const report::TrackRecord* t : tracks) {
    auto found = digest.largest_region.find(t->id);
    if (found == digest.largest_region.end()) continue;
    auto faces = [](const report::RegionRecord& r) { return r.faces_a.size() + r.faces_b.size(); };
    if (!largest || faces(found->second) > faces(*largest) ||
        (faces(found->second) == faces(*largest) && found->second.id < largest->id)) {
      largest = &found->second;
    }
  }
  c.type = std::string("snag.") + report::kind_name(p.kind);
  c.message = counts_text(p);
  if (largest) c.message += "; largest " + region_text(digest, *largest);
  for (std::size_t i = 0; i < tracks.size() && i < kMaxListedTracks; ++i) c.failure_text += track_text(*tracks[i]) + "\n";
  if (tracks.size() > kMaxListedTracks) {
    c.failure_text += "... " + std::to_string(tracks.size() - kMaxListedTracks) + " more tracks\n";
  }
  if (largest) c.failure_text += "largest " + region_text(digest, *largest) + "\n";
  return c;
}

std::vector<TestCase> track_cases(const ReportDigest& digest, const report::PairSummary& p) {
  const std::vector<const report::TrackRecord*> tracks = tracks_of(digest, p);
  if (tracks.empty()) return {pair_case(digest, p)};
  std::vector<const report::TrackRecord*> by_id = tracks;
  std::sort(by_id.begin(), by_id.end(),
            [](const report::TrackRecord* x, const report::TrackRecord* y) { return x->id < y->id; });
  const bool failed = pair_fails(digest.trailer, p);
  std::vector<TestCase> cases;
  for (const report::TrackRecord* t : by_id) {
    TestCase c;
    c.name = pair_label(digest.header, p.object_a, p.object_b) + " " + report::kind_name(p.kind) + " track " +
             std::to_string(t->id);
    c.failed = failed;
    std::string text = track_text(*t);
    auto largest = digest.largest_region.find(t->id);
    if (largest != digest.largest_region.end()) text += "; largest " + region_text(digest, largest->second);
    if (failed) {
      c.type = std::string("snag.") + report::kind_name(p.kind);
      c.message = text;
    } else {
      c.out_text = text + "; not over the report's thresholds";
    }
    cases.push_back(std::move(c));
  }
  return cases;
}

double total_seconds(const report::Trailer& trailer) {
  const nlohmann::json timing = nlohmann::json::parse(trailer.timing_json, nullptr, false);
  if (timing.is_object() && timing.contains("total") && timing["total"].is_number()) {
    return timing["total"].get<double>();
  }
  return 0;
}

void write_property(std::ostream& out, const std::string& name, const std::string& value) {
  out << "      <property name=\"" << xml_escape(name) << "\" value=\"" << xml_escape(value) << "\"/>\n";
}

// classname "snag.<stem>": dots in the stem would read as package separators.
std::string class_name(const ReportDigest& digest) {
  std::string stem = report_stem(digest.path);
  std::replace(stem.begin(), stem.end(), '.', '_');
  return "snag." + stem;
}

}  // namespace

void write_junit(std::ostream& out, const std::vector<ReportDigest>& reports, JunitGranularity granularity) {
  std::vector<std::vector<TestCase>> suites;
  std::size_t tests = 0, failures = 0;
  double seconds = 0;
  for (const ReportDigest& digest : reports) {
    std::vector<TestCase> cases;
    for (const report::PairSummary& p : checked_pairs(digest)) {
      if (granularity == JunitGranularity::kPair) {
        cases.push_back(pair_case(digest, p));
      } else {
        for (TestCase& c : track_cases(digest, p)) cases.push_back(std::move(c));
      }
    }
    tests += cases.size();
    failures += std::count_if(cases.begin(), cases.end(), [](const TestCase& c) { return c.failed; });
    seconds += total_seconds(digest.trailer);
    suites.push_back(std::move(cases));
  }

  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out << "<testsuites name=\"snag\" tests=\"" << tests << "\" failures=\"" << failures << "\" errors=\"0\" time=\""
      << number(seconds) << "\">\n";
  for (std::size_t s = 0; s < reports.size(); ++s) {
    const ReportDigest& digest = reports[s];
    const report::Header& header = digest.header;
    const report::ReportSettings& settings = header.settings;
    const std::vector<TestCase>& cases = suites[s];
    const std::size_t suite_failures =
        std::count_if(cases.begin(), cases.end(), [](const TestCase& c) { return c.failed; });
    const std::string classname = class_name(digest);
    out << "  <testsuite name=\"" << xml_escape(classname) << "\" tests=\"" << cases.size() << "\" failures=\""
        << suite_failures << "\" errors=\"0\" skipped=\"0\" time=\"" << number(total_seconds(digest.trailer))
        << "\" id=\"" << s << "\" package=\"snag\">\n";
    out << "    <properties>\n";
    write_property(out, "report", digest.path);
    write_property(out, "snag_version", header.snag_version);
    write_property(out, "source", header.source);
    write_property(out, "verdict", report::verdict_text(digest.trailer));
    write_property(out, "frames", std::to_string(digest.trailer.frames));
    write_property(out, "settings.mode", settings.mode);
    write_property(out, "settings.backend", settings.backend);
    write_property(out, "settings.precision", settings.precision);
    write_property(out, "settings.thickness", number(settings.thickness));
    write_property(out, "settings.grid", settings.grid);
    write_property(out, "settings.frames", settings.frames);
    write_property(out, "settings.weld", settings.weld);
    write_property(out, "settings.events", settings.events);
    write_property(out, "settings.manifest", settings.manifest);
    out << "    </properties>\n";
    for (const TestCase& c : cases) {
      out << "    <testcase name=\"" << xml_escape(c.name) << "\" classname=\"" << xml_escape(classname) << "\"";
      if (!c.failed && c.out_text.empty()) {
        out << "/>\n";
        continue;
      }
      out << ">\n";
      if (c.failed) {
        out << "      <failure message=\"" << xml_escape(c.message) << "\" type=\"" << xml_escape(c.type) << "\">"
            << xml_text(c.failure_text) << "</failure>\n";
      }
      if (!c.out_text.empty()) out << "      <system-out>" << xml_text(c.out_text) << "</system-out>\n";
      out << "    </testcase>\n";
    }
    out << "    <system-out>" << xml_text(digest.path + "\n" + summary_text(digest)) << "</system-out>\n";
    out << "  </testsuite>\n";
  }
  out << "</testsuites>\n";
}

}  // namespace snag::exporters
