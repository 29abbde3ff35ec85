// A part of a scan split over several processes: the frames of one range of
// steps with their raw events, stored in a binary file by the process that
// scanned them and replayed, in order, into the one ReportSink that writes
// the report. Raw events (not report records) travel, so that rules,
// regions, tracks, ids and the event cap are applied once, over the whole
// run, exactly as in one process.
//
// File layout (native byte order; the part never leaves the run that wrote
// it): the magic "snag-part-1\n"; per frame 'F', position, cache frame
// index, time, FrameSummary, event count, the events; at the end 'E', the
// range's frame count, its stages and timing JSON (length, text).
#pragma once

#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "libcd/pipeline/scan.hpp"

namespace snag::report {

/// What a part says about its range as a whole, besides its frames.
struct PartTotals {
  std::size_t frames = 0;
  std::string stages_json, timing_json;  ///< tools/common/scan_stats.hpp's objects, as text
};

/// Applied to each step's events before they are stored: re-decides them at
/// each pair's own thickness (see report_sink.hpp's Redecide); may be empty.
using PartRedecide =
    std::function<void(const std::vector<Vec3>&, const std::vector<Vec3>&, std::vector<Event>&)>;

/// A ScanSink that stores each frame it gets, flushed frame by frame so that
/// a reader can follow it. Throws InputError naming the file when it cannot
/// be written.
class PartWriter : public ScanSink {
 public:
  explicit PartWriter(const std::string& path, PartRedecide redecide = {});
  ~PartWriter() override;
  PartWriter(const PartWriter&) = delete;
  PartWriter& operator=(const PartWriter&) = delete;

  void frame(ScannedFrame& frame) override;
  /// Writes the end record and closes the file.
  void finish(const PartTotals& totals);

 private:
  void write(const void* data, std::size_t bytes);
  std::string path_;
  std::FILE* file_ = nullptr;
  PartRedecide redecide_;
};

/// Called by replay_part() when it has read all that was written of a part
/// still being written (or when the part is not there yet): waits a little
/// and returns whether the writer has finished (closed the part), so that
/// what is missing after one more read is missing for good.
using PartWait = std::function<bool()>;

/// Replays a part into `sink`, frame by frame, reading each frame that has
/// events from `source` (the whole cache, positions as in the part) for the
/// sink's regions. The frames carry no next positions: the part's events
/// were re-decided already. `progress` gets each frame's position. Returns
/// the part's totals. The sink runs on a thread of its own, one frame at
/// a time, in order, while the next frame is read (as in scan_cache()).
/// With `wait_for_writer`, the part may still be being written (PartWriter
/// flushes each frame): the replay follows the writer, so that the merge
/// of a part overlaps its scan; without, the part must be complete.
/// Throws InputError naming the file when it is truncated or not a part,
/// and what the sink, the source or `wait_for_writer` throws.
PartTotals replay_part(const std::string& path, const FrameSource& source, ScanSink& sink,
                       const std::function<void(std::size_t)>& progress = {},
                       const PartWait& wait_for_writer = {});

}  // namespace snag::report
