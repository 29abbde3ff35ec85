// The HTML page of snag-report: one self-contained file that opens from disk
// (no network, no server) and that a person understands in a minute. Per
// report: the verdict against the report's rules first, a chart of events and
// regions per frame (Chart.js; collisions and intersections stacked, a click
// selects a frame), the tracks table (sortable), and a 3D view (three.js,
// orbit controls) of the frames whose positions the page carries, the faces
// of each region coloured, with a frame slider. Several reports make one
// batch page: a summary table, then a section per report.
//
// The libraries are inlined from Debian's libjs-chart.js and libjs-three,
// embedded into the binary at build time (EmbedJs.cmake).
//
// Self-check: when the page has drawn, <body> carries data-ready="1",
// data-reports, data-frames-charted, data-tracks-listed (tracks that did not
// merge), data-regions-coloured and data-faces-drawn (the frame on display of
// each 3D view, summed), data-frame-shown (the first report's),
// data-webgl="1" or "0" (no WebGL: a visible message and a flat 2D drawing
// instead) and data-error when some part failed; each report's <section>
// carries the same for itself. Tests read these back from a headless browser.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "exporters/digest.hpp"

namespace snag::exporters {

/// One object's mesh: its triangles as local vertex ids (the scan's topology,
/// welded as the report says), in the order of the report's face ids.
struct HtmlMesh {
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< #F by 3 local vertex ids
};

/// The positions of one cache frame.
struct HtmlFrame {
  std::size_t frame = 0;                    ///< the cache's frame index
  std::vector<std::vector<float>> objects;  ///< per object: 3 * #V floats (x, y, z, ...), scene units
};

/// What the 3D view of one report draws: the meshes of the report's objects
/// (header order) and the positions of some frames.
struct HtmlScene {
  std::vector<HtmlMesh> objects;
  /// Most important first (the worst frames): over the size budget, frames are
  /// dropped from the back. The page shows them in frame order.
  std::vector<HtmlFrame> frames;
};

struct HtmlInputs {
  /// Per report (same order as `reports`; may be shorter): its scene, or
  /// nullopt for a page without 3D view. The region faces coloured in a frame
  /// are those the digest kept (read_digest's keep_faces_of must name the
  /// frames given here).
  std::vector<std::optional<HtmlScene>> scenes;
  std::string title;  ///< the page's title; "" for one made from the reports
  /// Bytes of page text for the 3D views' geometry, shared by the reports.
  /// Over it, faces away from the regions are sampled (full resolution is
  /// kept within a margin of each region), then frames are dropped.
  std::size_t geometry_budget = std::size_t{16} << 20;
};

/// Writes the page for `reports` (one: a report page; several: a batch page).
/// Throws UsageError when `inputs` does not fit the reports (a scene with a
/// different object count, positions of the wrong length, a vertex id out of
/// range) or when snag was built with SNAG_WITH_HTML=OFF; std::ios failures
/// are the caller's to check on `out`.
void write_html(std::ostream& out, const std::vector<ReportDigest>& reports, const HtmlInputs& inputs);

}  // namespace snag::exporters
