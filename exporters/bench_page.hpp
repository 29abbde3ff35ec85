// snag-bench's page: one self-contained HTML file (no network, no server)
// with the speed-accuracy charts (time per query against false negatives and
// against false positives, per method and data set, log scales), a chart per
// stability family (each method's error rate along the knob), and per scene
// the share of candidates decided at each tier, the adaptive run against the
// heavy one and the broad phases' tests, time and memory; tables give the
// numbers. Chart.js is the one snag-report's page inlines (Debian's
// libjs-chart.js, embedded at build time by EmbedJs.cmake).
//
// Self-check on <body> (for tests): data-ready="1" when drawn, data-charts,
// data-families, data-scenes, and data-error when something failed. The
// address suffix #only=ID shows only the chart of that id (880 by 490
// pixels and its caption), for screenshots: ids "speed-fn", "speed-fp", "family-NAME",
// "scene-I-tiers", "scene-I-broad".
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>

namespace snag::exporters {

/// Writes the page for `results`, the JSON of snag-bench (tools/bench/bench_results.hpp).
/// Throws UsageError when snag was built with SNAG_WITH_HTML=OFF; std::ios
/// failures are the caller's to check on `out`.
void write_bench_page(std::ostream& out, const nlohmann::json& results);

}  // namespace snag::exporters
