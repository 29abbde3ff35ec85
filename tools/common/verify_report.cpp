#include "tools/common/verify_report.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "libcd/core/error.hpp"
#include "report/rules.hpp"

namespace snag::tools {

namespace {

using nlohmann::json;
using report::kNone;

// --- the report against the cache ------------------------------------------

// Checks that the report's objects are the scene's, in order, welded alike.
void check_objects(const report::ReportReader& reader, const Scene& scene) {
  const std::vector<report::ObjectInfo>& objects = reader.header().objects;
  const InputLocation where{reader.path(), 1};
  if (objects.size() != scene.objects().size()) {
    throw InputError(where, "the report has " + std::to_string(objects.size()) + " objects, the cache has " +
                                std::to_string(scene.objects().size()));
  }
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const report::ObjectInfo& info = objects[o];
    const Object& object = scene.objects()[o];
    if (info.name != object.name) {
      throw InputError(where, "object " + std::to_string(o) + " is \"" + info.name + "\" in the report, \"" +
                                  object.name + "\" in the cache");
    }
    if (info.weld != object.weld.method) {
      throw InputError(where, "object \"" + info.name + "\" was welded '" + info.weld + "' for the report but '" +
                                  object.weld.method + "' here: give the same --weld as the scan");
    }
    if (info.vertices != object.vertex_count || info.file_vertices != file_vertex_count(object) ||
        info.triangles != object.triangles.size() || info.edges != object.edges.size()) {
      throw InputError(where, "object \"" + info.name + "\": the report has " + std::to_string(info.vertices) +
                                  " vertices (" + std::to_string(info.file_vertices) + " in the file), " +
                                  std::to_string(info.triangles) + " triangles, " + std::to_string(info.edges) +
                                  " edges; the cache has " + std::to_string(object.vertex_count) + " (" +
                                  std::to_string(file_vertex_count(object)) + "), " +
                                  std::to_string(object.triangles.size()) + ", " +
                                  std::to_string(object.edges.size()));
    }
  }
}

// Global ids of a report's element references (the reader checked them
// against the header, check_objects the header against the scene).
Index vertex_id(const Scene& scene, const report::ElementRef& ref) {
  return scene.vertex_offset(ref.object) +
         vertex_of_file_vertex(scene.objects()[ref.object], static_cast<Index>(ref.id));
}

Index face_id(const Scene& scene, const report::ElementRef& ref) {
  return scene.triangle_offset(ref.object) + static_cast<Index>(ref.id);
}

Index edge_id(const report::ReportReader& reader, const Scene& scene, const report::ElementRef& ref) {
  const Object& object = scene.objects()[ref.object];
  const Index u = vertex_of_file_vertex(object, static_cast<Index>(ref.id));
  const Index v = vertex_of_file_vertex(object, static_cast<Index>(ref.id2));
  const Edge edge{std::min(u, v), std::max(u, v)};
  const auto it = std::lower_bound(object.edges.begin(), object.edges.end(), edge);
  if (it == object.edges.end() || *it != edge) {
    throw InputError({reader.path(), reader.line()}, std::to_string(ref.id) + "-" + std::to_string(ref.id2) +
                                                         " is not an edge of \"" + object.name + "\"");
  }
  return scene.edge_offset(ref.object) + static_cast<Index>(it - object.edges.begin());
}

// 0 intersections, 1 VF, 2 EE: the kinds frame records count.
int category(EventKind kind, ContactType type) {
  if (kind == EventKind::kIntersection) return 0;
  return type == ContactType::kVertexFace ? 1 : 2;
}

std::string object_name(const report::Header& header, std::size_t o) { return "\"" + header.objects[o].name + "\""; }

// The checks of one frame: its record, its listed events, its regions.
class FrameCheck {
 public:
  FrameCheck(const report::Header& header, ReportEvents& out) : header_(header), out_(out) {}

  void start(const report::FrameRecord& frame, std::size_t line) {
    frame_ = frame;
    frame_line_ = line;
    events_.clear();
    regions_.clear();
  }
  void add_event(const report::EventRecord& e, std::size_t line) { events_.push_back({e, line}); }
  void add_region(const report::RegionRecord& r, std::size_t line) { regions_.push_back({r, line}); }

  // Checks what the frame holds; mismatches that hold only for a complete
  // list go to `counted` (known complete only at the trailer).
  void finish(std::vector<RegionMismatch>& counted) {
    auto mismatch = [&](std::vector<RegionMismatch>& to, std::size_t region, std::size_t line, std::string reason) {
      to.push_back({frame_.index, region, line, std::move(reason)});
    };
    std::unordered_map<std::size_t, std::size_t> region_at;  // id -> index into regions_
    for (std::size_t k = 0; k < regions_.size(); ++k) region_at.emplace(regions_[k].record.id, k);
    std::vector<std::size_t> named(regions_.size(), 0);
    std::array<std::size_t, 3> listed{0, 0, 0};
    std::size_t uncertain = 0, allowed = 0;

    for (const auto& [e, line] : events_) {
      if (e.allowed != kNone) {
        ++allowed;
        if (e.region != kNone) {
          mismatch(out_.mismatches, e.region, line, "an allowed event names a region (allowed events have none)");
        }
        continue;
      }
      ++listed[category(e.kind, e.type)];
      uncertain += e.kind == EventKind::kCollision && e.certainty == Certainty::kUncertain;
      if (e.region == kNone) {
        mismatch(out_.mismatches, kNone, line, "a checked event names no region");
        continue;
      }
      const auto found = region_at.find(e.region);
      if (found == region_at.end()) continue;  // the reader refuses this
      const report::RegionRecord& r = regions_[found->second].record;
      ++named[found->second];
      const std::string event_name = "the event on line " + std::to_string(line);
      if (e.kind != r.kind) {
        mismatch(out_.mismatches, r.id, line, event_name + " is " + report::kind_name(e.kind) + ", its region " +
                                                  report::kind_name(r.kind));
        continue;
      }
      const std::size_t a = std::min(e.a.object, e.b.object), b = std::max(e.a.object, e.b.object);
      if (a != r.object_a || b != r.object_b) {
        mismatch(out_.mismatches, r.id, line,
                 event_name + " is between " + object_name(header_, a) + " and " + object_name(header_, b) +
                     ", its region between " + object_name(header_, r.object_a) + " and " +
                     object_name(header_, r.object_b));
        continue;
      }
      // The faces an event touches must be faces of its region; an EE
      // collision names edges, whose faces are around them: objects suffice.
      auto check_face = [&](const report::ElementRef& face) {
        const std::vector<std::size_t>& faces = face.object == r.object_a ? r.faces_a : r.faces_b;
        if (!std::binary_search(faces.begin(), faces.end(), face.id)) {
          mismatch(out_.mismatches, r.id, line,
                   event_name + " touches face " + std::to_string(face.id) + " of " +
                       object_name(header_, face.object) + ", which its region does not list");
        }
      };
      if (header_.settings.events == "none") {
        // regions without face lists (and events listed against the settings: check_totals says so)
      } else if (e.kind == EventKind::kIntersection) {
        check_face(e.a);
        check_face(e.b);
      } else if (e.type == ContactType::kVertexFace) {
        check_face(e.b);
      }
    }

    for (std::size_t k = 0; k < regions_.size(); ++k) {
      const auto& [r, line] = regions_[k];
      ++out_.regions_checked;
      if (named[k] != r.events) {
        mismatch(counted, r.id, line,
                 "the region counts " + std::to_string(r.events) + " events, " + std::to_string(named[k]) +
                     " listed events name it");
      }
    }
    if (regions_.size() != frame_.regions) {
      mismatch(out_.mismatches, kNone, frame_line_,
               "the frame record counts " + std::to_string(frame_.regions) + " regions, the frame has " +
                   std::to_string(regions_.size()));
    }
    if (frame_.collisions != frame_.vf + frame_.ee) {
      mismatch(out_.mismatches, kNone, frame_line_, "the frame record's collisions are not its vf + ee");
    }
    const std::array<std::size_t, 3> counts{frame_.intersections, frame_.vf, frame_.ee};
    const char* names[3] = {"intersections", "VF collisions", "EE collisions"};
    for (int c = 0; c < 3; ++c) {
      if (listed[c] != counts[c]) {
        mismatch(counted, kNone, frame_line_,
                 "the frame record counts " + std::to_string(counts[c]) + " " + names[c] + ", the report lists " +
                     std::to_string(listed[c]));
      }
    }
    if (uncertain != frame_.uncertain) {
      mismatch(counted, kNone, frame_line_,
               "the frame record counts " + std::to_string(frame_.uncertain) + " uncertain collisions, the report lists " +
                   std::to_string(uncertain));
    }
    if (allowed != frame_.allowed) {
      mismatch(counted, kNone, frame_line_,
               "the frame record counts " + std::to_string(frame_.allowed) + " allowed events, the report lists " +
                   std::to_string(allowed));
    }
    out_.frame_counts.push_back(counts);
  }

 private:
  template <typename Record>
  struct Lined {
    Record record;
    std::size_t line;
  };
  const report::Header& header_;
  ReportEvents& out_;
  report::FrameRecord frame_;
  std::size_t frame_line_ = 0;
  std::vector<std::pair<report::EventRecord, std::size_t>> events_;
  std::vector<Lined<report::RegionRecord>> regions_;
};

// The trailer's totals against the sums of the frame records and the records read.
struct Totals {
  std::size_t frames = 0, collisions = 0, vf = 0, ee = 0, intersections = 0, uncertain = 0, allowed = 0;
  std::size_t regions = 0, region_records = 0, tracks = 0, listed = 0;
};

void check_totals(const report::Header& header, const report::Trailer& t, const Totals& sum, std::size_t line,
                  std::vector<RegionMismatch>& out) {
  auto compare = [&](const char* what, std::size_t trailer, std::size_t records, const char* of) {
    if (trailer != records) {
      out.push_back({kNone, kNone, line,
                     std::string("the trailer counts ") + std::to_string(trailer) + " " + what + ", " + of + " " +
                         std::to_string(records)});
    }
  };
  compare("frames", t.frames, sum.frames, "the report has");
  compare("frames", header.frame_count, sum.frames, "the header announced them, the report has");
  compare("events", t.events, sum.collisions + sum.intersections, "the frame records");
  compare("collisions", t.collisions, sum.collisions, "the frame records");
  compare("VF collisions", t.vf, sum.vf, "the frame records");
  compare("EE collisions", t.ee, sum.ee, "the frame records");
  compare("intersections", t.intersections, sum.intersections, "the frame records");
  compare("uncertain collisions", t.uncertain, sum.uncertain, "the frame records");
  compare("allowed events", t.allowed, sum.allowed, "the frame records");
  compare("regions", t.regions, sum.regions, "the frame records");
  compare("regions", t.regions, sum.region_records, "the region records");
  compare("tracks", t.tracks, sum.tracks, "the track records");
  compare("listed events", t.listed, sum.listed, "the event records");
  if (header.settings.events == "none" && sum.listed > 0) {
    out.push_back({kNone, kNone, line, "the report lists events though its settings say events \"none\""});
  }
}

// --- output ----------------------------------------------------------------

double cache_frame(const FrameSource& source, std::size_t frame) {
  return static_cast<double>(source.frame_index(frame));
}

// Element references as reports write them: local ids, vertices by the file's ids.
json vertex_ref(const Scene& scene, Index v) {
  const std::size_t o = scene.object_of_vertex(v);
  const Object& object = scene.objects()[o];
  return {{"object", object.name}, {"vertex", file_vertex_id(object, v - scene.vertex_offset(o))}};
}
json face_ref(const Scene& scene, Index f) {
  const std::size_t o = scene.object_of_triangle(f);
  return {{"object", scene.objects()[o].name}, {"face", f - scene.triangle_offset(o)}};
}
json edge_ref(const Scene& scene, Index e) {
  const std::size_t o = scene.object_of_edge(e);
  const Object& object = scene.objects()[o];
  const Edge& ends = scene.edges()[e];
  const Index base = scene.vertex_offset(o);
  return {{"object", object.name},
          {"edge", {file_vertex_id(object, ends[0] - base), file_vertex_id(object, ends[1] - base)}}};
}

json event_json(const FrameSource& source, const Event& e) {
  const Scene& scene = source.scene();
  json out{{"kind", report::kind_name(e.kind)}, {"frame", source.frame_index(e.frame)}};
  if (e.kind == EventKind::kCollision) {
    out["type"] = report::type_name(e.type);
    if (e.type == ContactType::kVertexFace) {
      out["a"] = vertex_ref(scene, e.a);
      out["b"] = face_ref(scene, e.b);
    } else {
      out["a"] = edge_ref(scene, e.a);
      out["b"] = edge_ref(scene, e.b);
    }
  } else {
    out["a"] = face_ref(scene, e.a);
    out["b"] = face_ref(scene, e.b);
  }
  return out;
}

json interval(double frame, double lo, double hi) { return {frame + lo, frame + hi}; }

struct Counts {
  std::size_t confirmed = 0, false_events = 0, toi_mismatches = 0;
};

Counts count_verdicts(const validate::VerifyResult& result) {
  Counts counts;
  for (const validate::EventCheck& check : result.checks) {
    switch (check.verdict) {
      case validate::Verdict::kConfirmed: ++counts.confirmed; break;
      case validate::Verdict::kFalse: ++counts.false_events; break;
      case validate::Verdict::kToiMismatch: ++counts.toi_mismatches; break;
    }
  }
  return counts;
}

std::string event_line(const FrameSource& source, const Event& e) {
  std::ostringstream line;
  if (e.kind == EventKind::kCollision) {
    line << "collision " << report::type_name(e.type) << " step " << source.frame_index(e.frame) << "->"
         << source.frame_index(e.frame + 1);
  } else {
    line << "intersection frame " << source.frame_index(e.frame);
  }
  line << ": " << describe_pair(source.scene(), e);
  return line.str();
}

// "event 12" or "event 12 (line 40)" when the events came from a report.
std::string event_name(const Verification& v, std::size_t i) {
  std::string name = "event " + std::to_string(i);
  if (v.report != nullptr) name += " (line " + std::to_string(v.report->lines[i]) + ")";
  return name;
}

std::size_t missed_count(const Verification& v) {
  if (v.unlisted != nullptr) return v.unlisted->missed.size() + v.unlisted->missed_beyond_counts;
  return v.result->missed.size();
}

const std::vector<Event>& missed_events(const Verification& v) {
  return v.unlisted != nullptr ? v.unlisted->missed : v.result->missed;
}

json counts_json(const validate::QueryCounts& c) {
  return {{"queries", c.queries},
          {"positives", c.positives},
          {"true_positives", c.true_positives},
          {"false_positives", c.false_positives},
          {"false_negatives", c.false_negatives},
          {"uncertain", c.uncertain},
          {"uncertain_positives", c.uncertain_positives},
          {"seconds", c.seconds},
          {"microseconds_per_query", c.queries == 0 ? 0.0 : 1e6 * c.seconds / static_cast<double>(c.queries)}};
}

}  // namespace

ReportEvents read_report_events(report::ReportReader& reader, const FrameSource& source) {
  const Scene& scene = source.scene();
  const report::Header& header = reader.header();
  check_objects(reader, scene);
  const std::size_t frame_count = source.frame_count();
  if (header.frame_count != frame_count) {
    throw InputError({reader.path(), 1}, "the report covers " + std::to_string(header.frame_count) +
                                             " frames, the cache (after frame selection) has " +
                                             std::to_string(frame_count));
  }

  ReportEvents out;
  out.complete = header.settings.events == "all";
  FrameCheck frame_check(header, out);
  std::vector<RegionMismatch> counted;  // hold only when the list is complete
  Totals sum;
  bool in_frame = false;
  std::size_t position = 0;  // of the current frame in the source
  for (report::ReportReader::Record record; (record = reader.next()) != report::ReportReader::Record::kEnd;) {
    switch (record) {
      case report::ReportReader::Record::kFrame: {
        const report::FrameRecord& f = reader.frame();
        if (in_frame) frame_check.finish(counted);
        position = f.position;  // the reader checked: 0, 1, ... below the header's frame count
        if (source.frame_index(position) != f.index) {
          throw InputError({reader.path(), reader.line()},
                           "frame " + std::to_string(position) + " of the report is cache frame " +
                               std::to_string(f.index) + ", of this selection " +
                               std::to_string(source.frame_index(position)) + ": give the scan's --frames");
        }
        frame_check.start(f, reader.line());
        in_frame = true;
        ++sum.frames;
        sum.collisions += f.collisions;
        sum.vf += f.vf;
        sum.ee += f.ee;
        sum.intersections += f.intersections;
        sum.uncertain += f.uncertain;
        sum.allowed += f.allowed;
        sum.regions += f.regions;
        break;
      }
      case report::ReportReader::Record::kEvent: {
        const report::EventRecord& r = reader.event();
        Event e;
        e.kind = r.kind;
        e.type = r.type;
        e.frame = position;
        e.position = r.position;
        e.certainty = r.certainty;
        if (r.kind == EventKind::kCollision) {
          if (position + 1 >= frame_count) {
            throw InputError({reader.path(), reader.line()},
                             "a collision in the step from frame " + std::to_string(r.frame) +
                                 ", the last frame of the report");
          }
          if (r.type == ContactType::kVertexFace) {
            e.a = vertex_id(scene, r.a);
            e.b = face_id(scene, r.b);
          } else {
            e.a = edge_id(reader, scene, r.a);
            e.b = edge_id(reader, scene, r.b);
          }
          e.toi_lo = r.toi_lo - static_cast<double>(r.frame);
          e.toi_hi = r.toi_hi - static_cast<double>(r.frame);
        } else {
          e.a = face_id(scene, r.a);
          e.b = face_id(scene, r.b);
        }
        out.events.push_back(e);
        out.lines.push_back(reader.line());
        out.allowed.push_back(r.allowed != kNone);
        frame_check.add_event(r, reader.line());
        ++sum.listed;
        break;
      }
      case report::ReportReader::Record::kRegion:
        frame_check.add_region(reader.region(), reader.line());
        ++sum.region_records;
        break;
      case report::ReportReader::Record::kTrack: ++sum.tracks; break;
      case report::ReportReader::Record::kTrailer: {
        if (in_frame) frame_check.finish(counted);
        in_frame = false;
        const report::Trailer& t = reader.trailer();
        out.left_out = t.left_out;
        out.complete = out.complete && t.left_out == 0;
        check_totals(header, t, sum, reader.line(), out.mismatches);
        break;
      }
      case report::ReportReader::Record::kEnd: break;
    }
  }
  if (out.complete) out.mismatches.insert(out.mismatches.end(), counted.begin(), counted.end());
  std::stable_sort(out.mismatches.begin(), out.mismatches.end(),
                   [](const RegionMismatch& x, const RegionMismatch& y) { return x.line < y.line; });
  return out;
}

UnlistedEvents split_unlisted(const report::Header& header, const FrameSource& source, const ReportEvents& listed,
                              const validate::VerifyResult& result) {
  UnlistedEvents out;
  const report::RuleSet rules(source.scene(), header.rules, header.settings.thickness);
  // Per frame and kind: checked events found exactly (listed and confirmed, or not listed).
  std::vector<std::array<std::size_t, 3>> found(listed.frame_counts.size(), {0, 0, 0});
  auto count_found = [&](const Event& e) {
    if (e.frame < found.size()) ++found[e.frame][category(e.kind, e.type)];
  };
  for (std::size_t i = 0; i < listed.events.size(); ++i) {
    if (!listed.allowed[i] && result.checks[i].verdict != validate::Verdict::kFalse) count_found(listed.events[i]);
  }
  for (const Event& e : result.missed) {
    Event at_cache_frame = e;
    at_cache_frame.frame = source.frame_index(e.frame);
    const report::Disposition disposition = rules.classify(at_cache_frame);
    if (disposition.kind == report::Disposition::kNotChecked ||
        disposition.kind == report::Disposition::kNeighbourhood) {
      ++out.not_checked;
      continue;
    }
    if (listed.complete) {
      out.missed.push_back(e);
    } else {
      out.unlisted.push_back(e);
      if (disposition.kind == report::Disposition::kChecked) count_found(e);
    }
  }
  if (!listed.complete) {
    for (std::size_t f = 0; f < found.size(); ++f) {
      for (int c = 0; c < 3; ++c) {
        if (found[f][c] > listed.frame_counts[f][c]) out.missed_beyond_counts += found[f][c] - listed.frame_counts[f][c];
      }
    }
  }
  return out;
}

std::string describe_pair(const Scene& scene, const Event& e) {
  auto object_name = [&](std::size_t o) { return scene.objects()[o].name; };
  auto vertex = [&](Index v) {
    const std::size_t o = scene.object_of_vertex(v);
    return object_name(o) + " vertex " + std::to_string(file_vertex_id(scene.objects()[o], v - scene.vertex_offset(o)));
  };
  auto face = [&](Index f) {
    const std::size_t o = scene.object_of_triangle(f);
    return object_name(o) + " face " + std::to_string(f - scene.triangle_offset(o));
  };
  auto edge = [&](Index id) {
    const std::size_t o = scene.object_of_edge(id);
    const Object& object = scene.objects()[o];
    const Edge& ends = scene.edges()[id];
    const Index base = scene.vertex_offset(o);
    return object_name(o) + " edge " + std::to_string(file_vertex_id(object, ends[0] - base)) + "-" +
           std::to_string(file_vertex_id(object, ends[1] - base));
  };
  switch (e.type) {
    case ContactType::kVertexFace: return vertex(e.a) + " / " + face(e.b);
    case ContactType::kEdgeEdge: return edge(e.a) + " / " + edge(e.b);
    case ContactType::kTriangleTriangle: return face(e.a) + " / " + face(e.b);
  }
  return "?";
}

bool all_confirmed(const Verification& v) {
  const Counts counts = count_verdicts(*v.result);
  const bool regions_agree = v.report == nullptr || v.report->mismatches.empty();
  return counts.false_events == 0 && counts.toi_mismatches == 0 && missed_count(v) == 0 && regions_agree;
}

json verification_json(const FrameSource& source, const Verification& v) {
  const std::vector<Event>& reported = *v.events;
  const validate::VerifyResult& result = *v.result;
  const validate::VerifySettings& settings = *v.settings;
  const Counts counts = count_verdicts(result);
  json false_events = json::array(), mismatches = json::array(), missed = json::array(), unlisted = json::array();
  for (std::size_t i = 0; i < reported.size(); ++i) {
    const validate::EventCheck& check = result.checks[i];
    if (check.verdict == validate::Verdict::kConfirmed) continue;
    json item = event_json(source, reported[i]);
    item["report_index"] = i;
    if (v.report != nullptr) item["line"] = v.report->lines[i];
    item["reason"] = check.reason;
    if (reported[i].kind == EventKind::kCollision) {
      item["toi_interval"] = interval(cache_frame(source, reported[i].frame), reported[i].toi_lo, reported[i].toi_hi);
    }
    if (check.verdict == validate::Verdict::kFalse) {
      false_events.push_back(std::move(item));
    } else {
      item["exact_toi_interval"] =
          interval(cache_frame(source, reported[i].frame), check.exact_toi_lo, check.exact_toi_hi);
      mismatches.push_back(std::move(item));
    }
  }
  auto found_json = [&](const Event& e) {
    json item = event_json(source, e);
    if (e.kind == EventKind::kCollision) item["exact_toi_interval"] = interval(cache_frame(source, e.frame), e.toi_lo, e.toi_hi);
    return item;
  };
  for (const Event& e : missed_events(v)) missed.push_back(found_json(e));
  if (v.unlisted != nullptr) {
    for (const Event& e : v.unlisted->unlisted) unlisted.push_back(found_json(e));
  }
  json out{{"version", 2},
           {"tool", "snag-verify"},
           {"source", source.description()},
           {"thickness", settings.thickness},
           {"object_thickness", settings.object_thickness},
           {"toi_tolerance", settings.toi_tolerance},
           {"exhaustive", settings.exhaustive},
           {"events", reported.size()},
           {"complete", v.report == nullptr || v.report->complete},
           {"confirmed", counts.confirmed},
           {"false", counts.false_events},
           {"toi_mismatch", counts.toi_mismatches},
           {"missed", settings.exhaustive ? json(missed_count(v)) : json(nullptr)},
           {"unlisted", v.unlisted != nullptr && !v.report->complete ? json(v.unlisted->unlisted.size()) : json(nullptr)},
           {"not_checked", v.unlisted != nullptr ? json(v.unlisted->not_checked) : json(nullptr)},
           {"exhaustive_tests",
            {{"vf", result.vf_tested},
             {"ee", result.ee_tested},
             {"triangle_pairs", result.triangle_pairs_tested},
             {"vf_excluded", result.vf_excluded},
             {"ee_excluded", result.ee_excluded}}},
           {"frames_read", result.frames_read},
           {"timing", {{"reported", result.seconds_reported}, {"exhaustive", result.seconds_exhaustive}}},
           {"false_events", false_events},
           {"toi_mismatches", mismatches},
           {"missed_events", missed},
           {"unlisted_events", unlisted}};
  if (v.report != nullptr) {
    json mismatched = json::array();
    for (const RegionMismatch& m : v.report->mismatches) {
      mismatched.push_back({{"frame", m.frame == kNone ? json(nullptr) : json(m.frame)},
                            {"region", m.region == kNone ? json(nullptr) : json(m.region)},
                            {"line", m.line},
                            {"reason", m.reason}});
    }
    out["regions"] = {{"checked", v.report->regions_checked},
                      {"counts_checked", v.report->complete},
                      {"mismatched", mismatched}};
  } else {
    out["regions"] = nullptr;
  }
  return out;
}

void print_verification(std::FILE* out, const FrameSource& source, const Verification& v) {
  const std::vector<Event>& reported = *v.events;
  const validate::VerifyResult& result = *v.result;
  const validate::VerifySettings& settings = *v.settings;
  const Counts counts = count_verdicts(result);
  std::fprintf(out, "events: %zu\n", reported.size());
  if (v.report != nullptr && !v.report->complete) {
    std::fprintf(out,
                 "listed: not every event (%zu left out): the unlisted ones cannot be confirmed; the listed ones "
                 "are verified\n",
                 v.report->left_out);
  }
  std::fprintf(out, "confirmed: %zu\nfalse: %zu\ntoi mismatch: %zu\n", counts.confirmed, counts.false_events,
               counts.toi_mismatches);
  if (settings.exhaustive) {
    std::fprintf(out,
                 "missed: %zu (exhaustive: %zu VF, %zu EE, %zu triangle pairs decided; %zu VF and %zu EE of them "
                 "by the certified exclusion)\n",
                 missed_count(v), result.vf_tested, result.ee_tested, result.triangle_pairs_tested,
                 result.vf_excluded, result.ee_excluded);
    if (v.unlisted != nullptr && !v.report->complete) {
      std::fprintf(out,
                   "unlisted: %zu (found exactly, not listed: the report left events out, so these cannot be told "
                   "from misses; %zu are beyond what the frame records count and are counted as missed)\n",
                   v.unlisted->unlisted.size(), v.unlisted->missed_beyond_counts);
    }
    if (v.unlisted != nullptr && v.unlisted->not_checked > 0) {
      std::fprintf(out, "not checked: %zu (found exactly in pairs the scan's rules do not check)\n",
                   v.unlisted->not_checked);
    }
  } else {
    std::fprintf(out, "missed: not searched (use --exhaustive)\n");
  }
  if (v.report != nullptr) {
    std::fprintf(out, "regions: %zu checked, %zu mismatched%s\n", v.report->regions_checked,
                 v.report->mismatches.size(),
                 v.report->complete ? "" : " (event counts not checked: the list is not complete)");
  }
  for (std::size_t i = 0; i < reported.size(); ++i) {
    const validate::EventCheck& check = result.checks[i];
    if (check.verdict == validate::Verdict::kConfirmed) continue;
    const Event& e = reported[i];
    if (check.verdict == validate::Verdict::kFalse) {
      std::fprintf(out, "false: %s, %s (%s)\n", event_name(v, i).c_str(), event_line(source, e).c_str(),
                   check.reason.c_str());
    } else {
      std::fprintf(out, "toi mismatch: %s, %s: reported [%.17g, %.17g], exact [%.17g, %.17g]\n",
                   event_name(v, i).c_str(), event_line(source, e).c_str(), cache_frame(source, e.frame) + e.toi_lo,
                   cache_frame(source, e.frame) + e.toi_hi, cache_frame(source, e.frame) + check.exact_toi_lo,
                   cache_frame(source, e.frame) + check.exact_toi_hi);
    }
  }
  auto print_found = [&](const char* what, const Event& e) {
    if (e.kind == EventKind::kCollision) {
      std::fprintf(out, "%s: %s, toi in [%.17g, %.17g]\n", what, event_line(source, e).c_str(),
                   cache_frame(source, e.frame) + e.toi_lo, cache_frame(source, e.frame) + e.toi_hi);
    } else {
      std::fprintf(out, "%s: %s\n", what, event_line(source, e).c_str());
    }
  };
  for (const Event& e : missed_events(v)) print_found("missed", e);
  if (v.unlisted != nullptr) {
    // A report that lists no events leaves them all unlisted: the first few say what they are.
    constexpr std::size_t kShown = 20;
    const std::vector<Event>& unlisted = v.unlisted->unlisted;
    for (std::size_t i = 0; i < std::min(unlisted.size(), kShown); ++i) print_found("unlisted", unlisted[i]);
    if (unlisted.size() > kShown) {
      std::fprintf(out, "unlisted: ... and %zu more (--json lists them all)\n", unlisted.size() - kShown);
    }
  }
  if (v.report != nullptr) {
    for (const RegionMismatch& m : v.report->mismatches) {
      std::string where = "line " + std::to_string(m.line);
      if (m.frame != kNone) where += ", frame " + std::to_string(m.frame);
      if (m.region != kNone) where += ", region " + std::to_string(m.region);
      std::fprintf(out, "region mismatch: %s: %s\n", where.c_str(), m.reason.c_str());
    }
  }
}

json query_evaluation_json(const validate::QueryEvaluation& evaluation) {
  json disagreements = json::array();
  for (const validate::QueryDisagreement& d : evaluation.disagreements) {
    disagreements.push_back({{"method", d.method},
                             {"file", d.file},
                             {"line", d.line},
                             {"type", d.edge_edge ? "ee" : "vf"},
                             {"truth", d.truth},
                             {"answer", d.answer}});
  }
  const std::size_t queries = evaluation.exact_vf.queries + evaluation.exact_ee.queries;
  return {{"version", 1},
          {"tool", "snag-verify"},
          {"queries", queries},
          {"methods",
           {{"exact", {{"vf", counts_json(evaluation.exact_vf)}, {"ee", counts_json(evaluation.exact_ee)}}},
            {"filter", {{"vf", counts_json(evaluation.filter_vf)}, {"ee", counts_json(evaluation.filter_ee)}}}}},
          {"disagreements", disagreements}};
}

void print_query_evaluation(std::FILE* out, const validate::QueryEvaluation& evaluation) {
  std::fprintf(out, "%-7s %-4s %8s %9s %6s %6s %9s %12s\n", "method", "kind", "queries", "positives", "FP", "FN",
               "uncertain", "us/query");
  auto row = [&](const char* method, const char* kind, const validate::QueryCounts& c) {
    std::fprintf(out, "%-7s %-4s %8zu %9zu %6zu %6zu %9zu %12.2f\n", method, kind, c.queries, c.positives,
                 c.false_positives, c.false_negatives, c.uncertain,
                 c.queries == 0 ? 0.0 : 1e6 * c.seconds / static_cast<double>(c.queries));
  };
  row("exact", "VF", evaluation.exact_vf);
  row("exact", "EE", evaluation.exact_ee);
  row("filter", "VF", evaluation.filter_vf);
  row("filter", "EE", evaluation.filter_ee);
  for (const validate::QueryDisagreement& d : evaluation.disagreements) {
    std::fprintf(out, "wrong: %s %s %s:%zu: truth %s, answered %s\n", d.method.c_str(), d.edge_edge ? "EE" : "VF",
                 d.file.c_str(), d.line, d.truth ? "yes" : "no", d.answer.c_str());
  }
}

}  // namespace snag::tools
