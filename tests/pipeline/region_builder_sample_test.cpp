// RegionBuilder on the bundled cloth_ball sample: every frame's events from
// the CPU back end grouped into regions with one thread and with eight, and
// compared field for field with the plain reference builder.
#include <gtest/gtest.h>

#include <vector>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include "libcd/pipeline/scan.hpp"
#include "report/regions.hpp"
#include "tests/pipeline/sample_cache.hpp"
#include "tests/report/reference_regions.hpp"

namespace snag {
namespace {

TEST(RegionBuilderSample, EveryFrameMatchesThePlainBuilderForAnyThreadCount) {
  const auto source = test::open_sample_cache();
  const Scene& scene = source->scene();
  auto backend = make_cpu_backend();
  backend->bind(scene, BackendSettings{});
  const ScanResult scan = scan_cache(*source, *backend, ScanSettings{});
  std::size_t regions_seen = 0, largest = 0;
  std::size_t next = 0;
  for (std::size_t position = 0; position < source->frame_count(); ++position) {
    std::vector<Event> events;
    while (next < scan.events.size() && scan.events[next].frame == source->frame_index(position))
      events.push_back(scan.events[next++]);
    const std::vector<Vec3> x = test::read_positions(*source, position);
    const std::vector<char> all(events.size(), 1);
    std::vector<report::RegionRecord> reference;
    std::vector<std::size_t> reference_of;
    test::reference_regions(scene, events, all, x, position, reference, reference_of);
    for (int threads : {1, 8}) {
      SCOPED_TRACE(testing::Message() << "frame " << position << ", " << threads << " threads");
      tbb::global_control most(tbb::global_control::max_allowed_parallelism, threads);
      tbb::task_arena arena(threads);
      std::vector<report::RegionRecord> built;
      std::vector<std::size_t> built_of;
      report::RegionBuilder builder(scene);
      arena.execute([&] { builder.build(events, all, x, position, built, built_of); });
      ASSERT_EQ(built.size(), reference.size());
      for (std::size_t r = 0; r < built.size(); ++r)
        ASSERT_EQ(test::region_difference(built[r], reference[r]), "") << "region " << r;
      EXPECT_EQ(built_of, reference_of);
    }
    regions_seen += reference.size();
    for (const auto& r : reference) largest = std::max(largest, r.events);
  }
  EXPECT_EQ(next, scan.events.size());
  // The sample has contact: regions, some of many events, were compared.
  EXPECT_GT(regions_seen, 10u);
  EXPECT_GT(largest, 100u);
}

}  // namespace
}  // namespace snag
