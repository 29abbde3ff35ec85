// A part of a scan split over several processes: the frames of one range of
// steps, digested (rules and regions: frame_digest.hpp) by the process that
// scanned them, stored in a binary file and joined, in order, by the one
// ReportSink that writes the report. The digests hold what depends on their
// frame alone; region ids, tracks (joined across ranges), the event cap and
// the totals are the join's, over the whole run, exactly as in one process.
// A part holds each frame's events only as far as the report could list
// them (none unless events are listed; at most the cap).
//
// File layout (native byte order; the part never leaves the run that wrote
// it): the magic "snag-part-2\n"; per frame 'F' and its digest (the frame
// record, dropped counts, allow counts, pair counts, regions with their face
// lists, kept and listable counts, the listable events with their allow
// rules and regions); at the end 'E', the range's frame count, its stages
// and timing JSON (length, text).
#pragma once

#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "libcd/pipeline/scan.hpp"
#include "report/frame_digest.hpp"
#include "report/report_sink.hpp"

namespace snag::report {

/// What a part says about its range as a whole, besides its frames.
struct PartTotals {
  std::size_t frames = 0;
  std::string stages_json, timing_json;  ///< tools/common/scan_stats.hpp's objects, as text
  double join_seconds = 0;               ///< replay_part(): the sink's time joining the frames
};

/// Applied to each step's events before they are stored: re-decides them at
/// each pair's own thickness (see report_sink.hpp's Redecide); may be empty.
using PartRedecide =
    std::function<void(const std::vector<Vec3>&, const std::vector<Vec3>&, std::vector<Event>&)>;

/// A ScanSink that digests each frame it gets and stores the digest, flushed
/// frame by frame so that a reader can follow it. `settings` (events,
/// max_events) say how many events the report may list. Throws InputError
/// naming the file when it cannot be written. `rules` must outlive it.
class PartWriter : public ScanSink {
 public:
  PartWriter(const std::string& path, const Scene& scene, const RuleSet& rules, const ReportSettings& settings,
             PartRedecide redecide = {});
  ~PartWriter() override;
  PartWriter(const PartWriter&) = delete;
  PartWriter& operator=(const PartWriter&) = delete;

  void frame(ScannedFrame& frame) override;
  /// Writes the end record and closes the file.
  void finish(const PartTotals& totals);

 private:
  void write(const void* data, std::size_t bytes);
  template <typename T>
  void write_vector(const std::vector<T>& values);  ///< its size, then its values
  std::string path_;
  std::FILE* file_ = nullptr;
  ReportSettings settings_;
  PartRedecide redecide_;
  FrameDigester digester_;
  FrameDigest digest_;
  std::size_t stored_ = 0;  // events stored so far: no more than the cap can ever be listed
};

/// Called by replay_part() when it has read all that was written of a part
/// still being written (or when the part is not there yet): waits a little
/// and returns whether the writer has finished (closed the part), so that
/// what is missing after one more read is missing for good.
using PartWait = std::function<bool()>;

/// Joins a part's digests into `sink`, frame by frame (the sink's scene
/// and rules must be the writer's; `source` is the cache the positions are
/// of). `progress` gets each frame's position. Returns the part's totals.
/// The sink joins on a thread of its own, one frame at a time, in order,
/// while the next frame is read (as in scan_cache()). With
/// `wait_for_writer`, the part may still be being written (PartWriter
/// flushes each frame): the replay follows the writer, so that the merge
/// of a part overlaps its scan; without, the part must be complete.
/// Throws InputError naming the file when it is truncated, not a part or
/// not of this cache, and what the sink or `wait_for_writer` throws.
PartTotals replay_part(const std::string& path, const FrameSource& source, ReportSink& sink,
                       const std::function<void(std::size_t)>& progress = {},
                       const PartWait& wait_for_writer = {});

}  // namespace snag::report
