// CSV for scripts: one row per region, or one row per event listed in the
// reports, RFC 4180 (comma-separated, CRLF line ends, fields with commas,
// quotes or line breaks quoted, quotes doubled), with a header row. Every row
// starts with the report's path, so that several reports make one table.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "exporters/digest.hpp"

namespace snag::exporters {

/// One row per region of each report, in report and id order: report, id,
/// kind, object_a, object_b (names), frame (cache index), track (the track
/// the region's track ended in: merged tracks followed), events, face_count,
/// bounds_lo_x/y/z, bounds_hi_x/y/z, centroid_x/y/z, toi (collisions; empty
/// for intersections).
void write_region_csv(std::ostream& out, const std::vector<ReportDigest>& reports);

/// One row per event record of each report, read again as a stream (memory
/// for one record): report, kind, type (vf, ee; empty for intersections),
/// frame, toi, toi_lo, toi_hi (collisions), object_a, a_element (vertex, edge
/// or face), a_id, a_id2 (an edge's second vertex), the same for b,
/// position_x/y/z, certainty (collisions), region (empty when allowed),
/// allowed (the allow rule's index, empty when checked). Throws InputError as
/// report::ReportReader does.
void write_event_csv(std::ostream& out, const std::vector<std::string>& report_paths);

}  // namespace snag::exporters
