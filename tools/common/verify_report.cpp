#include "tools/common/verify_report.hpp"
#include "tools/common/report.hpp"

#include <map>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "libcd/core/error.hpp"

namespace snag::tools {

namespace {

using nlohmann::json;

[[noreturn]] void bad_report(const std::string& path, const std::string& message) {
  throw InputError({path}, message);
}

const json& member(const std::string& path, const json& object, const char* key, const char* where) {
  if (!object.is_object() || !object.contains(key)) {
    bad_report(path, std::string(where) + ": no \"" + key + "\" key");
  }
  return object.at(key);
}

std::size_t unsigned_member(const std::string& path, const json& object, const char* key, const std::string& where) {
  const json& value = member(path, object, key, where.c_str());
  if (!value.is_number_unsigned() && !(value.is_number_integer() && value.get<long long>() >= 0)) {
    bad_report(path, where + ": \"" + key + "\" is not a non-negative integer");
  }
  return value.get<std::size_t>();
}

std::string string_member(const std::string& path, const json& object, const char* key, const std::string& where) {
  const json& value = member(path, object, key, where.c_str());
  if (!value.is_string()) bad_report(path, where + ": \"" + key + "\" is not a string");
  return value.get<std::string>();
}

double number_member(const std::string& path, const json& object, const char* key, const std::string& where) {
  const json& value = member(path, object, key, where.c_str());
  if (!value.is_number()) bad_report(path, where + ": \"" + key + "\" is not a number");
  return value.get<double>();
}

// The object of the scene named in a reference {"object": NAME, ...}.
std::size_t object_index(const ScanReport& report, const Scene& scene, const json& ref, const std::string& where) {
  const std::string name = string_member(report.path, ref, "object", where);
  const auto& objects = scene.objects();
  for (std::size_t o = 0; o < objects.size(); ++o)
    if (objects[o].name == name) return o;
  bad_report(report.path, where + ": object \"" + name + "\" is not in the cache");
}

Index local_id(const ScanReport& report, const json& ref, const char* key, std::size_t count,
               const std::string& where) {
  const std::size_t id = unsigned_member(report.path, ref, key, where);
  if (id >= count) {
    bad_report(report.path, where + ": " + key + " " + std::to_string(id) + " is out of range (the object has " +
                                std::to_string(count) + ")");
  }
  return static_cast<Index>(id);
}

// Reports name vertices by the file's ids; a welded vertex by any of those joined into it.
Index vertex_id(const ScanReport& report, const Scene& scene, const json& ref, const std::string& where) {
  const std::size_t o = object_index(report, scene, ref, where);
  const Object& object = scene.objects()[o];
  return scene.vertex_offset(o) +
         vertex_of_file_vertex(object, local_id(report, ref, "vertex", file_vertex_count(object), where));
}

Index face_id(const ScanReport& report, const Scene& scene, const json& ref, const std::string& where) {
  const std::size_t o = object_index(report, scene, ref, where);
  return scene.triangle_offset(o) + local_id(report, ref, "face", scene.objects()[o].triangles.size(), where);
}

Index edge_id(const ScanReport& report, const Scene& scene, const json& ref, const std::string& where) {
  const std::size_t o = object_index(report, scene, ref, where);
  const json& ends = member(report.path, ref, "edge", where.c_str());
  if (!ends.is_array() || ends.size() != 2 || !ends[0].is_number_integer() || !ends[1].is_number_integer()) {
    bad_report(report.path, where + ": \"edge\" is not a pair of vertex ids");
  }
  const long long u = ends[0].get<long long>(), v = ends[1].get<long long>();
  const Object& object = scene.objects()[o];
  const auto file_vertices = static_cast<long long>(file_vertex_count(object));
  if (u < 0 || v < 0 || u >= file_vertices || v >= file_vertices) {
    bad_report(report.path, where + ": edge vertex id out of range (the object has " +
                                std::to_string(file_vertices) + " vertices)");
  }
  const Index a = vertex_of_file_vertex(object, static_cast<Index>(u));
  const Index b = vertex_of_file_vertex(object, static_cast<Index>(v));
  const Edge edge{std::min(a, b), std::max(a, b)};
  const auto it = std::lower_bound(object.edges.begin(), object.edges.end(), edge);
  if (it == object.edges.end() || *it != edge) {
    bad_report(report.path, where + ": " + std::to_string(u) + "-" + std::to_string(v) + " is not an edge of \"" +
                                object.name + "\"");
  }
  return scene.edge_offset(o) + static_cast<Index>(it - object.edges.begin());
}


// An event as JSON: kind, type, frame, a, b, and for collisions the toi
// interval in frame units.
// Events hold frames as positions in the (selected) source; reports and
// output name them by the cache's own index, as snag-scan does.
double cache_frame(const FrameSource& source, std::size_t frame) {
  return static_cast<double>(source.frame_index(frame));
}

json event_json(const FrameSource& source, const Event& e) {
  const Scene& scene = source.scene();
  json out{{"kind", e.kind == EventKind::kCollision ? "collision" : "intersection"},
           {"frame", source.frame_index(e.frame)}};
  if (e.kind == EventKind::kCollision) {
    out["type"] = type_name(e.type);
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
    line << "collision " << type_name(e.type) << " step " << source.frame_index(e.frame) << "->"
         << source.frame_index(e.frame + 1);
  } else {
    line << "intersection frame " << source.frame_index(e.frame);
  }
  line << ": " << describe_pair(source.scene(), e);
  return line.str();
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

ScanReport read_scan_report(const std::string& path) {
  std::ifstream in(path);
  if (!in) bad_report(path, "cannot open the report");
  ScanReport report;
  report.path = path;
  try {
    report.json = json::parse(in);
  } catch (const json::parse_error& error) {
    bad_report(path, std::string("not a JSON report: ") + error.what());
  }
  const json& j = report.json;
  if (!j.is_object()) bad_report(path, "not a JSON report: the top level is not an object");
  if (!member(path, j, "version", "report").is_number_integer() || j.at("version").get<long long>() != 1) {
    bad_report(path, "unsupported report version (this snag-verify reads version 1)");
  }
  const json& settings = member(path, j, "settings", "report");
  report.mode = string_member(path, settings, "mode", "settings");
  if (report.mode != "ccd" && report.mode != "dcd" && report.mode != "all") {
    bad_report(path, "settings: unknown mode \"" + report.mode + "\"");
  }
  report.frames = string_member(path, settings, "frames", "settings");
  if (settings.contains("weld")) report.weld = string_member(path, settings, "weld", "settings");
  report.backend = string_member(path, settings, "backend", "settings");
  report.precision = string_member(path, settings, "precision", "settings");
  report.thickness = number_member(path, settings, "thickness", "settings");
  if (!(report.thickness >= 0) || !std::isfinite(report.thickness)) {
    bad_report(path, "settings: thickness must be a finite number >= 0");
  }
  if (!member(path, j, "objects", "report").is_array()) bad_report(path, "\"objects\" is not an array");
  if (!member(path, j, "frames", "report").is_array()) bad_report(path, "\"frames\" is not an array");
  if (!member(path, j, "events", "report").is_array()) bad_report(path, "\"events\" is not an array");
  return report;
}

std::vector<Event> report_events(const ScanReport& report, const FrameSource& source) {
  const Scene& scene = source.scene();
  const std::string& path = report.path;
  const json& objects = report.json.at("objects");
  if (objects.size() != scene.objects().size()) {
    bad_report(path, "the report has " + std::to_string(objects.size()) + " objects, the cache has " +
                         std::to_string(scene.objects().size()));
  }
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const Object& object = scene.objects()[o];
    const std::string where = "object " + std::to_string(o);
    const std::string name = string_member(path, objects[o], "name", where);
    if (name != object.name) {
      bad_report(path, where + " is \"" + name + "\" in the report, \"" + object.name + "\" in the cache");
    }
    if (objects[o].contains("weld")) {
      const std::string weld = string_member(path, objects[o], "weld", where);
      if (weld != object.weld.method) {
        bad_report(path, "object \"" + name + "\" was welded '" + weld + "' for the report but '" +
                             object.weld.method + "' here: give the same --weld as the scan");
      }
    }
    const std::size_t vertices = unsigned_member(path, objects[o], "vertices", where);
    const std::size_t triangles = unsigned_member(path, objects[o], "triangles", where);
    const std::size_t edges = unsigned_member(path, objects[o], "edges", where);
    if (vertices != object.vertex_count || triangles != object.triangles.size() || edges != object.edges.size()) {
      bad_report(path, "object \"" + name + "\": the report has " + std::to_string(vertices) + " vertices, " +
                           std::to_string(triangles) + " triangles, " + std::to_string(edges) +
                           " edges; the cache has " + std::to_string(object.vertex_count) + ", " +
                           std::to_string(object.triangles.size()) + ", " + std::to_string(object.edges.size()));
    }
  }
  const std::size_t frame_count = source.frame_count();
  if (report.json.at("frames").size() != frame_count) {
    bad_report(path, "the report covers " + std::to_string(report.json.at("frames").size()) +
                         " frames, the cache (after frame selection) has " + std::to_string(frame_count));
  }

  // The report names frames by the cache's own index; events hold positions
  // in the (selected) source.
  std::map<std::size_t, std::size_t> position_of_frame;
  for (std::size_t i = 0; i < frame_count; ++i) position_of_frame[source.frame_index(i)] = i;

  std::vector<Event> events;
  const json& list = report.json.at("events");
  events.reserve(list.size());
  for (std::size_t i = 0; i < list.size(); ++i) {
    const json& item = list[i];
    const std::string where = "event " + std::to_string(i);
    Event e;
    const std::string kind = string_member(path, item, "kind", where);
    const std::size_t reported_frame = unsigned_member(path, item, "frame", where);
    const auto position = position_of_frame.find(reported_frame);
    if (position == position_of_frame.end()) {
      bad_report(path, where + ": frame " + std::to_string(reported_frame) + " is not among the frames read");
    }
    e.frame = position->second;
    const json& a = member(path, item, "a", where.c_str());
    const json& b = member(path, item, "b", where.c_str());
    if (kind == "collision") {
      e.kind = EventKind::kCollision;
      if (e.frame + 1 >= frame_count) {
        bad_report(path, where + ": collision in step " + std::to_string(e.frame) + "->" +
                             std::to_string(e.frame + 1) + ", but the cache has " + std::to_string(frame_count) +
                             " frames");
      }
      const std::string type = string_member(path, item, "type", where);
      if (type == "vf") {
        e.type = ContactType::kVertexFace;
        e.a = vertex_id(report, scene, a, where);
        e.b = face_id(report, scene, b, where);
      } else if (type == "ee") {
        e.type = ContactType::kEdgeEdge;
        e.a = edge_id(report, scene, a, where);
        e.b = edge_id(report, scene, b, where);
      } else {
        bad_report(path, where + ": unknown collision type \"" + type + "\"");
      }
      const json& toi = member(path, item, "toi_interval", where.c_str());
      if (!toi.is_array() || toi.size() != 2 || !toi[0].is_number() || !toi[1].is_number()) {
        bad_report(path, where + ": \"toi_interval\" is not a pair of numbers");
      }
      e.toi_lo = toi[0].get<double>() - static_cast<double>(reported_frame);
      e.toi_hi = toi[1].get<double>() - static_cast<double>(reported_frame);
      if (!(e.toi_lo <= e.toi_hi)) bad_report(path, where + ": \"toi_interval\" is empty");
      if (item.contains("certainty") && item.at("certainty") == "uncertain") e.certainty = Certainty::kUncertain;
    } else if (kind == "intersection") {
      e.kind = EventKind::kIntersection;
      e.type = ContactType::kTriangleTriangle;
      if (e.frame >= frame_count) {
        bad_report(path, where + ": frame " + std::to_string(e.frame) + ", but the cache has " +
                             std::to_string(frame_count) + " frames");
      }
      e.a = face_id(report, scene, a, where);
      e.b = face_id(report, scene, b, where);
    } else {
      bad_report(path, where + ": unknown kind \"" + kind + "\"");
    }
    events.push_back(e);
  }
  return events;
}

std::string describe_pair(const Scene& scene, const Event& e) {
  auto object_name = [&](std::size_t o) { return scene.objects()[o].name; };
  auto vertex = [&](Index v) {
    const std::size_t o = scene.object_of_vertex(v);
    return object_name(o) + " vertex " + std::to_string(v - scene.vertex_offset(o));
  };
  auto face = [&](Index f) {
    const std::size_t o = scene.object_of_triangle(f);
    return object_name(o) + " face " + std::to_string(f - scene.triangle_offset(o));
  };
  auto edge = [&](Index id) {
    const std::size_t o = scene.object_of_edge(id);
    const Edge& ends = scene.edges()[id];
    const Index base = scene.vertex_offset(o);
    return object_name(o) + " edge " + std::to_string(ends[0] - base) + "-" + std::to_string(ends[1] - base);
  };
  switch (e.type) {
    case ContactType::kVertexFace: return vertex(e.a) + " / " + face(e.b);
    case ContactType::kEdgeEdge: return edge(e.a) + " / " + edge(e.b);
    case ContactType::kTriangleTriangle: return face(e.a) + " / " + face(e.b);
  }
  return "?";
}

bool all_confirmed(const validate::VerifyResult& result) {
  const Counts counts = count_verdicts(result);
  return counts.false_events == 0 && counts.toi_mismatches == 0 && result.missed.empty();
}

json verification_json(const FrameSource& source, const std::vector<Event>& reported,
                       const validate::VerifyResult& result, const validate::VerifySettings& settings) {
  const Scene& scene = source.scene();
  const Counts counts = count_verdicts(result);
  json false_events = json::array(), mismatches = json::array(), missed = json::array();
  for (std::size_t i = 0; i < reported.size(); ++i) {
    const validate::EventCheck& check = result.checks[i];
    if (check.verdict == validate::Verdict::kConfirmed) continue;
    json item = event_json(source, reported[i]);
    item["report_index"] = i;
    item["reason"] = check.reason;
    if (reported[i].kind == EventKind::kCollision) {
      item["toi_interval"] = interval(cache_frame(source, reported[i].frame), reported[i].toi_lo, reported[i].toi_hi);
    }
    if (check.verdict == validate::Verdict::kFalse) {
      false_events.push_back(std::move(item));
    } else {
      item["exact_toi_interval"] = interval(cache_frame(source, reported[i].frame), check.exact_toi_lo, check.exact_toi_hi);
      mismatches.push_back(std::move(item));
    }
  }
  for (const Event& e : result.missed) {
    json item = event_json(source, e);
    if (e.kind == EventKind::kCollision) item["exact_toi_interval"] = interval(cache_frame(source, e.frame), e.toi_lo, e.toi_hi);
    missed.push_back(std::move(item));
  }
  return {{"version", 1},
          {"tool", "snag-verify"},
          {"source", source.description()},
          {"thickness", settings.thickness},
          {"toi_tolerance", settings.toi_tolerance},
          {"exhaustive", settings.exhaustive},
          {"events", reported.size()},
          {"confirmed", counts.confirmed},
          {"false", counts.false_events},
          {"toi_mismatch", counts.toi_mismatches},
          {"missed", settings.exhaustive ? json(result.missed.size()) : json(nullptr)},
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
          {"missed_events", missed}};
}

void print_verification(std::FILE* out, const FrameSource& source, const std::vector<Event>& reported,
                        const validate::VerifyResult& result, const validate::VerifySettings& settings) {
  const Scene& scene = source.scene();
  const Counts counts = count_verdicts(result);
  std::fprintf(out, "events: %zu\nconfirmed: %zu\nfalse: %zu\ntoi mismatch: %zu\n", reported.size(),
               counts.confirmed, counts.false_events, counts.toi_mismatches);
  if (settings.exhaustive) {
    std::fprintf(out,
                 "missed: %zu (exhaustive: %zu VF, %zu EE, %zu triangle pairs decided; %zu VF and %zu EE of them "
                 "by the certified exclusion)\n",
                 result.missed.size(), result.vf_tested, result.ee_tested, result.triangle_pairs_tested,
                 result.vf_excluded, result.ee_excluded);
  } else {
    std::fprintf(out, "missed: not searched (use --exhaustive)\n");
  }
  for (std::size_t i = 0; i < reported.size(); ++i) {
    const validate::EventCheck& check = result.checks[i];
    if (check.verdict == validate::Verdict::kConfirmed) continue;
    const Event& e = reported[i];
    if (check.verdict == validate::Verdict::kFalse) {
      std::fprintf(out, "false: event %zu, %s (%s)\n", i, event_line(source, e).c_str(), check.reason.c_str());
    } else {
      std::fprintf(out, "toi mismatch: event %zu, %s: reported [%.17g, %.17g], exact [%.17g, %.17g]\n", i,
                   event_line(source, e).c_str(), cache_frame(source, e.frame) + e.toi_lo,
                   cache_frame(source, e.frame) + e.toi_hi, cache_frame(source, e.frame) + check.exact_toi_lo,
                   cache_frame(source, e.frame) + check.exact_toi_hi);
    }
  }
  for (const Event& e : result.missed) {
    if (e.kind == EventKind::kCollision) {
      std::fprintf(out, "missed: %s, toi in [%.17g, %.17g]\n", event_line(source, e).c_str(),
                   cache_frame(source, e.frame) + e.toi_lo, cache_frame(source, e.frame) + e.toi_hi);
    } else {
      std::fprintf(out, "missed: %s\n", event_line(source, e).c_str());
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
