// What the exporters of snag-report need from one report, read in one
// streaming pass: the header, every frame record, region and track (region
// face lists only for the frames asked for), and the trailer. Events are not
// kept: exporters that list events read the report again, streaming.
#pragma once

#include <cstddef>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "report/records.hpp"

namespace snag::exporters {

struct ReportDigest {
  std::string path;
  report::Header header;
  std::vector<report::FrameRecord> frames;    ///< in scan order
  /// In id order; faces_a/faces_b empty outside the kept frames (face_count
  /// always holds the region's number of faces).
  std::vector<report::RegionRecord> regions;
  std::vector<report::TrackRecord> tracks;    ///< every track record, merged ones included, in report order
  report::Trailer trailer;
  /// Track id -> the id of the track it ended in: itself, or the end of its
  /// merged_into chain. Every track record's id is a key.
  std::map<std::size_t, std::size_t> root_track;
  /// Per track that did not merge (by id): its largest region over the
  /// tracks merged into it (most faces; the earliest id of equals), with its
  /// face lists whatever the kept frames (empty only in --events none reports).
  std::map<std::size_t, report::RegionRecord> largest_region;
};

/// Reads the report at `path`. Region face lists are kept for the cache frame
/// indices in `keep_faces_of` (all frames when `keep_all_faces`). Throws
/// InputError as ReportReader does.
ReportDigest read_digest(const std::string& path, const std::set<std::size_t>& keep_faces_of = {},
                         bool keep_all_faces = false);

/// Cache frame indices of the frames with the most checked events (collisions
/// and intersections), most first, ties by frame; at most `count`, only frames
/// with at least one event.
std::vector<std::size_t> worst_frames(const ReportDigest& digest, std::size_t count);

/// The track a region's track id ended in (ReportDigest::root_track; the id
/// itself when the report has no record of it).
std::size_t root_track_of(const ReportDigest& digest, std::size_t track);

/// Every object pair and kind the report's rules check (pairs, no_self and
/// the mode of the header), with the trailer's counts where it has them and
/// zeros where nothing was found, in the order: kind (collisions first), then
/// object a, object b. Pairs the trailer lists but the rules would not check
/// are included too.
std::vector<report::PairSummary> checked_pairs(const ReportDigest& digest);

/// Whether the checked events of a pair and kind failed the report: it has
/// some, and a threshold the verdict reached counts them ("events",
/// "regions", "tracks" count both kinds, "collisions" and "intersections"
/// their own).
bool pair_fails(const report::Trailer& trailer, const report::PairSummary& pair);

/// "cloth (self)" or "cloth / body": how people read a pair of objects.
std::string pair_label(const report::Header& header, std::size_t object_a, std::size_t object_b);

/// The summary report::print_summary writes, as text.
std::string summary_text(const ReportDigest& digest);

/// A report's file name without its directory and a .jsonl or .json extension
/// ("runs/shot_010.jsonl" -> "shot_010"); "-" gives "stdin".
std::string report_stem(const std::string& path);

}  // namespace snag::exporters
