// The report sink joins a frame that lists no events on a thread of its own
// while it digests the next one, and digests two frames at once on the scan's
// sink threads: its report is byte for byte the report of
// the same frames digested and joined one after the other, the scan's list
// of a frame may change as soon as frame() returns, and what a join threw
// comes out of the next frame().
#include "report/report_sink.hpp"

#include <gtest/gtest.h>

#include <ostream>
#include <sstream>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <vector>

#include "libcd/pipeline/sink_thread.hpp"
#include "report/frame_digest.hpp"
#include "report/report_writer.hpp"
#include "report/rules.hpp"

namespace snag::report {
namespace {

/// A grid of n x n unit quads in the plane z = 0, two faces each: vertex
/// (i, j) is j (n + 1) + i, quad (i, j) faces 2 (j n + i) and 2 (j n + i) + 1.
struct Grid {
  Scene scene;
  std::vector<Vec3> x;
};

Grid grid(Index n) {
  std::vector<Triangle> triangles;
  for (Index j = 0; j < n; ++j) {
    for (Index i = 0; i < n; ++i) {
      const Index v = j * (n + 1) + i;
      triangles.push_back({v, v + 1, v + n + 1});
      triangles.push_back({v + 1, v + n + 2, v + n + 1});
    }
  }
  Grid g{Scene({make_object("cloth", (n + 1) * (n + 1), triangles)}), {}};
  for (Index j = 0; j <= n; ++j)
    for (Index i = 0; i <= n; ++i) g.x.push_back({double(i), double(j), 0.0});
  return g;
}

/// Frame k's events: the two faces of every quad q with (q + k) % stride == 0
/// intersect, and the first corner of each such quad touches a face three
/// quads on: regions and tracks that change from frame to frame.
std::vector<Event> frame_events(const Grid& g, std::size_t k, std::size_t stride) {
  std::vector<Event> events;
  const std::size_t quads = g.scene.triangle_count() / 2;
  for (std::size_t q = 0; q < quads; ++q) {
    if ((q + k) % stride != 0) continue;
    Event collision;
    collision.kind = EventKind::kCollision;
    collision.type = ContactType::kVertexFace;
    collision.a = g.scene.triangles()[2 * q][0];
    collision.b = static_cast<Index>(2 * ((q + 3) % quads));
    collision.toi_lo = collision.toi_hi = 0.25 + 0.5 * double(q % 2);
    collision.position = g.x[collision.a];
    collision.frame = k;
    events.push_back(collision);
  }
  for (std::size_t q = 0; q < quads; ++q) {
    if ((q + k) % stride != 0) continue;
    Event intersection;
    intersection.kind = EventKind::kIntersection;
    intersection.type = ContactType::kTriangleTriangle;
    intersection.a = static_cast<Index>(2 * q);
    intersection.b = static_cast<Index>(2 * q + 1);
    intersection.position = g.x[g.scene.triangles()[2 * q][1]];
    intersection.frame = k;
    events.push_back(intersection);
  }
  return events;
}

Header header_of(const Scene& scene, const std::string& events, std::size_t max_events, std::size_t frames) {
  Header header;
  header.source = "grid";
  for (const Object& object : scene.objects()) {
    header.objects.push_back({object.name, object.vertex_count, file_vertex_count(object), object.triangles.size(),
                              object.edges.size(), object.weld.method, 0.0});
  }
  header.frame_count = frames;
  header.settings.events = events;
  header.settings.max_events = max_events;
  return header;
}

ScannedFrame scanned(std::size_t k, std::vector<Event>& events, const std::vector<Vec3>& x) {
  ScannedFrame frame;
  frame.position = k;
  frame.time = double(k);
  frame.summary.frame = k;
  frame.events = &events;
  frame.x = &x;
  return frame;
}

// The first frames list events (joined before frame() returns), the later
// ones none (joined while the next is digested); the scan's list is given a
// later frame's events as soon as frame() returns.
TEST(ReportSink, FramesJoinedBesideTheNextDigestWriteTheReportOfFramesJoinedInTurn) {
  const Grid g = grid(12);
  const RuleSet rules(g.scene, {}, 0.0);
  constexpr std::size_t kFrames = 9;
  const Header header = header_of(g.scene, "all", 40, kFrames);

  std::ostringstream in_turn_out;
  {
    ReportWriter writer(in_turn_out);
    ReportSink sink(g.scene, header, rules, &writer);
    FrameDigester digester(g.scene, rules);
    for (std::size_t k = 0; k < kFrames; ++k) {
      std::vector<Event> events = frame_events(g, k, 3 + k % 2);
      ScannedFrame frame = scanned(k, events, g.x);
      FrameDigest digest;
      digester.digest(frame, digest);
      sink.join(digest);
    }
    sink.finish("{}", "{}");
  }

  std::ostringstream out;
  {
    ReportWriter writer(out);
    ReportSink sink(g.scene, header, rules, &writer);
    std::vector<Event> events;
    for (std::size_t k = 0; k < kFrames; ++k) {
      events = frame_events(g, k, 3 + k % 2);
      ScannedFrame frame = scanned(k, events, g.x);
      sink.frame(frame);
      events = frame_events(g, k + 1, 2);  // the scan's list, no longer the sink's
    }
    sink.finish("{}", "{}");
  }
  // Through the scan's sink threads: two frames digested at once, each
  // frame's list its own until the sink is done with it.
  std::ostringstream two_at_once_out;
  {
    ReportWriter writer(two_at_once_out);
    ReportSink sink(g.scene, header, rules, &writer);
    std::vector<std::vector<Event>> lists(kFrames);
    {
      SinkThread thread(sink, 2);
      for (std::size_t k = 0; k < kFrames; ++k) {
        lists[k] = frame_events(g, k, 3 + k % 2);
        thread.hand(scanned(k, lists[k], g.x));
      }
      thread.drain();
    }
    sink.finish("{}", "{}");
  }
  ASSERT_GT(in_turn_out.str().size(), 0u);
  EXPECT_EQ(two_at_once_out.str(), in_turn_out.str());
  EXPECT_NE(in_turn_out.str().find("\"record\":\"event\""), std::string::npos);
  EXPECT_NE(in_turn_out.str().find("\"record\":\"track\""), std::string::npos);
  EXPECT_EQ(out.str(), in_turn_out.str());
}

/// Takes `room` bytes, then fails every write.
class FailingBuffer : public std::streambuf {
 public:
  explicit FailingBuffer(std::size_t room) : room_(room) {}

 protected:
  std::streamsize xsputn(const char*, std::streamsize count) override {
    if (static_cast<std::size_t>(count) > room_) return 0;
    room_ -= static_cast<std::size_t>(count);
    return count;
  }
  int_type overflow(int_type c) override { return xsputn(nullptr, 1) == 1 ? c : traits_type::eof(); }

 private:
  std::size_t room_;
};

// A frame of a region of every face of a large grid (its face list over the
// writer's 1 MiB buffer) is joined beside the next frame's digest; the
// stream fails as it is written, and the next frame() says so.
TEST(ReportSink, AJoinThatFailsIsThrownByTheNextFrame) {
  const Grid g = grid(300);
  const RuleSet rules(g.scene, {}, 0.0);
  FailingBuffer buffer(1000);
  std::ostream stream(&buffer);
  ReportWriter writer(stream);
  ReportSink sink(g.scene, header_of(g.scene, "regions", 0, 2), rules, &writer);
  std::vector<Event> events = frame_events(g, 0, 1);
  ScannedFrame first = scanned(0, events, g.x);
  sink.frame(first);  // joined beside the next: no events listed
  std::vector<Event> next = frame_events(g, 1, 1);
  ScannedFrame second = scanned(1, next, g.x);
  try {
    sink.frame(second);
    FAIL() << "the failed write of the first frame was not reported";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("writing the report failed"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace snag::report
