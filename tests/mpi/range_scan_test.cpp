// A scan split into ranges and joined again (what snag-scan does over MPI,
// without MPI): the ranges cover every step once, and the first range
// scanned straight into the report's sink with the others digested into
// their parts and joined gives the report one scan gives, byte for byte but
// for the times. The oracle is the single scan itself.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "libcd/core/error.hpp"
#include "libcd/pipeline/pair_thickness.hpp"
#include "report/report_sink.hpp"
#include "report/scan_part.hpp"
#include "tests/tools/run_process.hpp"
#include "tools/common/range_scan.hpp"
#include "tools/common/rule_options.hpp"
#include "tools/common/scan_stats.hpp"
#include "tools/common/stages_merge.hpp"

namespace snag::tools {
namespace {

const std::string kSample = std::string(SNAG_SOURCE_DIR) + "/samples/cloth_ball";

TEST(SplitSteps, CoversEveryStepOnceInNearlyEqualRanges) {
  for (std::size_t frames = 0; frames <= 30; ++frames) {
    for (std::size_t parts = 1; parts <= 6; ++parts) {
      const std::vector<StepRange> ranges = split_steps(frames, parts);
      ASSERT_EQ(ranges.size(), parts);
      std::size_t next_step = 0, used = 0, fewest = frames, most = 0;
      for (std::size_t r = 0; r < parts; ++r) {
        if (ranges[r].empty) continue;
        ++used;
        ASSERT_EQ(used, r + 1) << "empty ranges come last";
        EXPECT_EQ(ranges[r].first, next_step);
        next_step = ranges[r].last;
        fewest = std::min(fewest, ranges[r].last - ranges[r].first);
        most = std::max(most, ranges[r].last - ranges[r].first);
        // Every range but the last hands its last frame to the next one.
        EXPECT_EQ(ranges[r].overlap, r + 1 < parts && !ranges[r + 1].empty);
      }
      if (frames == 0) {
        EXPECT_EQ(used, 0u);
        continue;
      }
      EXPECT_EQ(next_step, frames - 1) << frames << " frames, " << parts << " parts";
      EXPECT_EQ(used, std::max<std::size_t>(1, std::min(parts, frames - 1)));
      if (frames > 1) EXPECT_LE(most - fewest, 1u);
    }
  }
}

// With a merge cost, the ranges still cover every step once, each used
// range has a step, and the steps follow the weights (1 - cost)^(used - 1 - r)
// within rounding where even the first range's share is two steps or more.
TEST(SplitSteps, MergeCostShrinksTheEarlierRangesGeometrically) {
  for (const double cost : {0.1, 0.2, 0.5, 0.9}) {
    for (std::size_t frames = 1; frames <= 200; frames += 7) {
      for (std::size_t parts = 1; parts <= 5; ++parts) {
        const std::vector<StepRange> ranges = split_steps(frames, parts, cost);
        const std::size_t steps = frames - 1, used = std::max<std::size_t>(1, std::min(parts, steps));
        double total = 0;
        for (std::size_t r = 0; r < used; ++r) total += std::pow(1 - cost, static_cast<double>(used - 1 - r));
        // The first range's ideal share; below two steps, the one-step minimum moves the boundaries.
        const double smallest = static_cast<double>(steps) * std::pow(1 - cost, static_cast<double>(used - 1)) / total;
        std::size_t next_step = 0;
        for (std::size_t r = 0; r < parts; ++r) {
          ASSERT_EQ(ranges[r].empty, r >= used) << frames << " frames, " << parts << " parts, range " << r;
          if (ranges[r].empty) continue;
          EXPECT_EQ(ranges[r].first, next_step);
          EXPECT_EQ(ranges[r].overlap, r + 1 < used);
          next_step = ranges[r].last;
          if (steps == 0) continue;
          const std::size_t length = ranges[r].last - ranges[r].first;
          EXPECT_GE(length, 1u);
          const double ideal = static_cast<double>(steps) * std::pow(1 - cost, static_cast<double>(used - 1 - r)) / total;
          if (smallest >= 2) EXPECT_LT(std::abs(static_cast<double>(length) - ideal), 2.0) << frames << " " << r;
        }
        EXPECT_EQ(next_step, steps);
      }
    }
  }
  // Cost 0 is the even split.
  for (std::size_t frames = 1; frames <= 30; ++frames) {
    for (std::size_t parts = 1; parts <= 6; ++parts) {
      const auto even = split_steps(frames, parts), costless = split_steps(frames, parts, 0.0);
      for (std::size_t r = 0; r < parts; ++r) EXPECT_EQ(even[r].last, costless[r].last);
    }
  }
}

// Copies a file into place in pieces of `piece` bytes on a thread of its
// own, as a part's writer for replay_part() in lock-step with the reader:
// the file is made once the reader has waited for it, and each next piece
// written once the reader has waited again, so that the reader meets the
// end of what is written at every piece's end (records cut anywhere).
// `stop_at`: the copy ends there, as a writer that stopped short.
class SlowCopy {
 public:
  SlowCopy(const std::string& from, const std::string& to, std::size_t piece = 4093,
           std::size_t stop_at = std::string::npos) {
    std::ifstream in(from, std::ios::binary);
    bytes_.assign(std::istreambuf_iterator<char>(in), {});
    bytes_.resize(std::min(bytes_.size(), stop_at));
    thread_ = std::thread([this, to, piece] {
      std::size_t seen = 0;
      // Until the reader waits again (or the copy is dropped); false when dropped.
      auto reader_waited = [&] {
        while (waits_ == seen && !dropped_) std::this_thread::sleep_for(std::chrono::microseconds(50));
        seen = waits_;
        return !dropped_;
      };
      if (!reader_waited()) return;
      std::ofstream out(to, std::ios::binary);
      for (std::size_t at = 0; at < bytes_.size(); at += piece) {
        if (at > 0 && !reader_waited()) return;
        out.write(bytes_.data() + at, static_cast<std::streamsize>(std::min(piece, bytes_.size() - at)));
        out.flush();
        ++pieces_;
      }
      out.close();
      finished_ = true;
    });
  }
  ~SlowCopy() {
    dropped_ = true;
    thread_.join();
  }
  SlowCopy(const SlowCopy&) = delete;
  SlowCopy& operator=(const SlowCopy&) = delete;

  report::PartWait wait() {
    return [this] {
      const bool finished = finished_;  // before the pause: what was written by then is there
      ++waits_;
      if (!finished) std::this_thread::sleep_for(std::chrono::microseconds(100));
      return finished;
    };
  }
  std::size_t waits() const { return waits_; }
  std::size_t pieces() const { return pieces_; }

 private:
  std::string bytes_;
  std::thread thread_;
  std::atomic<bool> finished_{false}, dropped_{false};
  std::atomic<std::size_t> waits_{0}, pieces_{0};
};

struct Scanned {
  std::string report;
  std::string stages_json;
};

// The sample's frames 20 to 26 under its manifest (an allow rule, fail
// rules), with a cap of events that falls inside a later range, and the
// cloth thinner than the run so that collisions are re-decided.
class SplitScan : public ::testing::Test {
 protected:
  void SetUp() override { open("20:26"); }

  void open(const std::string& frames) {
    CacheArguments cache;
    cache.frames = frames;
    RuleArguments rules;
    rules.manifest = kSample + "/scene.yaml";
    rules.object_thickness = {"cloth=0.0005"};
    setup_ = resolve_scan_setup(cache, rules, 0.001);
    source_ = io::open_cache(setup_.cache);
    rules_ = std::make_unique<report::RuleSet>(source_->scene(), setup_.rules, setup_.thickness);
    backend_ = make_cpu_backend();
    BackendSettings settings;
    settings.thickness = rules_->max_thickness();
    backend_->bind(source_->scene(), settings);
    header_.settings.max_events = 1500;
    header_.rules = rules_->rules();
    const Scene& scene = source_->scene();
    std::vector<double> thickness;
    for (std::size_t o = 0; o < scene.objects().size(); ++o) thickness.push_back(rules_->object_thickness(o));
    ASSERT_TRUE(rules_->thickness_varies());
    redecide_ = [this, &scene, thickness, settings](const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                                   std::vector<Event>& events) {
      redecided_ += redecide_at_pair_thickness(scene, x_t0, x_t1, thickness, settings.thickness, settings.ccd,
                                               nullptr, events).redecided;
    };
  }

  Scanned scan_whole() {
    std::ostringstream out;
    report::ReportWriter writer(out);
    report::ReportSink sink(source_->scene(), header_, *rules_, &writer, redecide_);
    const ScanTotals totals = scan_cache(*source_, *backend_, ScanSettings{}, sink);
    sink.finish(stages_json(totals), "{}");
    return {out.str(), stages_json(totals)};
  }

  // Each part is written whole, then replayed: by replay_part() alone, or,
  // with `following`, while a thread copies it into place a few bytes at a
  // time (records cut anywhere), as a rank writes it while rank 0 reads.
  Scanned scan_split(std::size_t parts, const std::string& dir, bool following = false, double merge_cost = 0) {
    const std::vector<StepRange> ranges = split_steps(source_->frame_count(), parts, merge_cost);
    std::ostringstream out;
    report::ReportWriter writer(out);
    report::ReportSink sink(source_->scene(), header_, *rules_, &writer, redecide_);
    // Scanned in reverse, as ranks finish in any order.
    std::vector<std::string> stages;
    for (std::size_t r = parts; r-- > 1;) {
      report::PartWriter part(dir + "/part-" + std::to_string(r), source_->scene(), *rules_, header_.settings,
                              redecide_);
      const ScanTotals totals = scan_range(*source_, ranges[r], *backend_, ScanSettings{}, part);
      part.finish({totals.frames, stages_json(totals), "{}"});
    }
    const ScanTotals first = scan_range(*source_, ranges[0], *backend_, ScanSettings{}, sink);
    stages.push_back(stages_json(first));
    for (std::size_t r = 1; r < parts; ++r) {
      const std::string whole_part = dir + "/part-" + std::to_string(r);
      std::string part_stages;
      if (following) {
        SlowCopy copy(whole_part, whole_part + "-following");
        part_stages = report::replay_part(whole_part + "-following", *source_, sink, {}, copy.wait()).stages_json;
        // Each piece was written after the reader met the end of the one before.
        EXPECT_GT(copy.pieces(), 10u);
        EXPECT_GE(copy.waits(), copy.pieces());
      } else {
        part_stages = report::replay_part(whole_part, *source_, sink).stages_json;
      }
      // As snag-scan does: a range with nothing to scan says nothing of the stages.
      if (!ranges[r].empty) stages.push_back(part_stages);
    }
    const std::string merged = merge_stages_json(stages);
    sink.finish(merged, "{}");
    return {out.str(), merged};
  }

  void expect_split_gives_whole(std::size_t parts, bool following = false, double merge_cost = 0) {
    const Scanned whole = scan_whole();
    const test::TemporaryDirectory temporary;
    const Scanned split = scan_split(parts, temporary.path(), following, merge_cost);
    EXPECT_EQ(split.stages_json, whole.stages_json);
    EXPECT_EQ(split.report, whole.report);
  }

  // The second of two ranges, written whole into a part at `path`.
  void write_second_half(const std::string& path) {
    report::PartWriter part(path, source_->scene(), *rules_, header_.settings, redecide_);
    const ScanTotals totals =
        scan_range(*source_, split_steps(source_->frame_count(), 2)[1], *backend_, ScanSettings{}, part);
    part.finish({totals.frames, stages_json(totals), "{}"});
  }

  ScanSetup setup_;
  std::unique_ptr<FrameSource> source_;
  std::unique_ptr<report::RuleSet> rules_;
  std::unique_ptr<Backend> backend_;
  report::Header header_;
  report::Redecide redecide_;
  std::size_t redecided_ = 0;
};


TEST_F(SplitScan, ThreeRangesGiveTheSingleScanReport) {
  const Scanned whole = scan_whole();
  const test::TemporaryDirectory temporary;
  const std::string dir = temporary.path();
  const Scanned split = scan_split(3, dir);
  EXPECT_GT(redecided_, 0u);
  // The report's own check that the cap was crossed and that tracks crossed the ranges' boundaries.
  const auto trailer = nlohmann::json::parse(whole.report.substr(whole.report.rfind("{\"record\":\"trailer\"")));
  ASSERT_GT(trailer["summary"]["left_out"].get<std::size_t>(), 0u);
  const std::vector<StepRange> ranges = split_steps(source_->frame_count(), 3);
  bool crossing = false;
  std::istringstream lines(whole.report);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("{\"record\":\"track\"", 0) != 0) continue;
    const auto track = nlohmann::json::parse(line);
    const std::size_t first = track["first_frame"], last = track["last_frame"];
    for (std::size_t r = 1; r < ranges.size(); ++r) {
      const std::size_t boundary = source_->frame_index(ranges[r].first);
      crossing = crossing || (first < boundary && last >= boundary);
    }
  }
  ASSERT_TRUE(crossing) << "no track crosses a range boundary: the test checks nothing there";
  // The cap is reached in a later range than the first: the ranks' parts
  // hold the events that the join lists after rank 0's.
  std::size_t last_listed_frame = 0;
  std::istringstream events(whole.report);
  for (std::string line; std::getline(events, line);) {
    if (line.rfind("{\"record\":\"event\"", 0) == 0) last_listed_frame = nlohmann::json::parse(line)["frame"];
  }
  ASSERT_GE(last_listed_frame, source_->frame_index(ranges[1].first)) << "the cap falls in the first range";
  EXPECT_EQ(split.stages_json, whole.stages_json);
  EXPECT_EQ(split.report, whole.report);
}

// The parts read while they are written, over uneven ranges (rank 0's
// smaller first range), give the same report.
TEST_F(SplitScan, PartsFollowedWhileWrittenGiveTheSingleScanReport) { expect_split_gives_whole(3, true, 0.3); }

// What the report lists decides what the parts hold (every event, up to the
// cap, none): each way, the joined report is the single scan's. A cap of 10
// is reached in the first range, 0 is no cap.
TEST_F(SplitScan, EveryListingGivesTheSingleScanReport) {
  const std::pair<std::string, std::size_t> listings[] = {{"all", 0}, {"all", 10}, {"regions", 0}, {"none", 0}};
  for (const auto& [events, cap] : listings) {
    header_.settings.events = events;
    header_.settings.max_events = cap;
    SCOPED_TRACE(events + " " + std::to_string(cap));
    expect_split_gives_whole(3, false, 0.3);
  }
}

// The join lists events from the digests; a digest (a part) that holds fewer
// than the report lists is a broken run, never a shorter report.
TEST_F(SplitScan, JoinRefusesADigestWithoutTheEventsItLists) {
  report::ReportSink sink(source_->scene(), header_, *rules_, nullptr);
  report::FrameDigest digest;
  digest.record.collisions = 2;
  digest.kept = 2;
  digest.listable = 1;
  const Event event{};
  digest.events = &event;
  digest.allowed_by.assign(1, report::kNone);
  digest.region_of.assign(1, report::kNone);
  digest.allow_counts.assign(rules_->rules().allow.size(), 0);
  EXPECT_THROW(sink.join(digest), std::logic_error);
}

// A writer that finishes short, or never writes its part: the reader says so
// instead of waiting for ever.
TEST_F(SplitScan, PartFollowedToAnEarlyEndIsTruncated) {
  open("20:24");
  const test::TemporaryDirectory temporary;
  const std::string dir = temporary.path();
  const std::string path = dir + "/part-1";
  write_second_half(path);
  report::ReportSink sink(source_->scene(), header_, *rules_, nullptr);
  const std::size_t size = std::filesystem::file_size(path);
  {
    SlowCopy copy(path, path + "-short", 997, size / 2);
    try {
      report::replay_part(path + "-short", *source_, sink, {}, copy.wait());
      FAIL() << "a part that ended short was replayed";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(path + "-short"), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find("truncated"), std::string::npos) << error.what();
    }
    EXPECT_GT(copy.pieces(), 10u);
    EXPECT_GT(copy.waits(), copy.pieces()) << "the reader did not wait at the short end";
  }
  std::size_t waits = 0;
  try {
    report::replay_part(dir + "/never", *source_, sink, {}, [&] { return ++waits >= 3; });
    FAIL() << "a part that was never written was replayed";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(dir + "/never: cannot open the part"), std::string::npos)
        << error.what();
  }
  EXPECT_EQ(waits, 3u);
}

TEST_F(SplitScan, MoreRangesThanStepsGiveTheSingleScanReport) {
  open("20:22");
  expect_split_gives_whole(4);
}

TEST_F(SplitScan, TruncatedPartIsRejectedWithItsName) {
  open("20:24");
  const test::TemporaryDirectory temporary;
  const std::string dir = temporary.path();
  const std::string path = dir + "/part-1";
  write_second_half(path);
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes.substr(0, bytes.size() / 2);
  std::ostringstream out;
  report::ReportSink sink(source_->scene(), header_, *rules_, nullptr);
  try {
    report::replay_part(path, *source_, sink);
    FAIL() << "a truncated part was replayed";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("truncated"), std::string::npos) << error.what();
  }
}

TEST(MergeStages, AddsCountersKeepsTheLastGridAndTheLargestPeak) {
  const std::string a =
      R"({"ccd_broad_phase":{"cell_size":0.5,"grid":[1,2,3],"tests":10,"peak_memory_bytes":100,)"
      R"("subdivision_levels":1,"subdivided_per_level":[4,1]},"narrow_phase":{"vf_tests":3,"ee_tests":1,)"
      R"("exact_queries":1,"exact_fraction":0.25}})";
  const std::string b =
      R"({"ccd_broad_phase":{"cell_size":0.25,"grid":[4,5,6],"tests":5,"peak_memory_bytes":50,)"
      R"("subdivision_levels":2,"subdivided_per_level":[1,1,7]},"narrow_phase":{"vf_tests":2,"ee_tests":2,)"
      R"("exact_queries":2,"exact_fraction":0.5}})";
  const auto merged = nlohmann::json::parse(merge_stages_json({a, b}));
  const auto& broad = merged["ccd_broad_phase"];
  EXPECT_EQ(broad["cell_size"], 0.25);
  EXPECT_EQ(broad["grid"], nlohmann::json({4, 5, 6}));
  EXPECT_EQ(broad["tests"], 15);
  EXPECT_EQ(broad["peak_memory_bytes"], 100);
  EXPECT_EQ(broad["subdivision_levels"], 2);
  EXPECT_EQ(broad["subdivided_per_level"], nlohmann::json({5, 2, 7}));
  EXPECT_EQ(merged["narrow_phase"]["exact_fraction"], 3.0 / 8.0);
  EXPECT_EQ(merge_stages_json({a}), nlohmann::json::parse(a).dump());
  const auto timing = nlohmann::json::parse(merge_timing_json({R"({"read":1.5,"total":9})", R"({"read":2,"total":9})"}, 4));
  EXPECT_EQ(timing["read"], 3.5);
  EXPECT_EQ(timing["total"], 4.0);
}

}  // namespace
}  // namespace snag::tools
