// RegionBuilder against the plain reference (reference_regions.hpp) on random
// events of every kind over three meshes, with one thread and with eight:
// the same regions, field for field, and the same region of every event.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include "report/regions.hpp"
#include "tests/report/reference_regions.hpp"

namespace snag::report {
namespace {

// An n x n grid of quads, two triangles each, over (n + 1)^2 vertices.
Object grid(const std::string& name, Index n) {
  std::vector<Triangle> triangles;
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j) {
      const Index v = i * (n + 1) + j;
      triangles.push_back({v, v + 1, v + n + 1});
      triangles.push_back({v + 1, v + n + 2, v + n + 1});
    }
  return make_object(name, (n + 1) * (n + 1), triangles);
}

// Random events, many of them in a few crowded patches (large regions that
// the threads share) and the rest anywhere (many small ones).
std::vector<Event> random_events(const Scene& scene, std::size_t count, std::mt19937& random) {
  const Index faces = static_cast<Index>(scene.triangle_count()), vertices = static_cast<Index>(scene.vertex_count());
  const Index edges = static_cast<Index>(scene.edges().size());
  std::uniform_real_distribution<double> unit(0, 1);
  auto pick = [&](Index n, bool crowded) {
    const Index patch = n / 16;
    return crowded ? static_cast<Index>(random() % (patch + 1)) + n / 3 : static_cast<Index>(random() % n);
  };
  std::vector<Event> events(count);
  for (Event& e : events) {
    const bool crowded = unit(random) < 0.5;
    const double kind = unit(random);
    if (kind < 0.3) {
      e.kind = EventKind::kIntersection;
      e.type = ContactType::kTriangleTriangle;
      e.a = pick(faces, crowded);
      e.b = pick(faces, false);
    } else if (kind < 0.65) {
      e.type = ContactType::kVertexFace;
      e.a = pick(vertices, crowded);
      e.b = pick(faces, false);
    } else {
      e.type = ContactType::kEdgeEdge;
      e.a = pick(edges, crowded);
      e.b = pick(edges, crowded);
    }
    e.frame = 3;
    e.toi_lo = unit(random);
    e.position = {unit(random), unit(random), unit(random)};
  }
  return events;
}

struct Regions {
  std::vector<RegionRecord> records;
  std::vector<std::size_t> region_of;
};

Regions build_with_threads(const Scene& scene, const std::vector<Event>& events, const std::vector<char>& in_region,
                           const std::vector<Vec3>& x, int threads) {
  tbb::global_control most(tbb::global_control::max_allowed_parallelism, threads);
  tbb::task_arena arena(threads);
  Regions out;
  RegionBuilder builder(scene);
  arena.execute([&] { builder.build(events, in_region, x, 3, out.records, out.region_of); });
  return out;
}

void expect_same(const Regions& built, const Regions& reference) {
  ASSERT_EQ(built.records.size(), reference.records.size());
  for (std::size_t r = 0; r < built.records.size(); ++r)
    ASSERT_EQ(test::region_difference(built.records[r], reference.records[r]), "") << "region " << r;
  EXPECT_EQ(built.region_of, reference.region_of);
}

TEST(RegionBuilder, MatchesThePlainBuilderOnRandomEventsForAnyThreadCount) {
  const Scene scene({grid("cloth", 24), grid("body", 12), grid("sleeve", 6)});
  std::vector<Vec3> x(scene.vertex_count());
  std::mt19937 random(14);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (Vec3& p : x) p = {unit(random), unit(random), unit(random)};
  for (std::size_t count : {1u, 40u, 900u, 6000u, 50000u}) {
    const std::vector<Event> events = random_events(scene, count, random);
    std::vector<char> in_region(events.size());
    for (char& in : in_region) in = random() % 8 != 0;  // some allowed ones left out
    Regions reference;
    test::reference_regions(scene, events, in_region, x, 3, reference.records, reference.region_of);
    for (int threads : {1, 8}) {
      SCOPED_TRACE(testing::Message() << count << " events, " << threads << " threads");
      expect_same(build_with_threads(scene, events, in_region, x, threads), reference);
    }
  }
}

TEST(RegionBuilder, AppendsAfterRegionsAlreadyThereAndIsReusable) {
  const Scene scene({grid("cloth", 10), grid("body", 10)});
  const std::vector<Vec3> x(scene.vertex_count(), Vec3{0, 0, 0});
  std::mt19937 random(7);
  RegionBuilder builder(scene);
  Regions built, reference;
  for (int frame = 0; frame < 3; ++frame) {  // the builder's stamps carry over from frame to frame
    const std::vector<Event> events = random_events(scene, 300, random);
    const std::vector<char> all(events.size(), 1);
    builder.build(events, all, x, 3, built.records, built.region_of);
    test::reference_regions(scene, events, all, x, 3, reference.records, reference.region_of);
    expect_same(built, reference);
  }
}

}  // namespace
}  // namespace snag::report
