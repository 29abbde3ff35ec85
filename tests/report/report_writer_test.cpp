// ReportWriter::write_events, which formats many events on several threads,
// block by block and batch by batch: its text is byte for byte that of the
// same events written one by one, at every size around its blocks and
// batches, several times over with the same writer (its buffers are kept);
// a stream that fails while it writes throws.
#include "report/report_writer.hpp"

#include <gtest/gtest.h>

#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <vector>

namespace snag::report {
namespace {

Header two_objects() {
  Header header;
  header.source = "test";
  header.objects = {{"cloth", 10, 10, 12, 21, "none", 0.0}, {"ball", 8, 8, 12, 18, "none", 0.0}};
  header.frame_count = 2;
  return header;
}

/// Event i: each kind and type, both objects, and numbers that differ from
/// event to event.
EventRecord event_number(std::size_t i) {
  EventRecord e;
  e.kind = i % 3 == 2 ? EventKind::kIntersection : EventKind::kCollision;
  e.type = e.kind == EventKind::kIntersection ? ContactType::kTriangleTriangle
                                              : (i % 2 == 0 ? ContactType::kVertexFace : ContactType::kEdgeEdge);
  e.frame = 12;
  e.toi_lo = 12 + double(i % 1000) / 1000;
  e.toi_hi = e.toi_lo + 1e-7;
  e.toi = e.toi_lo;
  e.a = {i % 2, i % 10, (i + 1) % 10};
  e.b = {(i / 2) % 2, i % 12, (i + 3) % 12};
  e.position = {double(i) * 0.125, -double(i) / 3, 1e-3 * double(i)};
  e.certainty = i % 7 == 0 ? Certainty::kUncertain : Certainty::kProven;
  e.region = i % 5 == 0 ? kNone : i / 5;
  e.allowed = i % 5 == 0 ? 1 : kNone;
  return e;
}

TEST(ReportWriter, ManyEventsAtOnceWriteTheTextOfEventsWrittenOneByOne) {
  // Around the block (2048 events) and the batch (16 blocks) of write_events.
  const std::vector<std::size_t> counts = {0, 1, 4095, 4096, 32767, 32768, 32769, 65536, 100001};
  std::ostringstream at_once, one_by_one;
  ReportWriter many(at_once), single(one_by_one);
  many.use_names_of(two_objects());
  single.use_names_of(two_objects());
  for (std::size_t count : counts) {
    many.write_events(count, event_number);
    for (std::size_t i = 0; i < count; ++i) single.write_event(event_number(i));
    many.flush();
    single.flush();
    ASSERT_EQ(at_once.str().size(), one_by_one.str().size()) << count << " events";
    EXPECT_TRUE(at_once.str() == one_by_one.str()) << count << " events";
  }
  std::size_t lines = 0;
  for (char c : at_once.str()) lines += c == '\n';
  std::size_t total = 0;
  for (std::size_t count : counts) total += count;
  EXPECT_EQ(lines, total);
}

/// A stream buffer that takes `room` bytes, then fails.
class FullBuffer : public std::streambuf {
 public:
  explicit FullBuffer(std::size_t room) : room_(room) {}

 protected:
  std::streamsize xsputn(const char*, std::streamsize n) override {
    const auto taken = std::min<std::streamsize>(n, static_cast<std::streamsize>(room_));
    room_ -= static_cast<std::size_t>(taken);
    return taken;
  }
  int_type overflow(int_type c) override {
    if (room_ == 0 || traits_type::eq_int_type(c, traits_type::eof())) return traits_type::eof();
    --room_;
    return c;
  }

 private:
  std::size_t room_;
};

TEST(ReportWriter, AStreamThatFailsWhileManyEventsAreWrittenThrows) {
  for (std::size_t room : {std::size_t{0}, std::size_t{1} << 20, std::size_t{5} << 20}) {
    FullBuffer buffer(room);
    std::ostream out(&buffer);
    ReportWriter writer(out);
    writer.use_names_of(two_objects());
    EXPECT_THROW(writer.write_events(100000, event_number), std::runtime_error) << room << " bytes of room";
  }
}

}  // namespace
}  // namespace snag::report
