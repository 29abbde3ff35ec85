// The scan's side of the report: takes each frame from the scan (a
// ScanSink), digests it (rules and regions: frame_digest.hpp), joins the
// digest to the run (region ids, tracks, the event cap, totals), writes the
// frame's records, and keeps only running totals, so that the scan's memory
// does not grow with the number of frames or events.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <tuple>
#include <vector>

#include "libcd/pipeline/scan.hpp"
#include "report/frame_digest.hpp"
#include "report/regions.hpp"
#include "report/report_writer.hpp"
#include "report/rules.hpp"

namespace snag::report {

/// Re-decides a step's collisions at each pair's own thickness (see
/// libcd/pipeline/pair_thickness.hpp): x_t0, x_t1, the step's events.
using Redecide = std::function<void(const std::vector<Vec3>&, const std::vector<Vec3>&, std::vector<Event>&)>;

class ReportSink : public ScanSink {
 public:
  /// `writer` may be null (a summary without a report). The header is
  /// written at once; `rules` and `writer` must outlive the sink.
  ReportSink(const Scene& scene, const Header& header, const RuleSet& rules, ReportWriter* writer,
             Redecide redecide = {});

  void frame(ScannedFrame& frame) override;
  /// Joins a frame digested elsewhere (with this sink's scene and rules) as
  /// frame() joins its own digest: the frames of a run, in order, whether
  /// digested here or there. Needs the first events_to_list() of the
  /// digest's kept events listable; throws std::logic_error when they are
  /// not. The digest's regions get their ids and tracks.
  void join(FrameDigest& digest);

  const RuleSet& rules() const { return rules_; }

  /// Ends the open tracks, judges the thresholds and writes the trailer
  /// (stages and timing: JSON objects as text). Returns the trailer.
  const Trailer& finish(std::string stages_json, std::string timing_json);

 private:
  using PairKey = std::tuple<int, std::size_t, std::size_t>;  // kind, object a <= b
  PairSummary& pair(EventKind kind, std::size_t a, std::size_t b);
  void end_tracks(std::vector<TrackRecord>& ended);
  EventRecord event_record(const Event& e) const;

  const Scene& scene_;
  Header header_;
  const RuleSet& rules_;
  ReportWriter* writer_;
  Redecide redecide_;
  FrameDigester digester_;
  TrackBuilder tracks_;
  std::size_t next_region_ = 0;
  Trailer trailer_;
  std::map<PairKey, PairSummary> pairs_;
  // Scratch reused frame after frame.
  FrameDigest digest_;
  std::vector<TrackRecord> ended_;
};

}  // namespace snag::report
