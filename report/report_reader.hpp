// Streaming reader of scan reports (JSON Lines, schema version 2, see
// records.hpp and man/snag-report.5): one record at a time, so that reading
// a report of any size takes memory for one line, not for the file.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "report/records.hpp"

namespace snag::report {

class ReportReader {
 public:
  enum class Record { kFrame, kEvent, kRegion, kTrack, kTrailer, kEnd };

  /// Opens `path` ("-" = standard input) and reads the header. Throws
  /// InputError naming the file and the line when it cannot be read, is not a
  /// version-2 report (a version-1 report gets a message saying to scan again),
  /// or the header lacks a key or has one of the wrong type.
  explicit ReportReader(const std::string& path);
  ~ReportReader();
  ReportReader(const ReportReader&) = delete;
  ReportReader& operator=(const ReportReader&) = delete;

  const Header& header() const;

  /// Reads the next record and says which it was; kEnd after the trailer.
  /// Throws InputError (file, line, problem) for a malformed line, a record
  /// out of order, an object index or frame out of range, or a file that ends
  /// without a trailer (an incomplete report).
  Record next();

  /// The record next() last read, of the kind it returned.
  const FrameRecord& frame() const;
  const EventRecord& event() const;
  const RegionRecord& region() const;
  const TrackRecord& track() const;
  const Trailer& trailer() const;

  /// The line number (1-based) of the record last read.
  std::size_t line() const;
  const std::string& path() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace snag::report
