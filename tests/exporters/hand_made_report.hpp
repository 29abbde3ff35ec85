// A small report written with report::ReportWriter, whose every count the
// exporter tests know: two objects with names that need quoting in CSV and
// escaping in XML, three frames (cache indices 10 to 12), a track that
// merges into another, an allowed event, and a verdict that fails on
// collisions only (so the pair with intersections passes under the thresholds).
#pragma once

#include <fstream>
#include <string>

#include "report/report_writer.hpp"

namespace snag::test {

/// Object names: quotes, a comma, markup characters.
inline const std::string kCape = "cape, \"hero\"";
inline const std::string kBody = "body<1>&";

/// Writes the report to `path`:
///   frame 10: region 0 (cape self collision, faces 1 2, track 0, 2 events),
///             region 1 (cape / body intersection, cape face 3, body face 0, track 1, 1 event),
///             an allowed cape self collision (rule 0);
///   frame 11: region 2 (cape self collision, faces 2 4, track 0, 1 event),
///             region 3 (cape self collision, face 5, track 2, 1 event);
///   frame 12: nothing; then track 2 (merged into 0), track 0, track 1.
/// Cape has 6 vertices and 6 triangles, body 4 and 2. Fails: collisions 4 >= 1.
inline void write_hand_made_report(const std::string& path, const std::string& events = "all") {
  using namespace snag::report;
  std::ofstream file(path);
  ReportWriter writer(file);
  Header header;
  header.snag_version = "0.1.0";
  header.source = "hand-made";
  header.objects = {{kCape, 6, 6, 6, 11, "none", 0}, {kBody, 4, 4, 2, 5, "none", 0}};
  header.frame_count = 3;
  header.settings.backend = "cpu";
  header.settings.frames = "10:12";
  header.settings.events = events;
  header.rules.allow.push_back(AllowRule{kCape, kCape, EventKind::kCollision, 10, 10, std::nullopt, "known"});
  header.rules.fail.events = 0;
  header.rules.fail.collisions = 1;
  writer.write_header(header);

  auto region = [](std::size_t id, EventKind kind, std::size_t a, std::size_t b, std::size_t frame,
                   std::size_t track, std::vector<std::size_t> faces_a, std::vector<std::size_t> faces_b,
                   std::size_t events, double toi) {
    RegionRecord r;
    r.id = id;
    r.kind = kind;
    r.object_a = a;
    r.object_b = b;
    r.frame = frame;
    r.track = track;
    r.faces_a = std::move(faces_a);
    r.faces_b = std::move(faces_b);
    r.face_count = r.faces_a.size() + r.faces_b.size();
    r.events = events;
    r.bounds = {{0.1 * id, 0, 0}, {0.1 * id + 1, 1, 1}};
    r.centroid = {0.1 * id + 0.5, 1.0 / 3.0, -2.5e-7};
    r.toi = toi;
    return r;
  };
  auto collision = [](std::size_t frame, std::size_t vertex, std::size_t face, std::size_t region_id,
                      std::size_t allowed) {
    EventRecord e;
    e.kind = EventKind::kCollision;
    e.type = ContactType::kVertexFace;
    e.frame = frame;
    e.toi = e.toi_lo = frame + 0.25;
    e.toi_hi = frame + 0.2500001;
    e.a = {0, vertex, 0};
    e.b = {0, face, 0};
    e.position = {0.5, 0.25, 1e-3};
    e.region = region_id;
    e.allowed = allowed;
    return e;
  };
  auto track = [](std::size_t id, EventKind kind, std::size_t a, std::size_t b, std::size_t first, std::size_t last,
                  std::size_t regions, std::size_t events, std::size_t max_faces, std::size_t worst,
                  std::size_t merged_into) {
    TrackRecord t;
    t.id = id;
    t.kind = kind;
    t.object_a = a;
    t.object_b = b;
    t.first_frame = first;
    t.last_frame = last;
    t.frames = last - first + 1;
    t.regions = regions;
    t.events = events;
    t.max_faces = max_faces;
    t.worst_frame = worst;
    t.bounds = {{0, 0, 0}, {1, 1, 1}};
    t.centroid = {0.5, 0.5, 0.5};
    t.toi = kind == EventKind::kCollision ? 10.25 : 0;
    t.merged_into = merged_into;
    return t;
  };

  FrameRecord f;
  f.position = 0;
  f.index = 10;
  f.collisions = f.vf = 2;
  f.intersections = 1;
  f.allowed = 1;
  f.regions = 2;
  writer.write_frame(f);
  writer.write_event(collision(10, 0, 1, 0, kNone));
  writer.write_event(collision(10, 3, 2, 0, kNone));
  writer.write_event(collision(10, 4, 5, kNone, 0));
  EventRecord intersection;
  intersection.kind = EventKind::kIntersection;
  intersection.type = ContactType::kTriangleTriangle;
  intersection.frame = 10;
  intersection.a = {0, 3, 0};
  intersection.b = {1, 0, 0};
  intersection.position = {0.125, -0.5, 2};
  intersection.region = 1;
  writer.write_event(intersection);
  writer.write_region(region(0, EventKind::kCollision, 0, 0, 10, 0, {1, 2}, {}, 2, 10.25));
  writer.write_region(region(1, EventKind::kIntersection, 0, 1, 10, 1, {3}, {0}, 1, 0));

  f = FrameRecord{};
  f.position = 1;
  f.index = 11;
  f.collisions = f.vf = 2;
  f.regions = 2;
  writer.write_frame(f);
  writer.write_event(collision(11, 1, 4, 2, kNone));
  writer.write_event(collision(11, 0, 5, 3, kNone));
  writer.write_region(region(2, EventKind::kCollision, 0, 0, 11, 0, {2, 4}, {}, 1, 11.25));
  writer.write_region(region(3, EventKind::kCollision, 0, 0, 11, 2, {5}, {}, 1, 11.25));

  f = FrameRecord{};
  f.position = 2;
  f.index = 12;
  writer.write_frame(f);
  writer.write_track(track(2, EventKind::kCollision, 0, 0, 11, 11, 1, 1, 1, 11, 0));
  writer.write_track(track(0, EventKind::kCollision, 0, 0, 10, 11, 3, 4, 2, 10, kNone));
  writer.write_track(track(1, EventKind::kIntersection, 0, 1, 10, 10, 1, 1, 2, 10, kNone));

  Trailer t;
  t.frames = 3;
  t.events = 5;
  t.collisions = t.vf = 4;
  t.intersections = 1;
  t.allowed = 1;
  t.listed = 6;
  t.regions = 4;
  t.tracks = 2;
  PairSummary self{EventKind::kCollision, 0, 0, 4, 1, 3, 1, 2, 10, 2};
  PairSummary cross{EventKind::kIntersection, 0, 1, 1, 0, 1, 1, 1, 10, 1};
  t.pairs = {self, cross};
  t.allow_counts = {1};
  t.largest_tracks = {track(0, EventKind::kCollision, 0, 0, 10, 11, 3, 4, 2, 10, kNone),
                      track(1, EventKind::kIntersection, 0, 1, 10, 10, 1, 1, 2, 10, kNone)};
  t.pass = false;
  t.failed = {FailedRule{"collisions", 4, 1}};
  t.timing_json = "{\"total\":0.5}";
  writer.write_trailer(t);
  writer.flush();
}

}  // namespace snag::test
