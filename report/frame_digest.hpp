// A frame's share of the report that depends on that frame alone: the rules
// applied to its events, its counts per pair, and its regions. The report's
// sink digests each frame and then joins the digest to the run (region ids,
// tracks, the event cap, totals: report_sink.hpp). The cut lets a scan split
// over processes digest each range where it is scanned and send only the
// digests to the one process that joins them (scan_part.hpp): the joined
// report is the one process's, since that process digests and joins the same
// way.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <tuple>
#include <vector>

#include "libcd/pipeline/scan.hpp"
#include "report/records.hpp"
#include "report/regions.hpp"
#include "report/rules.hpp"

namespace snag::report {

/// One pair's and kind's events of a frame that the rules kept.
struct PairCounts {
  EventKind kind = EventKind::kIntersection;
  std::size_t object_a = 0, object_b = 0;  ///< a <= b
  std::size_t checked = 0, allowed = 0;
};

struct FrameDigest {
  /// Position, cache index, time and the checked and allowed counts; `regions` set.
  FrameRecord record;
  std::size_t not_checked = 0, neighbourhood = 0;  ///< events dropped by the pairs/self rules and the neighbourhood
  std::vector<std::size_t> allow_counts;           ///< events per allow rule
  std::vector<PairCounts> pairs;                   ///< ascending by (kind, a, b)
  /// Id and track not set (run-wide: the join gives them).
  std::vector<RegionRecord> regions;
  /// The events the rules kept (checked and allowed), in event order; the
  /// digest holds the first `listable` of them, which `events` points to
  /// (the frame's own list, or a buffer of the digest's reader).
  std::size_t kept = 0, listable = 0;
  const Event* events = nullptr;
  /// Per listable event: the allow rule that matched (kNone when checked)
  /// and the index in `regions` of its region (kNone when allowed).
  std::vector<std::size_t> allowed_by, region_of;
};

/// Of `kept` events of a frame, how many the report lists after `listed`
/// events of the frames before: all with events "all" up to max_events
/// over the run, none else.
std::size_t events_to_list(const ReportSettings& settings, std::size_t listed, std::size_t kept);

/// Digests frames one after the other; holds the scene-sized scratch of the
/// region builder, so that each frame costs time in its events.
class FrameDigester {
 public:
  /// `rules` must outlive the digester. `faces`: the scene's adjacency, when
  /// several digesters share it (made here when null).
  FrameDigester(const Scene& scene, const RuleSet& rules, std::shared_ptr<const FaceAdjacency> faces = nullptr);

  /// Applies the rules to the frame's events, moving the kept ones down in
  /// place (the scan lets a sink remove events), and builds the regions of
  /// the checked ones into `digest` (every field set; listable = kept,
  /// events = the frame's list).
  void digest(ScannedFrame& frame, FrameDigest& digest);

 private:
  using PairKey = std::tuple<int, std::size_t, std::size_t>;  // kind, object a <= b

  /// Counts of a block of a frame's events, summed over the blocks.
  struct Tally {
    std::size_t collisions = 0, vf = 0, ee = 0, uncertain = 0, intersections = 0, allowed = 0;
    std::size_t not_checked = 0, neighbourhood = 0;
    std::vector<std::size_t> allow_counts;  ///< per allow rule
    std::map<PairKey, PairCounts> pairs;
    void add(const Tally& other);
  };
  void tally(const std::vector<Event>& events, std::size_t begin, std::size_t end,
             std::vector<std::size_t>& allowed_by, Tally& sum);

  const Scene& scene_;
  const RuleSet& rules_;
  RegionBuilder regions_;
  // Per event of the frame, scratch.
  std::vector<Disposition::Kind> dispositions_;
  std::vector<GroupWord> group_of_;  ///< the checked events' groups (kNoGroup: allowed, dropped)
};

}  // namespace snag::report
