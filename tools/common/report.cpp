#include "tools/common/report.hpp"

namespace snag::tools {

using nlohmann::json;

const char* type_name(ContactType type) {
  switch (type) {
    case ContactType::kVertexFace: return "vf";
    case ContactType::kEdgeEdge: return "ee";
    case ContactType::kTriangleTriangle: return "tt";
  }
  return "?";
}

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
  const Edge& edge = scene.edges()[e];
  const Index base = scene.vertex_offset(o);
  const Object& object = scene.objects()[o];
  return {{"object", object.name},
          {"edge", {file_vertex_id(object, edge[0] - base), file_vertex_id(object, edge[1] - base)}}};
}

namespace {

json broad_json(const BroadPhaseStats& s) {
  return {{"cell_size", s.cell_size},
          {"grid", {s.grid_dims[0], s.grid_dims[1], s.grid_dims[2]}},
          {"cells_used", s.cells_used},
          {"root_triangles", s.root_triangles},
          {"triangles_subdivided", s.triangles_subdivided},
          {"subdivision_levels", s.triangles_per_level.empty() ? 0 : s.triangles_per_level.size() - 1},
          {"subdivided_per_level", s.subdivided_per_level},
          {"time_halvings", s.time_halvings},
          {"oversized_leaves", s.oversized_leaves},
          {"leaf_triangles", s.leaf_triangles},
          {"registrations", s.registrations},
          {"home_registrations", s.home_registrations},
          {"phantom_registrations", s.phantom_registrations},
          {"duplicate_registrations_removed", s.duplicate_registrations_removed},
          {"tests", s.tests},
          {"removed_by_control_bits", s.removed_by_control_bits},
          {"removed_by_extended_control_bits", s.removed_by_extended_control_bits},
          {"tests_after_control_bits", s.tests_after_control_bits},
          {"duplicate_root_pair_tests", s.duplicate_root_pair_tests},
          {"duplicate_culled_tests", s.duplicate_culled_tests},
          {"culled_by_dop", s.culled_by_dop},
          {"triangle_pairs", s.triangle_pairs},
          {"vf_before_culling", s.vf_before_culling},
          {"vf_after_culling", s.vf_after_culling},
          {"ee_before_culling", s.ee_before_culling},
          {"ee_after_culling", s.ee_after_culling},
          {"candidates", s.candidates},
          {"peak_memory_bytes", s.memory_bytes}};
}

json broad_timing(const BroadPhaseStats& s) {
  return {{"bounds", s.seconds_bounds},         {"subdivision", s.seconds_subdivision},
          {"registration", s.seconds_registration}, {"pairs", s.seconds_pairs},
          {"features", s.seconds_features},     {"total", s.seconds_total}};
}

}  // namespace

json make_report(const FrameSource& source, const ScanResult& result, const ReportSettings& settings) {
  const Scene& scene = source.scene();
  json objects = json::array();
  for (const Object& object : scene.objects()) {
    objects.push_back({{"name", object.name},
                       {"vertices", object.vertex_count},
                       {"file_vertices", file_vertex_count(object)},
                       {"weld", object.weld.method},
                       {"triangles", object.triangles.size()},
                       {"edges", object.edges.size()}});
  }
  json frames = json::array();
  std::size_t collisions = 0, vf = 0, ee = 0, intersections = 0, uncertain = 0;
  json per_frame = json::array();
  for (std::size_t i = 0; i < result.frames.size(); ++i) {
    const FrameSummary& f = result.frames[i];
    frames.push_back({{"index", f.frame}, {"time", source.frame_time(i)}});
    per_frame.push_back({{"frame", f.frame},
                         {"collisions", f.collisions},
                         {"vf", f.vertex_face},
                         {"ee", f.edge_edge},
                         {"intersections", f.intersections},
                         {"uncertain", f.uncertain}});
    collisions += f.collisions;
    vf += f.vertex_face;
    ee += f.edge_edge;
    intersections += f.intersections;
    uncertain += f.uncertain;
  }
  json events = json::array();
  for (const Event& e : result.events) {
    json event{{"kind", e.kind == EventKind::kCollision ? "collision" : "intersection"}, {"frame", e.frame}};
    if (e.kind == EventKind::kCollision) {
      event["type"] = type_name(e.type);
      event["toi"] = static_cast<double>(e.frame) + e.toi_lo;
      event["toi_interval"] = {static_cast<double>(e.frame) + e.toi_lo, static_cast<double>(e.frame) + e.toi_hi};
      if (e.type == ContactType::kVertexFace) {
        event["a"] = vertex_ref(scene, e.a);
        event["b"] = face_ref(scene, e.b);
      } else {
        event["a"] = edge_ref(scene, e.a);
        event["b"] = edge_ref(scene, e.b);
      }
      event["certainty"] = e.certainty == Certainty::kProven ? "proven" : "uncertain";
    } else {
      event["a"] = face_ref(scene, e.a);
      event["b"] = face_ref(scene, e.b);
    }
    event["position"] = {e.position.x, e.position.y, e.position.z};
    events.push_back(std::move(event));
  }
  const NarrowPhaseStats& n = result.stats.narrow;
  const std::size_t ccd_tests = n.vf_tests + n.ee_tests;
  const bool certified = settings.precision == "certified";
  return {
      {"version", kReportVersion},
      {"tool", "snag-scan"},
      {"source", settings.source},
      {"objects", objects},
      {"frames", frames},
      {"settings",
       {{"mode", settings.mode},
        {"backend", settings.backend},
        {"precision", settings.precision},
        {"thickness", settings.thickness},
        {"lambda", settings.lambda},
        {"threads", settings.threads},
        {"frames", settings.frames},
        {"weld", settings.weld}}},
      {"certified", certified},
      {"summary",
       {{"events", result.events.size()},
        {"collisions", collisions},
        {"vf", vf},
        {"ee", ee},
        {"intersections", intersections},
        {"uncertain", uncertain},
        {"per_frame", per_frame}}},
      {"stages",
       {{"ccd_broad_phase", broad_json(result.stats.ccd_broad)},
        {"static_broad_phase", broad_json(result.stats.static_broad)},
        {"narrow_phase",
         {{"vf_tests", n.vf_tests},
          {"vf_yes", n.vf_yes},
          {"vf_no", n.vf_no},
          {"vf_uncertain", n.vf_uncertain},
          {"ee_tests", n.ee_tests},
          {"ee_yes", n.ee_yes},
          {"ee_no", n.ee_no},
          {"ee_uncertain", n.ee_uncertain},
          {"exact_queries", n.certified},
          {"exact_confirmed", n.certified_true},
          {"exact_fraction", ccd_tests == 0 ? 0.0 : static_cast<double>(n.certified) / ccd_tests},
          {"triangle_tests", n.triangle_tests},
          {"triangles_intersecting", n.triangles_intersecting},
          {"predicate_calls", n.predicate_calls},
          {"predicate_exact", n.predicate_exact}}}}},
      {"timing",
       {{"total", result.total_seconds},
        {"read", result.read_seconds},
        {"ccd_broad_phase", broad_timing(result.stats.ccd_broad)},
        {"static_broad_phase", broad_timing(result.stats.static_broad)},
        {"ccd_narrow_phase", n.seconds_ccd},
        {"certification", n.seconds_certify},
        {"static_narrow_phase", n.seconds_static}}},
      {"events", events}};
}

}  // namespace snag::tools
