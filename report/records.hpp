// The records of a scan report, version 2 (man/snag-report.5). A report is
// JSON Lines: one JSON object per line, each with a "record" key, in this
// order:
//
//   header                       once: tool, version, source, objects, settings, rules
//   per frame, in frame order:
//     frame                      the frame's counts
//     event ...                  its intersections and the collisions of the step that starts at it, in event order
//     region ...                 its regions
//     track ...                  the tracks that ended before it
//   track ...                    the tracks still open at the end
//   trailer                      once: totals, per-pair summary, allow-rule counts, verdict, stages, timing
//
// A report without a trailer is incomplete (the writer renames it into place
// only after writing the trailer). These structs are what the writer takes and
// the reader gives; ids in them are local to their object and vertex ids are
// the file's, as written.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "libcd/geometry/vec3.hpp"
#include "libcd/pipeline/event.hpp"
#include "report/rules.hpp"

namespace snag::report {

/// Current schema version; readers accept this one only (version 1 was one JSON document).
constexpr int kSchemaVersion = 2;
constexpr std::size_t kNone = static_cast<std::size_t>(-1);

struct ObjectInfo {
  std::string name;
  std::size_t vertices = 0, file_vertices = 0, triangles = 0, edges = 0;
  std::string weld;        ///< the method that ran: "none", "exact" or the distance
  double thickness = 0;    ///< this object's contact thickness
};

/// How the scan ran, and the rules it was judged by (see rules.hpp for their meaning).
struct ReportSettings {
  std::string mode = "all";          ///< "ccd", "dcd" or "all"
  std::string backend;               ///< "cpu" or "cuda"
  std::string precision = "certified";
  double thickness = 0, lambda = 1.2;
  std::string grid = "uniform";      ///< "uniform" or "adaptive" (crowded cells subdivided): snag-scan --grid
  unsigned threads = 0;
  std::string frames;                ///< the --frames selection, "" for all
  std::string weld = "auto";
  std::string events = "all";        ///< "all", "regions" or "none": what the event records list
  std::size_t max_events = 0;        ///< "all": at most this many event records (0 = no cap)
  std::string manifest;              ///< the manifest's path, "" when none
};

struct Header {
  int version = kSchemaVersion;
  std::string tool = "snag-scan";
  std::string snag_version;
  std::string source;
  std::vector<ObjectInfo> objects;
  std::size_t frame_count = 0;   ///< frames the scan will write (after selection)
  ReportSettings settings;
  ScanRules rules;  ///< as given (names), with the thresholds
  bool certified = true;
};

struct FrameRecord {
  std::size_t position = 0;   ///< 0-based position in the scan
  std::size_t index = 0;      ///< the cache's frame index
  double time = 0;
  /// Checked events (not allowed, not dropped): collisions of the step that
  /// starts here, by type, and intersections in this frame.
  std::size_t collisions = 0, vf = 0, ee = 0, uncertain = 0, intersections = 0;
  std::size_t allowed = 0;    ///< events allowed by a rule (both kinds)
  std::size_t regions = 0;
};

/// An element reference: object index and local id; `id2` is the second end
/// of an edge. Vertex ids are the file's.
struct ElementRef {
  std::size_t object = 0;
  std::size_t id = 0, id2 = 0;
};

struct EventRecord {
  EventKind kind = EventKind::kCollision;
  ContactType type = ContactType::kVertexFace;
  std::size_t frame = 0;               ///< cache frame index (collisions: the step's first frame)
  double toi = 0, toi_lo = 0, toi_hi = 0;  ///< collisions: absolute, in frames (frame + fraction)
  ElementRef a, b;                     ///< vf: vertex, face; ee: edge, edge; intersection: face, face
  Vec3 position;
  Certainty certainty = Certainty::kProven;
  std::size_t region = kNone;          ///< the region it belongs to; kNone when allowed
  std::size_t allowed = kNone;         ///< the allow rule that matched, kNone when checked
};

struct Bounds {
  Vec3 lo, hi;
};

/// How bad an intersection region is, in scene units: written by snag-volume
/// only (the "measures" object of a region record, man/snag-report.5). Which
/// fields hold a value depends on `measure`:
/// - "overlap_volume" (two closed objects) and "self_overlap_volume" (a closed
///   object where its winding number is two or more): volume, volume_error;
/// - "penetration" (an open object into a closed one): depth, depth_error,
///   area, area_error;
/// - "curve_length" (open objects, or one open object with itself):
///   curve_length, segments (no voxels: voxel_size 0).
/// The errors are estimates: the change from the measure at twice the voxel size.
struct RegionMeasures {
  std::string measure;
  std::string reason;            ///< why this measure: each object's closedness
  double voxel_size = 0;
  double volume = 0, volume_error = 0;
  double depth = 0, depth_error = 0;
  double area = 0, area_error = 0;
  double curve_length = 0;
  std::size_t segments = 0;      ///< intersecting triangle pairs whose segments make the curve
};

/// Connected problem area of one frame (intersections) or step (collisions)
/// between one pair of objects.
struct RegionRecord {
  std::size_t id = 0;
  EventKind kind = EventKind::kIntersection;
  std::size_t object_a = 0, object_b = 0;  ///< a <= b; equal for self-contact
  std::size_t frame = 0;                   ///< cache frame index
  std::size_t track = 0;
  /// Sorted local face ids; faces_b empty when a == b. Reports written with
  /// settings.events "none" omit the lists (face_count stays): both empty.
  std::vector<std::size_t> faces_a, faces_b;
  std::size_t face_count = 0;              ///< faces_a.size() + faces_b.size() as built, kept when lists are not
  std::size_t events = 0;
  Bounds bounds;
  Vec3 centroid;
  double toi = 0;                          ///< collisions: the earliest time of impact (absolute)
  std::optional<RegionMeasures> measures;  ///< snag-volume's measures; absent in snag-scan's reports
};

/// Regions of consecutive frames that share faces.
struct TrackRecord {
  std::size_t id = 0;
  EventKind kind = EventKind::kIntersection;
  std::size_t object_a = 0, object_b = 0;
  std::size_t first_frame = 0, last_frame = 0;  ///< cache frame indices
  std::size_t frames = 0;                       ///< frames with a region of the track
  std::size_t regions = 0, events = 0;
  std::size_t max_faces = 0;                    ///< faces of its largest region
  std::size_t worst_frame = 0;                  ///< frame of its largest region
  Bounds bounds;                                ///< of all its regions
  Vec3 centroid;                                ///< of its largest region
  double toi = 0;                               ///< collisions: the earliest time of impact
  std::size_t merged_into = kNone;              ///< the track that went on when this one joined it
};

/// Per object pair and kind: the totals a person reads first.
struct PairSummary {
  EventKind kind = EventKind::kIntersection;
  std::size_t object_a = 0, object_b = 0;
  std::size_t events = 0, allowed = 0, regions = 0, tracks = 0;
  std::size_t frames = 0;        ///< frames with at least one checked event
  std::size_t worst_frame = 0;   ///< the frame with the most checked events
  std::size_t worst_frame_events = 0;
};

struct Trailer {
  std::size_t frames = 0;
  /// Checked events; `listed` of all events (checked and allowed) were written as records.
  std::size_t events = 0, collisions = 0, vf = 0, ee = 0, intersections = 0, uncertain = 0;
  std::size_t allowed = 0, listed = 0, left_out = 0;
  std::size_t not_checked = 0, neighbourhood = 0;  ///< dropped by the pairs/self rules and the neighbourhood
  std::size_t regions = 0, tracks = 0;
  std::vector<PairSummary> pairs;
  std::vector<std::size_t> allow_counts;           ///< events per allow rule
  std::vector<TrackRecord> largest_tracks;         ///< up to five, largest first (by events)
  bool pass = true;
  std::vector<FailedRule> failed;
  /// Stage counters and times, as JSON text (objects), copied through.
  std::string stages_json = "{}", timing_json = "{}";
};

const char* kind_name(EventKind kind);      ///< "collision" or "intersection"
const char* type_name(ContactType type);    ///< "vf", "ee" or "tt"

}  // namespace snag::report
