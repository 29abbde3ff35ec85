#include "exporters/html.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string_view>

#include "exporters/html_assets.hpp"
#include "exporters/html_decimation.hpp"
#include "exporters/markup.hpp"
#include "libcd/core/error.hpp"
#include "report/summary.hpp"

namespace snag::exporters {
namespace {

using nlohmann::json;

std::string html_escape(std::string_view text) { return markup_escape(text); }

/// The little-endian bytes of `values` (4-byte floats or integers) in base64;
/// the page decodes them with atob into typed arrays.
template <typename T>
std::string base64(const std::vector<T>& values) {
  static_assert(sizeof(T) == 4, "4-byte values");
  static const char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<unsigned char> bytes(values.size() * 4);
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint32_t word;
    std::memcpy(&word, &values[i], 4);
    for (int k = 0; k < 4; ++k) bytes[4 * i + k] = static_cast<unsigned char>(word >> (8 * k));
  }
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const unsigned b0 = bytes[i], b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0,
                   b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0;
    out += kDigits[b0 >> 2];
    out += kDigits[((b0 & 3) << 4) | (b1 >> 4)];
    out += i + 1 < bytes.size() ? kDigits[((b1 & 15) << 2) | (b2 >> 6)] : '=';
    out += i + 2 < bytes.size() ? kDigits[b2 & 63] : '=';
  }
  return out;
}

/// A number for the page: shortest round-trip text is long, 6 significant digits are plenty to read.
double rounded(double x) {
  if (!std::isfinite(x) || x == 0) return std::isfinite(x) ? x : 0;
  const double scale = std::pow(10.0, 5 - std::floor(std::log10(std::fabs(x))));
  return std::round(x * scale) / scale;
}

json vec3(const Vec3& p) { return json::array({rounded(p.x), rounded(p.y), rounded(p.z)}); }

std::string object_name(const ReportDigest& r, std::size_t o) {
  return o < r.header.objects.size() ? r.header.objects[o].name : "#" + std::to_string(o);
}

std::string pair_label(const ReportDigest& r, std::size_t a, std::size_t b) {
  return a == b ? object_name(r, a) + " (self)" : object_name(r, a) + " / " + object_name(r, b);
}

json track_json(const ReportDigest& r, const report::TrackRecord& t) {
  const bool collision = t.kind == EventKind::kCollision;
  return {{"id", t.id},
          {"kind", report::kind_name(t.kind)},
          {"objects", pair_label(r, t.object_a, t.object_b)},
          {"first_frame", t.first_frame},
          {"last_frame", t.last_frame},
          {"frames", t.frames},
          {"regions", t.regions},
          {"events", t.events},
          {"max_faces", t.max_faces},
          {"worst_frame", t.worst_frame},
          {"centroid", vec3(t.centroid)},
          {"size", vec3(t.bounds.hi - t.bounds.lo)},
          {"toi", collision && std::isfinite(t.toi) ? json(rounded(t.toi)) : json(nullptr)}};
}

/// Checks that `scene` fits report `r`; throws UsageError naming what does not.
void check_scene(const ReportDigest& r, const HtmlScene& scene) {
  const std::string where = "HTML page of " + r.path + ": ";
  if (scene.objects.size() != r.header.objects.size())
    throw UsageError(where + "the scene has " + std::to_string(scene.objects.size()) + " objects, the report " +
                     std::to_string(r.header.objects.size()));
  for (const HtmlFrame& frame : scene.frames) {
    if (frame.objects.size() != scene.objects.size())
      throw UsageError(where + "frame " + std::to_string(frame.frame) + " has positions of " +
                       std::to_string(frame.objects.size()) + " objects");
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
      const std::size_t floats = scene.frames[0].objects[o].size();
      if (frame.objects[o].size() != floats || floats % 3 != 0)
        throw UsageError(where + "frame " + std::to_string(frame.frame) + ": object " + object_name(r, o) +
                         " has " + std::to_string(frame.objects[o].size()) + " position values");
    }
  }
  if (scene.frames.empty()) return;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    const std::size_t vertices = scene.frames[0].objects[o].size() / 3;
    for (const auto& t : scene.objects[o].triangles)
      if (t[0] >= vertices || t[1] >= vertices || t[2] >= vertices)
        throw UsageError(where + "object " + object_name(r, o) + " has a triangle with a vertex id over " +
                         std::to_string(vertices));
  }
}

/// The 3D view's data: the chosen faces, the positions of the chosen frames,
/// and the regions of those frames with their faces as indices into the drawn faces.
json view_json(const ReportDigest& r, const HtmlScene& scene, std::size_t budget) {
  check_scene(r, scene);
  std::vector<ViewRegion> regions;
  std::vector<const report::RegionRecord*> region_records;
  for (const report::RegionRecord& region : r.regions) {
    for (std::size_t slot = 0; slot < scene.frames.size(); ++slot) {
      if (scene.frames[slot].frame != region.frame) continue;
      ViewRegion view{slot, region.bounds, std::vector<std::vector<std::size_t>>(scene.objects.size())};
      if (region.object_a < view.faces.size()) view.faces[region.object_a] = region.faces_a;
      if (region.object_b < view.faces.size() && region.object_b != region.object_a)
        view.faces[region.object_b] = region.faces_b;
      for (std::size_t o = 0; o < view.faces.size(); ++o)
        for (std::size_t f : view.faces[o])
          if (f >= scene.objects[o].triangles.size())
            throw UsageError("HTML page of " + r.path + ": region " + std::to_string(region.id) + " names face " +
                             std::to_string(f) + " of " + object_name(r, o) + ", which has " +
                             std::to_string(scene.objects[o].triangles.size()));
      regions.push_back(std::move(view));
      region_records.push_back(&region);
      break;
    }
  }
  const ViewSelection selection = select_view(scene, regions, budget);

  json objects = json::array();
  std::vector<std::vector<std::uint32_t>> vertex_ids(scene.objects.size());      // drawn vertex → local id
  std::vector<std::vector<std::int64_t>> face_slot(scene.objects.size());        // local face → drawn index
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    const auto& triangles = scene.objects[o].triangles;
    const std::size_t vertex_count = scene.frames.empty() ? 0 : scene.frames[0].objects[o].size() / 3;
    std::vector<std::int64_t> vertex_slot(vertex_count, -1);
    face_slot[o].assign(triangles.size(), -1);
    std::vector<std::uint32_t> index;
    for (std::uint32_t f : selection.faces[o]) {
      face_slot[o][f] = static_cast<std::int64_t>(index.size() / 3);
      for (std::uint32_t v : triangles[f]) {
        if (vertex_slot[v] < 0) {
          vertex_slot[v] = static_cast<std::int64_t>(vertex_ids[o].size());
          vertex_ids[o].push_back(v);
        }
        index.push_back(static_cast<std::uint32_t>(vertex_slot[v]));
      }
    }
    objects.push_back({{"name", object_name(r, o)},
                       {"faces_total", triangles.size()},
                       {"faces_drawn", selection.faces[o].size()},
                       {"vertices_drawn", vertex_ids[o].size()},
                       {"index", base64(index)}});
  }

  json frames = json::array();
  for (std::size_t slot = 0; slot < selection.frames; ++slot) {
    const HtmlFrame& frame = scene.frames[slot];
    json positions = json::array();
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
      std::vector<float> drawn;
      drawn.reserve(3 * vertex_ids[o].size());
      for (std::uint32_t v : vertex_ids[o])
        for (int k = 0; k < 3; ++k) drawn.push_back(frame.objects[o][3 * v + k]);
      positions.push_back(base64(drawn));
    }
    frames.push_back({{"frame", frame.frame}, {"positions", positions}});
  }

  json region_list = json::array();
  for (std::size_t i = 0; i < regions.size(); ++i) {
    if (regions[i].frame_slot >= selection.frames) continue;
    const report::RegionRecord& record = *region_records[i];
    json faces = json::array();
    for (std::size_t o = 0; o < regions[i].faces.size(); ++o) {
      if (regions[i].faces[o].empty()) continue;
      std::vector<std::uint32_t> drawn;
      for (std::size_t f : regions[i].faces[o]) drawn.push_back(static_cast<std::uint32_t>(face_slot[o][f]));
      faces.push_back({{"object", o}, {"faces", base64(drawn)}});
    }
    region_list.push_back({{"id", record.id},
                           {"kind", report::kind_name(record.kind)},
                           {"objects", pair_label(r, record.object_a, record.object_b)},
                           {"frame", record.frame},
                           {"track", record.track},
                           {"events", record.events},
                           {"face_count", record.face_count},
                           {"centroid", vec3(record.centroid)},
                           {"faces", faces}});
  }
  return {{"objects", objects},
          {"frames", frames},
          {"frames_given", scene.frames.size()},
          {"decimated", selection.decimated},
          {"regions", region_list}};
}

json report_json(const ReportDigest& r, const HtmlScene* scene, std::size_t budget) {
  const report::Header& h = r.header;
  const report::Trailer& t = r.trailer;
  json objects = json::array();
  for (const report::ObjectInfo& o : h.objects)
    objects.push_back({{"name", o.name}, {"vertices", o.vertices}, {"triangles", o.triangles}, {"weld", o.weld},
                       {"thickness", o.thickness}});
  json failed = json::array();
  for (const report::FailedRule& f : t.failed)
    failed.push_back({{"what", f.what}, {"count", f.count}, {"threshold", f.threshold}});
  json pairs = json::array();
  for (const report::PairSummary& p : t.pairs)
    pairs.push_back({{"kind", report::kind_name(p.kind)},
                     {"objects", pair_label(r, p.object_a, p.object_b)},
                     {"events", p.events},
                     {"allowed", p.allowed},
                     {"regions", p.regions},
                     {"tracks", p.tracks},
                     {"frames", p.frames},
                     {"worst_frame", p.worst_frame_events ? json(p.worst_frame) : json(nullptr)},
                     {"worst_frame_events", p.worst_frame_events}});

  // Per frame: events by kind (collisions of the step that starts there) and regions by kind.
  json index = json::array(), collisions = json::array(), intersections = json::array(), allowed = json::array();
  std::vector<std::size_t> frame_position_of;  // cache index → position in r.frames
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    const report::FrameRecord& f = r.frames[i];
    index.push_back(f.index);
    collisions.push_back(f.collisions);
    intersections.push_back(f.intersections);
    allowed.push_back(f.allowed);
    if (f.index >= frame_position_of.size()) frame_position_of.resize(f.index + 1, report::kNone);
    frame_position_of[f.index] = i;
  }
  std::vector<std::size_t> collision_regions(r.frames.size(), 0), intersection_regions(r.frames.size(), 0);
  for (const report::RegionRecord& region : r.regions) {
    if (region.frame >= frame_position_of.size() || frame_position_of[region.frame] == report::kNone) continue;
    auto& counts = region.kind == EventKind::kCollision ? collision_regions : intersection_regions;
    ++counts[frame_position_of[region.frame]];
  }
  json tracks = json::array();
  std::size_t merged = 0;
  for (const report::TrackRecord& track : r.tracks) {
    if (track.merged_into != report::kNone) {
      ++merged;
      continue;
    }
    tracks.push_back(track_json(r, track));
  }
  const auto& fail = h.rules.fail;
  return {{"path", r.path},
          {"source", h.source},
          {"snag_version", h.snag_version},
          {"certified", h.certified},
          {"objects", objects},
          {"settings",
           {{"mode", h.settings.mode},
            {"backend", h.settings.backend},
            {"precision", h.settings.precision},
            {"events", h.settings.events},
            {"frames", h.settings.frames},
            {"manifest", h.settings.manifest}}},
          {"thresholds",
           {{"events", fail.events},
            {"collisions", fail.collisions},
            {"intersections", fail.intersections},
            {"regions", fail.regions},
            {"tracks", fail.tracks}}},
          {"verdict", {{"pass", t.pass}, {"text", report::verdict_text(t)}, {"failed", failed}}},
          {"totals",
           {{"frames", t.frames},
            {"events", t.events},
            {"collisions", t.collisions},
            {"intersections", t.intersections},
            {"uncertain", t.uncertain},
            {"allowed", t.allowed},
            {"not_checked", t.not_checked},
            {"neighbourhood", t.neighbourhood},
            {"regions", t.regions},
            {"tracks", t.tracks}}},
          {"pairs", pairs},
          {"frames",
           {{"index", index},
            {"collisions", collisions},
            {"intersections", intersections},
            {"allowed", allowed},
            {"collision_regions", collision_regions},
            {"intersection_regions", intersection_regions}}},
          {"tracks", tracks},
          {"merged_tracks", merged},
          {"view", scene ? view_json(r, *scene, budget) : json(nullptr)}};
}

/// JSON inside <script>: "</" must not end the element, and U+2028/9 are fine in JSON.
std::string script_safe(std::string text) {
  for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3))
    text.replace(at, 2, "<\\/");
  return text;
}

/// "events 12361 reached the threshold 1, ..." or what passing means.
std::string failed_rules(const report::Trailer& t) {
  if (t.pass) return "no fail threshold reached";
  std::string text;
  for (const report::FailedRule& f : t.failed)
    text += (text.empty() ? "" : ", ") + f.what + " " + std::to_string(f.count) + " \u2265 " + std::to_string(f.threshold);
  return text;
}

void write_report_section(std::ostream& out, const ReportDigest& r, std::size_t i) {
  const bool pass = r.trailer.pass;
  out << "<section class=\"report\" id=\"report-" << i << "\" data-report=\"" << i << "\">\n"
      << "<h2>" << html_escape(r.path) << "</h2>\n"
      << "<p class=\"source\">" << html_escape(r.header.source) << "</p>\n"
      << "<div class=\"verdict " << (pass ? "pass" : "fail") << "\">" << (pass ? "PASS" : "FAIL") << "<span>"
      << html_escape(failed_rules(r.trailer)) << "</span></div>\n"
      << "<div class=\"report-body\"><p class=\"noscript-note\">The charts, the tracks table and the 3D view need "
         "JavaScript.</p></div>\n"
      << "</section>\n";
}

void write_batch_summary(std::ostream& out, const std::vector<ReportDigest>& reports) {
  out << "<section class=\"batch\"><h2>" << reports.size() << " reports</h2>\n<table class=\"summary\">"
      << "<thead><tr><th>report</th><th>verdict</th><th>frames</th><th>events</th><th>collisions</th>"
         "<th>intersections</th><th>allowed</th><th>regions</th><th>tracks</th></tr></thead><tbody>\n";
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const report::Trailer& t = reports[i].trailer;
    out << "<tr class=\"" << (t.pass ? "pass" : "fail") << "\"><td><a href=\"#report-" << i << "\">"
        << html_escape(reports[i].path) << "</a></td><td>" << html_escape(report::verdict_text(t)) << "</td><td>"
        << t.frames << "</td><td>" << t.events << "</td><td>" << t.collisions << "</td><td>" << t.intersections
        << "</td><td>" << t.allowed << "</td><td>" << t.regions << "</td><td>" << t.tracks << "</td></tr>\n";
  }
  out << "</tbody></table></section>\n";
}

}  // namespace

void write_html(std::ostream& out, const std::vector<ReportDigest>& reports, const HtmlInputs& inputs) {
  if (!html_assets::libraries)
    throw UsageError("this snag-report was built without the HTML page: configure with -DSNAG_WITH_HTML=ON "
                     "(needs Debian's libjs-chart.js and libjs-three)");
  std::size_t scenes = 0;
  for (std::size_t i = 0; i < reports.size() && i < inputs.scenes.size(); ++i) scenes += inputs.scenes[i].has_value();
  const std::size_t budget = scenes ? inputs.geometry_budget / scenes : 0;

  json data = json::array();
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const HtmlScene* scene = i < inputs.scenes.size() && inputs.scenes[i] ? &*inputs.scenes[i] : nullptr;
    data.push_back(report_json(reports[i], scene, budget));
  }
  std::string title = inputs.title;
  if (title.empty())
    title = reports.size() == 1 ? "snag report: " + reports[0].path : "snag reports: " + std::to_string(reports.size());

  out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
      << "<meta name=\"generator\" content=\"snag-report\">\n"
      << "<title>" << html_escape(title) << "</title>\n<style>\n"
      << html_assets::page_css << "</style>\n</head>\n<body data-ready=\"0\">\n"
      << "<header><h1>" << html_escape(title) << "</h1></header>\n<main>\n";
  if (reports.size() > 1) write_batch_summary(out, reports);
  for (std::size_t i = 0; i < reports.size(); ++i) write_report_section(out, reports[i], i);
  out << "</main>\n<script type=\"application/json\" id=\"snag-data\">"
      << script_safe(data.dump(-1, ' ', true, json::error_handler_t::replace)) << "</script>\n"
      << "<script>\n" << html_assets::chart_js << "\n</script>\n"
      << "<script>\n" << html_assets::three_js << "\n</script>\n"
      << "<script>\n" << html_assets::orbit_controls_js << "\n</script>\n"
      << "<script>\n" << html_assets::page_js << "\n</script>\n"
      << "</body>\n</html>\n";
}

}  // namespace snag::exporters
