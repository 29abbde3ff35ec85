// The summary a person reads at a terminal: per object pair and kind, the
// events, regions, tracks, frames affected and the worst frame; the largest
// tracks with their frames and positions; what the rules allowed or did not
// check; and the verdict. Built from a report's header and trailer, so that
// it reads the same from a scan that just ran and from a report file.
#pragma once

#include <cstdio>
#include <string>

#include "report/records.hpp"

namespace snag::report {

/// Writes the summary as text.
void print_summary(std::FILE* out, const Header& header, const Trailer& trailer);

/// "FAIL: collisions 12 >= 1, tracks 3 >= 1" or "pass".
std::string verdict_text(const Trailer& trailer);

}  // namespace snag::report
