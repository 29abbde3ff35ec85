#include "exporters/markdown.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "report/summary.hpp"

namespace snag::exporters {

namespace {

// Text for a table cell or a heading: characters Markdown would read as markup escaped, line breaks removed.
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\n' || c == '\r') {
      out += ' ';
      continue;
    }
    if (c == '|' || c == '\\' || c == '*' || c == '_' || c == '`' || c == '<' || c == '>' || c == '[' ||
        c == ']') {
      out += '\\';
    }
    out += c;
  }
  return out;
}

std::string number(double value) {
  if (!std::isfinite(value)) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

// A time of impact in frames, absolute: "20.0435".
std::string time_of_impact(double toi) {
  if (!std::isfinite(toi)) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.4f", toi);
  return text;
}

std::string frames_text(std::size_t first, std::size_t last) {
  return first == last ? std::to_string(first) : std::to_string(first) + "-" + std::to_string(last);
}

void write_report(std::ostream& out, const ReportDigest& digest) {
  const report::Header& header = digest.header;
  const report::Trailer& t = digest.trailer;
  out << "## " << (t.pass ? "pass" : "FAIL") << ": " << cell(report_stem(digest.path)) << "\n\n";
  out << "`" << digest.path << "`: " << t.frames << " frames, " << header.objects.size() << " objects; " << t.events
      << " events (" << t.collisions << " collisions, " << t.intersections << " intersections), " << t.regions
      << " regions, " << t.tracks << " tracks";
  if (t.allowed > 0) out << "; " << t.allowed << " allowed";
  out << ".\n\n";
  out << "**Verdict: " << cell(report::verdict_text(t)) << "**\n\n";

  out << "| pair | kind | events | regions | tracks | frames | worst frame | allowed | result |\n";
  out << "|:--|:--|--:|--:|--:|--:|:--|--:|:--|\n";
  for (const report::PairSummary& p : checked_pairs(digest)) {
    const std::string worst = p.events > 0 ? std::to_string(p.worst_frame) + " (" +
                                                 std::to_string(p.worst_frame_events) + " events)"
                                           : "-";
    out << "| " << cell(pair_label(header, p.object_a, p.object_b)) << " | " << report::kind_name(p.kind) << " | "
        << p.events << " | " << p.regions << " | " << p.tracks << " | " << p.frames << " | " << worst << " | "
        << p.allowed << " | " << (pair_fails(t, p) ? "FAIL" : "pass") << " |\n";
  }
  out << "\n";

  if (!t.largest_tracks.empty()) {
    out << "Largest tracks:\n\n";
    out << "| track | pair | kind | frames | events | faces (frame) | around | first contact |\n";
    out << "|--:|:--|:--|:--|--:|:--|:--|--:|\n";
    for (const report::TrackRecord& track : t.largest_tracks) {
      out << "| " << track.id << " | " << cell(pair_label(header, track.object_a, track.object_b)) << " | "
          << report::kind_name(track.kind) << " | " << frames_text(track.first_frame, track.last_frame) << " ("
          << track.frames << ") | " << track.events << " | " << track.max_faces << " (" << track.worst_frame
          << ") | (" << number(track.centroid.x) << ", " << number(track.centroid.y) << ", "
          << number(track.centroid.z) << ") | "
          << (track.kind == EventKind::kCollision ? time_of_impact(track.toi) : std::string("-")) << " |\n";
    }
    out << "\n";
  }
  if (t.left_out > 0) {
    out << t.listed << " of " << t.listed + t.left_out << " events are listed in the report; regions cover all.\n\n";
  }
}

}  // namespace

void write_markdown(std::ostream& out, const std::vector<ReportDigest>& reports) {
  const std::size_t failed = std::count_if(reports.begin(), reports.end(),
                                           [](const ReportDigest& d) { return !d.trailer.pass; });
  out << "# snag: ";
  if (failed == 0) {
    out << (reports.size() == 1 ? "pass" : "all " + std::to_string(reports.size()) + " reports pass");
  } else {
    out << "FAIL";
    if (reports.size() > 1) out << " (" << failed << " of " << reports.size() << " reports)";
  }
  out << "\n\n";
  for (const ReportDigest& digest : reports) write_report(out, digest);
}

}  // namespace snag::exporters
