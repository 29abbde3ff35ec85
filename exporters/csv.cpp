#include "exporters/csv.hpp"

#include <cmath>
#include <cstdio>

#include "report/report_reader.hpp"

namespace snag::exporters {

namespace {

// Writes fields of one row, quoting as RFC 4180 asks.
class CsvRow {
 public:
  explicit CsvRow(std::ostream& out) : out_(out) {}
  ~CsvRow() { out_ << "\r\n"; }
  CsvRow(const CsvRow&) = delete;
  CsvRow& operator=(const CsvRow&) = delete;

  CsvRow& text(const std::string& field) {
    separate();
    if (field.find_first_of(",\"\r\n") == std::string::npos) {
      out_ << field;
      return *this;
    }
    out_ << '"';
    for (char c : field) {
      if (c == '"') out_ << '"';
      out_ << c;
    }
    out_ << '"';
    return *this;
  }
  CsvRow& count(std::size_t value) { return text(std::to_string(value)); }
  /// Text that reads back to the same double (17 significant digits); empty when not finite.
  CsvRow& real(double value) {
    if (!std::isfinite(value)) return text("");
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.17g", value);
    return text(buffer);
  }
  CsvRow& point(const Vec3& p) { return real(p.x).real(p.y).real(p.z); }
  CsvRow& empty(std::size_t fields = 1) {
    for (std::size_t i = 0; i < fields; ++i) text("");
    return *this;
  }

 private:
  void separate() {
    if (!first_) out_ << ',';
    first_ = false;
  }
  std::ostream& out_;
  bool first_ = true;
};

std::string object_name(const report::Header& header, std::size_t o) {
  return o < header.objects.size() ? header.objects[o].name : std::string("?");
}

void header_row(std::ostream& out, const std::vector<const char*>& names) {
  CsvRow row(out);
  for (const char* name : names) row.text(name);
}

// The element columns of one side of an event: element, id, id2.
void element(CsvRow& row, const report::EventRecord& e, const report::ElementRef& ref, bool side_a) {
  if (e.kind == EventKind::kIntersection) {
    row.text("face").count(ref.id).empty();
  } else if (e.type == ContactType::kEdgeEdge) {
    row.text("edge").count(ref.id).count(ref.id2);
  } else if (side_a) {
    row.text("vertex").count(ref.id).empty();
  } else {
    row.text("face").count(ref.id).empty();
  }
}

}  // namespace

void write_region_csv(std::ostream& out, const std::vector<ReportDigest>& reports) {
  header_row(out, {"report", "id", "kind", "object_a", "object_b", "frame", "track", "events", "face_count",
                   "bounds_lo_x", "bounds_lo_y", "bounds_lo_z", "bounds_hi_x", "bounds_hi_y", "bounds_hi_z",
                   "centroid_x", "centroid_y", "centroid_z", "toi"});
  for (const ReportDigest& digest : reports) {
    for (std::size_t i = 0; i < digest.regions.size(); ++i) {
      const report::RegionRecord& r = digest.regions[i];
      CsvRow row(out);
      row.text(digest.path).count(r.id).text(report::kind_name(r.kind));
      row.text(object_name(digest.header, r.object_a)).text(object_name(digest.header, r.object_b));
      row.count(r.frame).count(root_track_of(digest, r.track)).count(r.events).count(r.face_count);
      row.point(r.bounds.lo).point(r.bounds.hi).point(r.centroid);
      if (r.kind == EventKind::kCollision) {
        row.real(r.toi);
      } else {
        row.empty();
      }
    }
  }
}

void write_event_csv(std::ostream& out, const std::vector<std::string>& report_paths) {
  header_row(out, {"report", "kind", "type", "frame", "toi", "toi_lo", "toi_hi", "object_a", "a_element", "a_id",
                   "a_id2", "object_b", "b_element", "b_id", "b_id2", "position_x", "position_y", "position_z",
                   "certainty", "region", "allowed"});
  for (const std::string& path : report_paths) {
    report::ReportReader reader(path);
    const report::Header& header = reader.header();
    for (report::ReportReader::Record record = reader.next(); record != report::ReportReader::Record::kEnd;
         record = reader.next()) {
      if (record != report::ReportReader::Record::kEvent) continue;
      const report::EventRecord& e = reader.event();
      const bool collision = e.kind == EventKind::kCollision;
      CsvRow row(out);
      row.text(path).text(report::kind_name(e.kind)).text(collision ? report::type_name(e.type) : "");
      row.count(e.frame);
      if (collision) {
        row.real(e.toi).real(e.toi_lo).real(e.toi_hi);
      } else {
        row.empty(3);
      }
      row.text(object_name(header, e.a.object));
      element(row, e, e.a, true);
      row.text(object_name(header, e.b.object));
      element(row, e, e.b, false);
      row.point(e.position);
      row.text(collision ? (e.certainty == Certainty::kProven ? "proven" : "uncertain") : "");
      if (e.region == report::kNone) {
        row.empty();
      } else {
        row.count(e.region);
      }
      if (e.allowed == report::kNone) {
        row.empty();
      } else {
        row.count(e.allowed);
      }
    }
  }
}

}  // namespace snag::exporters
