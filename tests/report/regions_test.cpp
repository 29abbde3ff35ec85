// Regions and tracks on hand-counted cases: a scene of two strips of eight
// quads (cloth and body), events placed by hand, and the regions and tracks
// a person would draw around them.
#include "report/regions.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace snag::report {
namespace {

// A strip of 8 quads: vertices (i, 0, z) i = 0..8 and (i, 1, z) as 9 + i;
// quad i is faces 2i and 2i + 1. Faces of quads i and i + 1 share vertices;
// quads two apart share none.
Object strip(const std::string& name) {
  std::vector<Triangle> triangles;
  for (Index i = 0; i < 8; ++i) {
    triangles.push_back({i, i + 1, 9 + i});
    triangles.push_back({i + 1, 10 + i, 9 + i});
  }
  return make_object(name, 18, triangles);
}

Scene two_strips() { return Scene({strip("cloth"), strip("body")}); }

std::vector<Vec3> positions() {
  std::vector<Vec3> x;
  for (double z : {0.0, 0.5}) {
    for (int row = 0; row < 2; ++row)
      for (int i = 0; i <= 8; ++i) x.push_back({double(i), double(row), z});
  }
  return x;
}

constexpr Index kBody = 16;  // global id of the body's first face

Event intersection(Index a, Index b, Vec3 where = {}) {
  Event e;
  e.kind = EventKind::kIntersection;
  e.type = ContactType::kTriangleTriangle;
  e.a = a;
  e.b = b;
  e.position = where;
  return e;
}

struct Built {
  std::vector<RegionRecord> regions;
  std::vector<std::size_t> region_of;
};

Built build(const Scene& scene, const std::vector<Event>& events, std::size_t frame = 0) {
  RegionBuilder builder(scene);
  Built out;
  const std::vector<char> all(events.size(), 1);
  builder.build(events, all, positions(), frame, out.regions, out.region_of);
  for (std::size_t r = 0; r < out.regions.size(); ++r) out.regions[r].id = r;
  return out;
}

TEST(Regions, TwoSeparateIntersectionsInOneFrameAreTwoRegions) {
  const Scene scene = two_strips();
  const Built b = build(scene, {intersection(0, kBody + 0, {0.2, 0.2, 0}), intersection(14, kBody + 14, {7.5, 0.5, 0})});
  ASSERT_EQ(b.regions.size(), 2u);
  EXPECT_EQ(b.region_of, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(b.regions[0].faces_a, (std::vector<std::size_t>{0}));
  EXPECT_EQ(b.regions[0].faces_b, (std::vector<std::size_t>{0}));
  EXPECT_EQ(b.regions[0].object_a, 0u);
  EXPECT_EQ(b.regions[0].object_b, 1u);
  EXPECT_EQ(b.regions[0].events, 1u);
  // Bounds of the region's faces in the frame: cloth face 0 at z 0, body face 0 at z 0.5.
  EXPECT_EQ(b.regions[0].bounds.lo.x, 0);
  EXPECT_EQ(b.regions[0].bounds.hi.x, 1);
  EXPECT_EQ(b.regions[0].bounds.hi.z, 0.5);
  EXPECT_EQ(b.regions[1].bounds.lo.x, 7);
  EXPECT_EQ(b.regions[1].centroid.x, 7.5);
}

TEST(Regions, FacesSharingAVertexJoinOneRegion) {
  const Scene scene = two_strips();
  // Cloth faces 1 and 2 (quads 0 and 1) share vertices; body faces 0 and 8 do not,
  // but each pair joins them through the cloth.
  const Built b = build(scene, {intersection(1, kBody + 0, {1, 0, 0}), intersection(2, kBody + 8, {3, 0, 0})});
  ASSERT_EQ(b.regions.size(), 1u);
  EXPECT_EQ(b.regions[0].faces_a, (std::vector<std::size_t>{1, 2}));
  EXPECT_EQ(b.regions[0].faces_b, (std::vector<std::size_t>{0, 8}));
  EXPECT_EQ(b.regions[0].events, 2u);
  EXPECT_EQ(b.regions[0].centroid.x, 2);
}

TEST(Regions, PairsAndKindsNeverShareARegion) {
  const Scene scene = two_strips();
  Event collision;
  collision.kind = EventKind::kCollision;
  collision.type = ContactType::kVertexFace;
  collision.a = 1;            // cloth vertex 1 (faces 0, 1, 2 around it)
  collision.b = kBody + 0;
  collision.toi_lo = 0.25;
  collision.toi_hi = 0.26;
  collision.frame = 7;
  // Sorted as the scan sorts them: collisions first.
  const Built b = build(scene, {collision, intersection(0, 3), intersection(0, kBody + 0)}, 7);
  ASSERT_EQ(b.regions.size(), 3u);
  EXPECT_EQ(b.regions[0].kind, EventKind::kCollision);
  EXPECT_EQ(b.regions[0].faces_a, (std::vector<std::size_t>{0, 1, 2}));  // around the vertex
  EXPECT_EQ(b.regions[0].faces_b, (std::vector<std::size_t>{0}));
  EXPECT_DOUBLE_EQ(b.regions[0].toi, 7.25);
  EXPECT_EQ(b.regions[1].object_a, 0u);  // cloth with itself
  EXPECT_EQ(b.regions[1].object_b, 0u);
  EXPECT_EQ(b.regions[1].faces_a, (std::vector<std::size_t>{0, 3}));
  EXPECT_TRUE(b.regions[1].faces_b.empty());
  EXPECT_EQ(b.regions[2].object_b, 1u);
}

TEST(Regions, EventsLeftOutOfRegionsGetNone) {
  const Scene scene = two_strips();
  RegionBuilder builder(scene);
  std::vector<RegionRecord> regions;
  std::vector<std::size_t> region_of;
  builder.build({intersection(0, kBody), intersection(14, kBody + 14)}, std::vector<char>{0, 1}, positions(), 0, regions, region_of);
  ASSERT_EQ(regions.size(), 1u);
  EXPECT_EQ(region_of, (std::vector<std::size_t>{kNone, 0}));
}

// Tracks over frames 0..4: one problem in frames 0-2 that moves along the
// strip, gone in frame 3, back in frame 4 (a new track).
TEST(Tracks, APersistingIntersectionIsOneTrack) {
  const Scene scene = two_strips();
  TrackBuilder tracks(scene);
  std::vector<TrackRecord> ended;
  const std::vector<std::vector<Event>> frames = {
      {intersection(0, kBody)}, {intersection(0, kBody), intersection(1, kBody + 1)}, {intersection(1, kBody + 1)},
      {}, {intersection(1, kBody + 1)}};
  std::vector<std::size_t> track_of_frame;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    Built b = build(scene, frames[f], f);
    tracks.add_frame(f, f, b.regions, ended);
    if (f == 3) {
      ASSERT_EQ(ended.size(), 1u);  // the first track ends when frame 3 has nothing
      EXPECT_EQ(ended[0].first_frame, 0u);
      EXPECT_EQ(ended[0].last_frame, 2u);
      EXPECT_EQ(ended[0].frames, 3u);
      EXPECT_EQ(ended[0].regions, 3u);
      EXPECT_EQ(ended[0].events, 4u);
      EXPECT_EQ(ended[0].max_faces, 4u);
      EXPECT_EQ(ended[0].worst_frame, 1u);
    }
    for (const RegionRecord& r : b.regions) track_of_frame.push_back(r.track);
  }
  EXPECT_EQ(track_of_frame, (std::vector<std::size_t>{0, 0, 0, 1}));
  tracks.finish(ended);
  ASSERT_EQ(ended.size(), 2u);
  EXPECT_EQ(ended[1].id, 1u);
  EXPECT_EQ(ended[1].first_frame, 4u);
  EXPECT_EQ(ended[1].merged_into, kNone);
}

TEST(Tracks, FramesThatShareNoFaceStartANewTrack) {
  const Scene scene = two_strips();
  TrackBuilder tracks(scene);
  std::vector<TrackRecord> ended;
  Built f0 = build(scene, {intersection(0, kBody)}, 0);
  tracks.add_frame(0, 0, f0.regions, ended);
  Built f1 = build(scene, {intersection(14, kBody + 14)}, 1);  // far along the strip
  tracks.add_frame(1, 1, f1.regions, ended);
  EXPECT_EQ(f1.regions[0].track, 1u);
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_EQ(ended[0].id, 0u);
}

TEST(Tracks, TwoTracksThatMeetGoOnAsTheOlderOne) {
  const Scene scene = two_strips();
  TrackBuilder tracks(scene);
  std::vector<TrackRecord> ended;
  Built f0 = build(scene, {intersection(0, kBody), intersection(8, kBody + 8)}, 0);
  tracks.add_frame(0, 0, f0.regions, ended);
  ASSERT_EQ(f0.regions.size(), 2u);
  // Frame 1: faces 0..8 of the cloth with body faces 0 and 8: one region touching both tracks.
  std::vector<Event> joined;
  for (Index f = 0; f <= 8; ++f) joined.push_back(intersection(f, kBody + (f < 4 ? 0 : 8)));
  Built f1 = build(scene, joined, 1);
  ASSERT_EQ(f1.regions.size(), 1u);
  tracks.add_frame(1, 1, f1.regions, ended);
  EXPECT_EQ(f1.regions[0].track, 0u);
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_EQ(ended[0].id, 1u);
  EXPECT_EQ(ended[0].merged_into, 0u);
  tracks.finish(ended);
  ASSERT_EQ(ended.size(), 2u);
  EXPECT_EQ(ended[1].id, 0u);
  EXPECT_EQ(ended[1].events, 2u + 9u);   // its own and the merged track's
  EXPECT_EQ(ended[1].regions, 3u);
  EXPECT_EQ(ended[1].frames, 2u);
}

TEST(Tracks, ARegionThatSplitsKeepsOneTrack) {
  const Scene scene = two_strips();
  TrackBuilder tracks(scene);
  std::vector<TrackRecord> ended;
  std::vector<Event> wide;
  for (Index f = 0; f < 16; ++f) wide.push_back(intersection(f, kBody + f));
  Built f0 = build(scene, wide, 0);
  ASSERT_EQ(f0.regions.size(), 1u);
  tracks.add_frame(0, 0, f0.regions, ended);
  Built f1 = build(scene, {intersection(0, kBody), intersection(15, kBody + 15)}, 1);
  ASSERT_EQ(f1.regions.size(), 2u);
  tracks.add_frame(1, 1, f1.regions, ended);
  EXPECT_EQ(f1.regions[0].track, 0u);
  EXPECT_EQ(f1.regions[1].track, 0u);
  EXPECT_TRUE(ended.empty());
}

}  // namespace
}  // namespace snag::report
