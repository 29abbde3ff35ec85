// Markdown for CI step summaries and merge request comments: per report its
// verdict, a table per object pair and kind (events, regions, tracks,
// frames, worst frame) and the largest tracks. GitHub-flavoured tables.
#pragma once

#include <ostream>
#include <vector>

#include "exporters/digest.hpp"

namespace snag::exporters {

/// Writes a title with the batch's verdict, then a section per report.
void write_markdown(std::ostream& out, const std::vector<ReportDigest>& reports);

}  // namespace snag::exporters
