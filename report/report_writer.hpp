// Streaming writer of scan reports (JSON Lines, schema version 2; records.hpp
// and man/snag-report.5). Each record is one line, written as it is given:
// the writer keeps one line of text, never the report.
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "report/json_text.hpp"
#include "report/records.hpp"

namespace snag::report {

class ReportWriter {
 public:
  /// Writes to `out`, which must outlive the writer. Names in element
  /// references come from the header given to write_header().
  explicit ReportWriter(std::ostream& out);

  void write_header(const Header& header);
  /// Takes the object names of `header` without writing it: to write a
  /// trailer alone (the summary as JSON).
  void use_names_of(const Header& header);
  void write_frame(const FrameRecord& frame);
  void write_event(const EventRecord& event);
  /// Writes events 0 .. count - 1 as event(i) gives them, in that order;
  /// large batches are formatted on several threads (event() must be safe
  /// to call from several threads at once).
  void write_events(std::size_t count, const std::function<EventRecord(std::size_t)>& event);
  void write_region(const RegionRecord& region);
  void write_track(const TrackRecord& track);
  void write_trailer(const Trailer& trailer);
  /// Flushes what is buffered; throws std::runtime_error when the stream failed.
  void flush();

 private:
  void end_line();
  void object_name(std::size_t o);
  void object_pair(std::size_t a, std::size_t b);  ///< ,"objects":[a,b]
  void track_fields(const TrackRecord& track);
  void region_measures(const RegionMeasures& measures);  ///< ,"measures":{...}

  std::ostream& out_;
  std::vector<std::string> names_;
  bool region_faces_ = true;  // settings.events "none": regions without their face lists
  JsonText line_;
  std::vector<JsonText> blocks_;  // write_events' buffers, kept for the next batch
};

}  // namespace snag::report
