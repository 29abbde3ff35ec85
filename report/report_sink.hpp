// The scan's side of the report: takes each frame from the scan (a
// ScanSink), digests it (rules and regions: frame_digest.hpp), joins the
// digest to the run (region ids, tracks, the event cap, totals), writes the
// frame's records, and keeps only running totals, so that the scan's memory
// does not grow with the number of frames or events. Two frames are digested
// at once (prepare(), on the scan's sink threads), each by a digester of its
// own, and joined in turn in frame(). A frame that lists no events is joined
// on a thread of the sink's own while the next ones are digested (the join
// reads only the digest); one that lists events reads the scan's list and is
// joined before frame() returns. The digesters (their scene-sized scratch
// and the scene's adjacency, which they share) are made on that thread as
// the sink is, while the scan starts, not on its first frames.
#pragma once

#include <tbb/task_arena.h>

#include <cstddef>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <tuple>
#include <vector>

#include "libcd/core/worker_thread.hpp"
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
  /// Waits for the frame being joined, if any (what it throws is dropped:
  /// finish() was not reached).
  ~ReportSink() override;
  ReportSink(const ReportSink&) = delete;
  ReportSink& operator=(const ReportSink&) = delete;

  /// Joins the frame, digested by prepare() (or here, when it was not).
  /// Rethrows what the join of an earlier frame threw.
  void frame(ScannedFrame& frame) override;
  std::size_t frames_at_once() const override { return kFramesAtOnce; }
  /// Re-decides the step's collisions and digests the frame (beside the
  /// other frame being digested and the frame being joined).
  void prepare(ScannedFrame& frame) override;
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
  static constexpr std::size_t kFramesAtOnce = 2;
  /// Waits for the frame being joined, if any, and gives its digest back;
  /// rethrows what the join threw.
  void wait_for_join();
  /// The digest prepare() made of the frame at `position`, or null.
  std::unique_ptr<FrameDigest> take_prepared(std::size_t position);
  void join_now(FrameDigest& digest);
  PairSummary& pair(EventKind kind, std::size_t a, std::size_t b);
  void end_tracks(std::vector<TrackRecord>& ended);
  EventRecord event_record(const Event& e) const;

  const Scene& scene_;
  Header header_;
  const RuleSet& rules_;
  ReportWriter* writer_;
  Redecide redecide_;
  TrackBuilder tracks_;
  std::size_t next_region_ = 0;
  Trailer trailer_;
  std::map<PairKey, PairSummary> pairs_;
  // Scratch reused frame after frame, under pool_mutex_: the digesters and
  // digests not in use (one digester a frame being digested; one digest a
  // frame being digested, waiting for its join or being joined), and the
  // digests made by prepare() that frame() has not yet taken, by position.
  std::mutex pool_mutex_;
  std::vector<std::unique_ptr<FrameDigester>> free_digesters_;
  std::vector<std::unique_ptr<FrameDigest>> free_digests_;
  std::map<std::size_t, std::unique_ptr<FrameDigest>> prepared_;
  std::unique_ptr<FrameDigest> joined_;  ///< the digest of the frame joined on joiner_, while joining_ is valid
  std::vector<TrackRecord> ended_;
  std::shared_ptr<const FaceAdjacency> faces_;  ///< the scene's, made with the digesters
  std::shared_future<void> digesters_made_;     ///< the digesters made on joiner_ (holds what that threw)
  // The join's parallel work (the tracks) runs in an arena of its own, apart
  // from the digest's on the sink's thread.
  tbb::task_arena join_arena_;
  std::future<void> joining_;  ///< the frame joined on joiner_, while valid
  WorkerThread joiner_;        ///< last: it stops first
};

}  // namespace snag::report
