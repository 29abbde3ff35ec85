// JUnit XML for CI servers (Jenkins, GitLab): one testsuite per report, a
// testcase per object pair and kind the rules check (or per track), failures
// carrying frames, element ids and positions. The structure follows the
// JUnit schema Jenkins reads: testsuites > testsuite > properties, testcase
// (> failure, system-out), system-out.
#pragma once

#include <ostream>
#include <vector>

#include "exporters/digest.hpp"

namespace snag::exporters {

enum class JunitGranularity {
  kPair,   ///< a testcase per object pair and kind ("cloth / body intersection")
  kTrack,  ///< a testcase per track, and one per pair and kind without tracks
};

/// Writes one testsuites document with a testsuite per report, in order.
/// A pair and kind fails when its checked events failed the report
/// (pair_fails()); a track fails when its pair and kind does. Passing cases
/// are plain testcases (a system-out says what was allowed or found under the
/// thresholds). Region face lists come from ReportDigest::largest_region.
void write_junit(std::ostream& out, const std::vector<ReportDigest>& reports, JunitGranularity granularity);

}  // namespace snag::exporters
