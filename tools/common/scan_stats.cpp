#include "tools/common/scan_stats.hpp"

#include <nlohmann/json.hpp>

namespace snag::tools {

using nlohmann::json;

namespace {

json broad_json(const BroadPhaseStats& s) {
  return {{"cell_size", s.cell_size},
          {"grid", {s.grid_dims[0], s.grid_dims[1], s.grid_dims[2]}},
          {"cells_used", s.cells_used},
          {"cells_subdivided", s.cells_subdivided},
          {"deepest_level", s.deepest_level},
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
          {"culled_by_boxes", s.culled_by_boxes},
          {"removed_by_control_bits", s.removed_by_control_bits},
          {"removed_by_extended_control_bits", s.removed_by_extended_control_bits},
          {"tests_after_control_bits", s.tests_after_control_bits},
          {"duplicate_root_pair_tests", s.duplicate_root_pair_tests},
          {"duplicate_culled_tests", s.duplicate_culled_tests},
          {"culled_by_dop", s.culled_by_dop},
          {"triangle_pairs", s.triangle_pairs},
          {"separated_triangle_pairs", s.separated_triangle_pairs},
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

std::string stages_json(const ScanTotals& totals) {
  const NarrowPhaseStats& n = totals.stats.narrow;
  const std::size_t ccd_tests = n.vf_tests + n.ee_tests;
  const json stages = {
      {"ccd_broad_phase", broad_json(totals.stats.ccd_broad)},
      {"static_broad_phase", broad_json(totals.stats.static_broad)},
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
        {"predicate_exact", n.predicate_exact}}}};
  return stages.dump();
}

std::string timing_json(const ScanTotals& totals) {
  const NarrowPhaseStats& n = totals.stats.narrow;
  const json timing = {{"total", totals.total_seconds},
                       {"read", totals.read_seconds},
                       {"report", totals.sink_seconds},
                       {"report_wait", totals.sink_wait_seconds},
                       {"ccd_broad_phase", broad_timing(totals.stats.ccd_broad)},
                       {"static_broad_phase", broad_timing(totals.stats.static_broad)},
                       {"ccd_narrow_phase", n.seconds_ccd},
                       {"certification", n.seconds_certify},
                       {"static_narrow_phase", n.seconds_static}};
  return timing.dump();
}

std::string with_start_seconds(const std::string& timing, double start_seconds) {
  json object = json::parse(timing);
  object["start"] = start_seconds;
  return object.dump();
}

}  // namespace snag::tools
