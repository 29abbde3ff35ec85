// snag-verify's side of the report: reading a scan report (version 2, JSON
// Lines, man/snag-report.5) as a stream and matching it to the cache it
// claims to describe, checking its regions against its events and its totals
// against its frames, and writing what the exact verification found, as text
// and as JSON (keys in man/snag-verify.1).
#pragma once

#include <array>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "libcd/pipeline/event.hpp"
#include "libcd/scene/frame_source.hpp"
#include "report/records.hpp"
#include "report/report_reader.hpp"
#include "validate/verify_events.hpp"
#include "validate/verify_queries.hpp"

namespace snag::tools {

/// One disagreement between a report's regions, events, frame records and
/// trailer.
struct RegionMismatch {
  std::size_t frame = report::kNone;   ///< cache frame index; kNone for the report's totals
  std::size_t region = report::kNone;  ///< region id; kNone when no region is concerned
  std::size_t line = 0;                ///< the report's line that disagrees
  std::string reason;
};

/// A report's listed events, as events of the cache, and what its own
/// records say about one another.
struct ReportEvents {
  /// The listed events (checked and allowed), global ids of the cache's scene,
  /// frames as positions in the (selected) source, toi relative to the frame,
  /// in report order.
  std::vector<Event> events;
  std::vector<std::size_t> lines;  ///< the report line of each event
  std::vector<char> allowed;       ///< 1 for each event an allow rule matched
  /// True when the report lists every event it found: settings.events is
  /// "all" and the trailer left none out. Otherwise an event found exactly
  /// but not listed cannot be told from one the report left out.
  bool complete = true;
  std::size_t left_out = 0;        ///< the trailer's count of events not listed
  std::size_t regions_checked = 0;
  std::vector<RegionMismatch> mismatches;
  /// Per frame position: the checked events the frame record counts, by kind
  /// and type (index: 0 intersections, 1 VF, 2 EE).
  std::vector<std::array<std::size_t, 3>> frame_counts;
};

/// Reads the rest of an opened report (after its header) and checks it
/// against `source`: every region against the events naming it (kind,
/// objects, frame and faces always; the event counts when the report is
/// complete), every frame record against its regions (and its events when
/// complete), the trailer's totals against the sums of the frame records.
/// Those disagreements are collected, not thrown.
/// Throws InputError (the report's file and line) when the report does not
/// describe this cache: object count, names, welding or vertex, file vertex,
/// triangle or edge counts differ, the frames differ, an edge is not an edge
/// of its object, or a collision starts at the last frame; and for what the
/// reader throws.
ReportEvents read_report_events(report::ReportReader& reader, const FrameSource& source);

/// What the exhaustive search found that the report does not list, split by
/// what it means.
struct UnlistedEvents {
  std::vector<Event> missed;       ///< checked by the scan's rules and not found by it
  std::vector<Event> unlisted;     ///< the report is not complete: missed, or left out of the list
  std::size_t not_checked = 0;     ///< in pairs the scan's rules do not check (not a miss)
  /// Incomplete reports: events found exactly beyond what the frame records
  /// count, summed over frames and kinds: certainly missed.
  std::size_t missed_beyond_counts = 0;
};

/// Splits VerifyResult::missed of an exhaustive verification of `listed`.
/// Throws UsageError when the report's rules name objects the cache lacks.
UnlistedEvents split_unlisted(const report::Header& header, const FrameSource& source, const ReportEvents& listed,
                              const validate::VerifyResult& result);

/// Human description of an event's pair, e.g. "cloth vertex 12 / body face 40".
std::string describe_pair(const Scene& scene, const Event& event);

/// What verification looked at: the events and, for a report, its checks.
struct Verification {
  const std::vector<Event>* events = nullptr;
  const ReportEvents* report = nullptr;         ///< null for --scan
  const UnlistedEvents* unlisted = nullptr;     ///< null without a report or without --exhaustive
  const validate::VerifyResult* result = nullptr;
  const validate::VerifySettings* settings = nullptr;
};

/// The verification summary as JSON (see man/snag-verify.1).
nlohmann::json verification_json(const FrameSource& source, const Verification& v);

/// Writes the counts and lists the false, mismatched and missed events and the region mismatches.
void print_verification(std::FILE* out, const FrameSource& source, const Verification& v);

/// True when verification found nothing wrong: every event confirmed, nothing
/// missed, the report's regions and totals agree.
bool all_confirmed(const Verification& v);

/// The query-set evaluation as JSON (see man/snag-verify.1).
nlohmann::json query_evaluation_json(const validate::QueryEvaluation& evaluation);

/// Writes the per-method, per-kind table and lists the wrong answers.
void print_query_evaluation(std::FILE* out, const validate::QueryEvaluation& evaluation);

}  // namespace snag::tools
