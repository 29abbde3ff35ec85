// snag-verify's side of the report: reading a scan report (schema in
// man/snag-scan.1) and matching it to the cache it claims to describe, and
// writing what the exact verification found, as text and as JSON (keys in
// man/snag-verify.1).
#pragma once

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "libcd/pipeline/event.hpp"
#include "libcd/scene/frame_source.hpp"
#include "validate/verify_events.hpp"
#include "validate/verify_queries.hpp"

namespace snag::tools {

/// A scan report as read from its file, with the settings verification needs.
struct ScanReport {
  std::string path;
  nlohmann::json json;
  std::string mode;       ///< "ccd", "dcd" or "all"
  std::string frames;     ///< the --frames selection the scan used ("" = all)
  std::string weld;       ///< the --weld setting the scan used ("" in reports older than it)
  std::string backend;    ///< informational
  std::string precision;  ///< informational
  double thickness = 0;   ///< contact distance, scene units
};

/// Reads and checks the shape of a report (version, tool, settings, objects,
/// frames, events). Throws InputError (the file) when it cannot be read, is
/// not JSON, or lacks a key or has one of the wrong type.
ScanReport read_scan_report(const std::string& path);

/// The report's events as global-id events of `source`'s scene, in report
/// order (toi in step units relative to the frame).
/// Throws InputError (the report's file) when the report does not describe
/// this cache: object count, names or vertex/triangle/edge counts differ, the
/// frame count differs, or an event has a frame or an id out of range, an
/// edge that is not an edge of its object, an unknown kind or type.
std::vector<Event> report_events(const ScanReport& report, const FrameSource& source);

/// Human description of an event's pair, e.g. "cloth vertex 12 / body face 40".
std::string describe_pair(const Scene& scene, const Event& event);

/// The verification summary as JSON (see man/snag-verify.1).
nlohmann::json verification_json(const FrameSource& source, const std::vector<Event>& reported,
                                 const validate::VerifyResult& result, const validate::VerifySettings& settings);

/// Writes the counts and lists the false, mismatched and missed events.
void print_verification(std::FILE* out, const FrameSource& source, const std::vector<Event>& reported,
                        const validate::VerifyResult& result, const validate::VerifySettings& settings);

/// The query-set evaluation as JSON (see man/snag-verify.1).
nlohmann::json query_evaluation_json(const validate::QueryEvaluation& evaluation);

/// Writes the per-method, per-kind table and lists the wrong answers.
void print_query_evaluation(std::FILE* out, const validate::QueryEvaluation& evaluation);

/// True when verification found nothing wrong (every event confirmed, nothing missed).
bool all_confirmed(const validate::VerifyResult& result);

}  // namespace snag::tools
