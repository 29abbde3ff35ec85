// snag-scan end to end on the cloth_ball sample: the report's keys, the
// deterministic order of its events, identical results across runs, thread
// counts and input formats, the modes, the exit codes, and events whose ids
// lie in range for their objects.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "tests/tools/report_json.hpp"
#include "tests/tools/run_process.hpp"
#include "tests/tools/sample_paths.hpp"

namespace snag::test {
namespace {

using nlohmann::json;

ProcessResult snag_scan(const std::vector<std::string>& arguments) { return run_process(SNAG_SCAN_EXE, arguments); }

struct ScanRun {
  ProcessResult process;
  json report;
};

/// Runs snag-scan with `arguments` plus "-q -r FILE" and parses the report.
/// Runs are remembered: tests that need the same run share it.
const ScanRun& scan(const std::vector<std::string>& arguments) {
  static std::map<std::vector<std::string>, ScanRun> runs;
  auto found = runs.find(arguments);
  if (found != runs.end()) return found->second;
  TemporaryDirectory dir;
  std::vector<std::string> full = arguments;
  full.insert(full.end(), {"-q", "-r", dir.path("report.json")});
  ScanRun run;
  run.process = snag_scan(full);
  EXPECT_TRUE(run.process.exit_code == 0 || run.process.exit_code == 1) << run.process.err;
  if (run.process.exit_code == 0 || run.process.exit_code == 1) run.report = load_report(dir.path("report.json"));
  return runs.emplace(arguments, std::move(run)).first->second;
}

std::vector<std::string> with(std::vector<std::string> inputs, const std::vector<std::string>& options) {
  inputs.insert(inputs.end(), options.begin(), options.end());
  return inputs;
}

/// The sample as point caches, whole cache, two threads, certified: the run most tests read.
const ScanRun& full_scan() { return scan(with(sample_pc2_inputs(), {"--threads", "2"})); }

/// Frames 24 to 26: the ball inside the folded cloth, hundreds of events of
/// both kinds; the comparisons between runs use this window to stay quick.
const std::vector<std::string> kWindow{"--frames", "24:26"};
const ScanRun& window_scan() { return scan(with(sample_pc2_inputs(), with({"--threads", "2"}, kWindow))); }

/// An object's position in the report's object list, and its counts.
struct ObjectInfo {
  std::size_t index = 0;
  std::size_t vertices = 0, triangles = 0;
};

std::map<std::string, ObjectInfo> objects_of(const json& report) {
  std::map<std::string, ObjectInfo> objects;
  for (std::size_t i = 0; i < report.at("objects").size(); ++i) {
    const json& o = report["objects"][i];
    objects[o.at("name").get<std::string>()] = {i, o.at("vertices").get<std::size_t>(),
                                                o.at("triangles").get<std::size_t>()};
  }
  return objects;
}

/// The key of one element reference in the global order of libcd: object
/// first (objects are concatenated), then the local id; an edge by its sorted
/// vertex pair (each object's edges are sorted by (lo, hi)).
std::vector<std::size_t> element_key(const json& ref, const std::map<std::string, ObjectInfo>& objects) {
  std::vector<std::size_t> key{objects.at(ref.at("object").get<std::string>()).index};
  if (ref.contains("vertex")) key.push_back(ref["vertex"].get<std::size_t>());
  if (ref.contains("face")) key.push_back(ref["face"].get<std::size_t>());
  if (ref.contains("edge")) {
    key.push_back(ref["edge"][0].get<std::size_t>());
    key.push_back(ref["edge"][1].get<std::size_t>());
  }
  return key;
}

/// The documented order key of an event: frame, kind, type, a, b.
using EventKey = std::tuple<std::size_t, int, int, std::vector<std::size_t>, std::vector<std::size_t>>;

EventKey event_key(const json& event, const std::map<std::string, ObjectInfo>& objects) {
  const std::string kind = event.at("kind");
  const int kind_rank = kind == "collision" ? 0 : 1;
  int type_rank = 2;  // intersections: triangle pairs
  if (kind == "collision") type_rank = event.at("type") == "vf" ? 0 : 1;
  return {event.at("frame").get<std::size_t>(), kind_rank, type_rank, element_key(event.at("a"), objects),
          element_key(event.at("b"), objects)};
}

std::size_t count_kind(const json& events, const std::string& kind) {
  std::size_t n = 0;
  for (const json& e : events) n += e.at("kind") == kind;
  return n;
}

/// The events of one kind, without their region ids (which number the
/// regions of both kinds together).
json events_of_kind(const json& events, const std::string& kind) {
  json selected = json::array();
  for (json e : events) {
    e.erase("region");
    if (e.at("kind") == kind) selected.push_back(e);
  }
  return selected;
}

TEST(SnagScan, ReportHasTheDocumentedTopLevelKeys) {
  const json& report = window_scan().report;
  for (const char* key : {"format", "version", "tool", "source", "objects", "frame_count", "settings", "rules"}) {
    EXPECT_TRUE(report["header"].contains(key)) << key;
  }
  for (const char* key : {"frames", "summary", "pairs", "allow", "largest_tracks", "verdict", "stages", "timing"}) {
    EXPECT_TRUE(report["trailer"].contains(key)) << key;
  }
  EXPECT_EQ(report["header"]["format"], "snag-report");
  // What the user waited for before the scan, and the scan, within the run's wall time.
  const json& timing = report["trailer"]["timing"];
  ASSERT_TRUE(timing.contains("start") && timing["start"].is_number());
  EXPECT_GT(timing["start"].get<double>(), 0.0);
  EXPECT_LT(timing["start"].get<double>() + timing["total"].get<double>(), window_scan().process.seconds);
  EXPECT_EQ(report["version"], 2);
  EXPECT_EQ(report["header"]["frame_count"], 3u);
  EXPECT_EQ(report["frames"].size(), 3u);
  EXPECT_EQ(report["objects"].size(), 2u);
  EXPECT_EQ(report["settings"]["mode"], "all");
  EXPECT_EQ(report["settings"]["precision"], "certified");
  EXPECT_EQ(report["certified"], true);
}

TEST(SnagScan, SampleHasCollisionsAndIntersectionsAndExitsOne) {
  const ScanRun& run = window_scan();
  EXPECT_EQ(run.process.exit_code, 1);
  EXPECT_GT(count_kind(run.report["events"], "collision"), 0u);
  EXPECT_GT(count_kind(run.report["events"], "intersection"), 0u);
}

void expect_summary_counts_match_events(const json& report) {
  const json& events = report["events"];
  const json& summary = report["summary"];
  std::size_t vf = 0, ee = 0, uncertain = 0;
  for (const json& e : events) {
    if (e["kind"] != "collision") continue;
    vf += e["type"] == "vf";
    ee += e["type"] == "ee";
    uncertain += e["certainty"] == "uncertain";
  }
  EXPECT_EQ(summary["events"], events.size());
  EXPECT_EQ(summary["collisions"], count_kind(events, "collision"));
  EXPECT_EQ(summary["intersections"], count_kind(events, "intersection"));
  EXPECT_EQ(summary["vf"], vf);
  EXPECT_EQ(summary["ee"], ee);
  EXPECT_EQ(summary["uncertain"], 0u);  // certified: nothing left undecided
  EXPECT_EQ(uncertain, 0u);
  // The frame records add up to the totals, frame by frame.
  std::map<std::size_t, std::size_t> collisions_per_frame, intersections_per_frame;
  for (const json& e : events) {
    (e["kind"] == "collision" ? collisions_per_frame : intersections_per_frame)[e["frame"].get<std::size_t>()]++;
  }
  for (const json& f : report["frames"]) {
    const std::size_t frame = f["index"];
    EXPECT_EQ(f["collisions"], collisions_per_frame[frame]) << "frame " << frame;
    EXPECT_EQ(f["intersections"], intersections_per_frame[frame]) << "frame " << frame;
  }
}

void expect_events_sorted_without_duplicates(const json& report) {
  const auto objects = objects_of(report);
  const json& events = report["events"];
  for (std::size_t i = 1; i < events.size(); ++i) {
    ASSERT_LT(event_key(events[i - 1], objects), event_key(events[i], objects))
        << "events " << i - 1 << " and " << i << ":\n" << events[i - 1].dump() << "\n" << events[i].dump();
  }
}

void expect_collisions_well_formed(const json& report) {
  const double last_frame = report.at("frames").back().at("index").get<double>();
  const auto objects = objects_of(report);
  std::size_t checked = 0;
  for (const json& e : report["events"]) {
    if (e["kind"] != "collision") continue;
    SCOPED_TRACE(e.dump());
    const double frame = e["frame"].get<double>();
    ASSERT_TRUE(e["type"] == "vf" || e["type"] == "ee");
    const double toi = e["toi"];
    EXPECT_GE(toi, frame);
    EXPECT_LE(toi, frame + 1);
    EXPECT_LE(e["toi_interval"][0].get<double>(), toi);
    EXPECT_GE(e["toi_interval"][1].get<double>(), toi);
    EXPECT_LE(e["toi_interval"][1].get<double>(), frame + 1);
    EXPECT_EQ(e["certainty"], "proven");
    EXPECT_LT(frame, last_frame);  // collisions are steps f -> f + 1 within the frames scanned
    const ObjectInfo& a = objects.at(e["a"]["object"].get<std::string>());
    const ObjectInfo& b = objects.at(e["b"]["object"].get<std::string>());
    if (e["type"] == "vf") {
      EXPECT_LT(e["a"].at("vertex").get<std::size_t>(), a.vertices);
      EXPECT_LT(e["b"].at("face").get<std::size_t>(), b.triangles);
    } else {
      for (const auto& [ref, object] : {std::pair{e["a"], a}, std::pair{e["b"], b}}) {
        const std::size_t lo = ref.at("edge")[0], hi = ref.at("edge")[1];
        EXPECT_LT(lo, hi);
        EXPECT_LT(hi, object.vertices);
      }
      // EE pairs share no vertex.
      if (e["a"]["object"] == e["b"]["object"]) {
        const std::set<std::size_t> ends{e["a"]["edge"][0], e["a"]["edge"][1], e["b"]["edge"][0], e["b"]["edge"][1]};
        EXPECT_EQ(ends.size(), 4u);
      }
    }
    EXPECT_EQ(e["position"].size(), 3u);
    ++checked;
  }
  EXPECT_GT(checked, 0u);
}

void expect_intersections_well_formed(const json& report) {
  const auto objects = objects_of(report);
  for (const json& e : report["events"]) {
    if (e["kind"] != "intersection") continue;
    SCOPED_TRACE(e.dump());
    EXPECT_LE(e["frame"].get<std::size_t>(), report.at("frames").back().at("index").get<std::size_t>());
    EXPECT_LT(e["a"].at("face").get<std::size_t>(), objects.at(e["a"]["object"].get<std::string>()).triangles);
    EXPECT_LT(e["b"].at("face").get<std::size_t>(), objects.at(e["b"]["object"].get<std::string>()).triangles);
    EXPECT_FALSE(e.contains("toi"));
  }
}

TEST(SnagScan, SummaryCountsMatchTheEvents) { expect_summary_counts_match_events(window_scan().report); }

TEST(SnagScan, EventsAreSortedByFrameKindTypeAndIdsWithoutDuplicates) {
  expect_events_sorted_without_duplicates(window_scan().report);
}

TEST(SnagScan, CollisionsHaveTypeTimeOfImpactAndIdsInRange) { expect_collisions_well_formed(window_scan().report); }

TEST(SnagScan, IntersectionsNameTwoFacesInRange) { expect_intersections_well_formed(window_scan().report); }

TEST(SnagScan, FrameSelectionKeepsTheCacheFrameNumbers) {
  const json& report = window_scan().report;
  ASSERT_EQ(report.at("frames").size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(report["frames"][i].at("index").get<std::size_t>(), 24 + i);
  ASSERT_FALSE(report.at("events").empty());
  for (const json& e : report["events"]) {
    EXPECT_GE(e.at("frame").get<std::size_t>(), 24u);
    EXPECT_LE(e.at("frame").get<std::size_t>(), 26u);
  }
}

TEST(SnagScan, TwoRunsGiveIdenticalEventsAndSummary) {
  const json& first = window_scan().report;
  ASSERT_GT(first["events"].size(), 100u);
  // The same scan again: a new process, not the remembered run.
  TemporaryDirectory dir;
  const ProcessResult again = snag_scan(
      with(sample_pc2_inputs(), with({"--threads", "2", "-q", "-r", dir.path("again.json")}, kWindow)));
  ASSERT_EQ(again.exit_code, 1) << again.err;
  const json second = load_report(dir.path("again.json"));
  EXPECT_TRUE(first["events"] == second["events"]);
  EXPECT_TRUE(first["summary"] == second["summary"]);
  EXPECT_TRUE(first["regions"] == second["regions"]);
  EXPECT_TRUE(first["tracks"] == second["tracks"]);
  EXPECT_TRUE(first["trailer"]["stages"] == second["trailer"]["stages"]);
}

TEST(SnagScan, OneThreadAndTwoThreadsGiveIdenticalEvents) {
  const json& two = window_scan().report;
  const json& one = scan(with(sample_pc2_inputs(), with({"--threads", "1"}, kWindow))).report;
  EXPECT_EQ(one["settings"]["threads"], 1);
  EXPECT_TRUE(one["events"] == two["events"]);
  EXPECT_TRUE(one["regions"] == two["regions"]);
  EXPECT_TRUE(one["tracks"] == two["tracks"]);
  EXPECT_TRUE(one["summary"] == two["summary"]);
}

TEST(SnagScan, AdaptiveGridGivesTheUniformGridsEventsAndSaysWhatItSplit) {
  const json& uniform = window_scan().report;
  const json& adaptive =
      scan(with(sample_pc2_inputs(), with({"--threads", "2", "--grid", "adaptive", "--backend", "cpu"}, kWindow))).report;
  EXPECT_TRUE(adaptive["events"] == uniform["events"]);
  EXPECT_TRUE(adaptive["regions"] == uniform["regions"]);
  EXPECT_TRUE(adaptive["summary"] == uniform["summary"]);
  EXPECT_EQ(adaptive["settings"]["grid"], "adaptive");
  EXPECT_EQ(uniform["settings"]["grid"], "uniform");
  for (const char* stage : {"ccd_broad_phase", "static_broad_phase"}) {
    const json& split = adaptive["trailer"]["stages"][stage];
    const json& plain = uniform["trailer"]["stages"][stage];
    EXPECT_GT(split["cells_subdivided"].get<std::size_t>(), 0u) << stage;  // the folded cloth crowds cells
    EXPECT_GE(split["deepest_level"].get<int>(), 1) << stage;
    EXPECT_EQ(plain["cells_subdivided"], 0) << stage;
    EXPECT_EQ(plain["deepest_level"], 0) << stage;
  }
}

TEST(SnagScan, PointCachesAndObjSequenceGiveIdenticalEvents) {
  const json& pc2 = window_scan().report;
  const json& obj = scan(with({kObjPattern, "--threads", "2"}, kWindow)).report;
  EXPECT_TRUE(pc2["objects"] == obj["objects"]) << pc2["objects"].dump() << "\n" << obj["objects"].dump();
  EXPECT_TRUE(pc2["events"] == obj["events"]);
  EXPECT_TRUE(pc2["summary"] == obj["summary"]);
}

TEST(SnagScan, CcdModeReportsOnlyTheCollisionsOfTheSameFrames) {
  const json& all = window_scan().report;
  const ScanRun& ccd = scan(with(sample_pc2_inputs(), with({"--threads", "2", "--mode", "ccd"}, kWindow)));
  EXPECT_EQ(ccd.report["settings"]["mode"], "ccd");
  EXPECT_EQ(count_kind(ccd.report["events"], "intersection"), 0u);
  EXPECT_TRUE(events_of_kind(ccd.report["events"], "collision") == events_of_kind(all["events"], "collision"));
  EXPECT_EQ(ccd.report["summary"]["intersections"], 0);
}

TEST(SnagScan, DcdModeReportsOnlyTheIntersectionsOfTheSameFrames) {
  const json& all = window_scan().report;
  const ScanRun& dcd = scan(with(sample_pc2_inputs(), with({"--threads", "2", "--mode", "dcd"}, kWindow)));
  EXPECT_EQ(dcd.report["settings"]["mode"], "dcd");
  EXPECT_EQ(count_kind(dcd.report["events"], "collision"), 0u);
  EXPECT_TRUE(events_of_kind(dcd.report["events"], "intersection") ==
              events_of_kind(all["events"], "intersection"));
  EXPECT_EQ(dcd.report["summary"]["collisions"], 0);
}

TEST(SnagScan, WholeSampleReportIsWellFormedWithIntersectionsFromFrame15On) {
  const ScanRun& run = full_scan();
  EXPECT_EQ(run.process.exit_code, 1);
  const json& report = run.report;
  EXPECT_EQ(report["frames"].size(), 40u);
  expect_summary_counts_match_events(report);
  expect_events_sorted_without_duplicates(report);
  expect_collisions_well_formed(report);
  expect_intersections_well_formed(report);
  // samples/README.md: Blender frames 1-15 (0-based 0-14) hold no
  // intersecting pair; 16-40 all do (14 to 562 pairs by a float test).
  std::set<std::size_t> frames;
  for (const json& e : report["events"]) {
    if (e["kind"] == "intersection") frames.insert(e["frame"].get<std::size_t>());
  }
  ASSERT_FALSE(frames.empty());
  EXPECT_GE(*frames.begin(), 14u);  // a near-touching pair may appear a frame early in exact arithmetic
  for (std::size_t f = 16; f < 40; ++f) EXPECT_TRUE(frames.count(f)) << "frame " << f;
}

TEST(SnagScan, FailOnZeroExitsCleanEvenWithEvents) {
  const ScanRun& run = scan(with(sample_pc2_inputs(), {"--frames", "20:22", "--fail-on", "0"}));
  EXPECT_EQ(run.process.exit_code, 0) << run.process.err;
  EXPECT_GT(run.report["events"].size(), 0u);
}

TEST(SnagScan, FailOnThresholdComparesWithTheEventCount) {
  const ScanRun& run = scan(with(sample_pc2_inputs(), {"--frames", "20:22"}));
  EXPECT_EQ(run.process.exit_code, 1);  // default --fail-on 1, events exist
  const std::size_t events = run.report["events"].size();
  ASSERT_GT(events, 0u);
  EXPECT_EQ(scan(with(sample_pc2_inputs(), {"--frames", "20:22", "--fail-on", std::to_string(events)}))
                .process.exit_code,
            1);
  EXPECT_EQ(scan(with(sample_pc2_inputs(), {"--frames", "20:22", "--fail-on", std::to_string(events + 1)}))
                .process.exit_code,
            0);
}

TEST(SnagScan, CleanFramesExitZero) {
  // The first frames: the cloth falls freely, far from the ball and itself.
  const ScanRun& run = scan(with(sample_pc2_inputs(), {"--frames", "0:3"}));
  EXPECT_EQ(run.process.exit_code, 0) << run.process.err;
  EXPECT_EQ(run.report["events"].size(), 0u);
}

TEST(SnagScan, ReportDashWritesTheReportToStandardOutput) {
  const std::vector<std::string> options{"--frames", "20:22", "-q", "--fail-on", "0"};
  const ProcessResult to_stdout = snag_scan(with(with(sample_pc2_inputs(), options), {"--report", "-"}));
  ASSERT_EQ(to_stdout.exit_code, 0) << to_stdout.err;
  const json from_stdout = parse_report_text(to_stdout.out);
  const json& from_file = scan(with(sample_pc2_inputs(), {"--frames", "20:22", "--fail-on", "0"})).report;
  EXPECT_TRUE(from_stdout["events"] == from_file["events"]);
  EXPECT_TRUE(from_stdout["summary"] == from_file["summary"]);
}

TEST(SnagScan, FastPrecisionIsNotCertifiedAndKeepsEveryCertifiedEvent) {
  // Fast mode reports uncertain answers as such: a superset of the certified
  // collisions (conservative), and the same intersections.
  const std::vector<std::string> options = with({"--threads", "2"}, kWindow);
  const json& fast = scan(with(sample_pc2_inputs(), with({"--precision", "fast"}, options))).report;
  const json& certified = window_scan().report;
  EXPECT_EQ(fast["certified"], false);
  EXPECT_EQ(fast["settings"]["precision"], "fast");
  EXPECT_EQ(certified["certified"], true);
  EXPECT_TRUE(events_of_kind(fast["events"], "intersection") == events_of_kind(certified["events"], "intersection"));
  const auto objects = objects_of(fast);
  std::set<EventKey> fast_keys;
  for (const json& e : fast["events"]) fast_keys.insert(event_key(e, objects));
  for (const json& e : certified["events"]) {
    EXPECT_TRUE(fast_keys.count(event_key(e, objects))) << "missing in fast mode: " << e.dump();
  }
}

/// OBJ text of axis-aligned unit cubes (12 triangles each) at the given
/// corners, as one object `name`, with vertex numbering continuing after `base` vertices.
std::string obj_cubes(const std::string& name, const std::vector<std::array<double, 3>>& corners, int base) {
  std::string text = "o " + name + "\n";
  static const int faces[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                   {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  for (std::size_t c = 0; c < corners.size(); ++c) {
    const auto [x, y, z] = corners[c];
    for (int k = 0; k < 8; ++k) {
      const int bx = (k == 1 || k == 2 || k == 5 || k == 6), by = (k == 2 || k == 3 || k == 6 || k == 7), bz = k >= 4;
      text += "v " + std::to_string(x + bx) + " " + std::to_string(y + by) + " " + std::to_string(z + bz) + "\n";
    }
  }
  for (std::size_t c = 0; c < corners.size(); ++c) {
    for (const auto& f : faces) {
      text += "f";
      for (int k : f) text += " " + std::to_string(base + 8 * static_cast<int>(c) + k + 1);
      text += "\n";
    }
  }
  return text;
}

// Hand-counted: object "a" holds two cubes far apart, object "b" two cubes
// each pushed half into one of them, in frames 0-2; in frame 1 only, a third
// pair overlaps elsewhere. Each frame has one region per overlapping pair of
// cubes; the two lasting overlaps are two tracks of frames 0-2, the brief one
// a track of frame 1 alone.
TEST(SnagScan, SeparateOverlapsAreSeparateRegionsAndLastingOnesOneTrackEach) {
  TemporaryDirectory dir;
  for (int f = 0; f < 3; ++f) {
    std::vector<std::array<double, 3>> a{{0, 0, 0}, {10, 0, 0}}, b{{0.5, 0.25, 0.3}, {10.5, 0.3, 0.2}};
    if (f == 1) {
      a.push_back({0, 10, 0});
      b.push_back({0.4, 10.2, 0.5});
    } else {  // the same vertex count in every frame: the third cubes apart
      a.push_back({0, 10, 0});
      b.push_back({0, 20, 0});
    }
    dir.write("frame_" + std::to_string(f) + ".obj", obj_cubes("a", a, 0) + obj_cubes("b", b, 24));
  }
  const ProcessResult run = snag_scan({dir.path("frame_%d.obj"), "--mode", "dcd", "-q", "-r", dir.path("r.jsonl")});
  ASSERT_EQ(run.exit_code, 1) << run.err;
  const json report = load_report(dir.path("r.jsonl"));
  std::vector<std::size_t> regions_per_frame;
  for (const json& f : report["frames"]) regions_per_frame.push_back(f["regions"]);
  EXPECT_EQ(regions_per_frame, (std::vector<std::size_t>{2, 3, 2}));
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  for (const json& t : report["tracks"]) {
    EXPECT_TRUE(t["merged_into"].is_null());
    EXPECT_EQ(t["objects"], json({"a", "b"}));
    spans.emplace_back(t["first_frame"], t["last_frame"]);
  }
  std::sort(spans.begin(), spans.end());
  EXPECT_EQ(spans, (std::vector<std::pair<std::size_t, std::size_t>>{{0, 2}, {0, 2}, {1, 1}}));
  EXPECT_EQ(report["summary"]["tracks"], 3);
  EXPECT_EQ(report["summary"]["regions"], 7);
}

// Regions and tracks on the whole sample: every checked event names a region
// of its frame, kind and objects; the region's counts are those of its
// events; tracks hold their regions' frames; the trailer adds them up.
TEST(SnagScan, RegionsHoldTheirEventsAndTracksTheirRegions) {
  const json& report = full_scan().report;
  const json& regions = report["regions"];
  ASSERT_GT(regions.size(), 10u);
  std::map<std::size_t, std::size_t> events_named;
  std::map<std::size_t, const json*> region_by_id;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    EXPECT_EQ(regions[i]["id"], i);
    region_by_id[i] = &regions[i];
  }
  for (const json& e : report["events"]) {
    ASSERT_FALSE(e["region"].is_null()) << e.dump();
    const json& region = *region_by_id.at(e["region"].get<std::size_t>());
    ++events_named[e["region"].get<std::size_t>()];
    EXPECT_EQ(region["frame"], e["frame"]);
    EXPECT_EQ(region["kind"], e["kind"]);
    std::set<std::string> objects{e["a"]["object"], e["b"]["object"]};
    EXPECT_EQ(objects, (std::set<std::string>{region["objects"][0], region["objects"][1]}));
    if (e["kind"] == "intersection") {
      for (const json& ref : {e["a"], e["b"]}) {
        bool found = false;
        for (const json& side : region["faces"]) {
          if (side["object"] != ref["object"]) continue;
          for (const json& id : side["ids"]) found = found || id == ref["face"];
        }
        EXPECT_TRUE(found) << e.dump();
      }
    }
  }
  std::size_t face_total = 0;
  std::map<std::size_t, const json*> track_by_id;
  std::size_t open_tracks = 0;
  for (const json& t : report["tracks"]) {
    track_by_id[t["id"].get<std::size_t>()] = &t;
    EXPECT_LE(t["first_frame"], t["last_frame"]);
    open_tracks += t["merged_into"].is_null();
  }
  for (const json& region : regions) {
    EXPECT_EQ(region["events"], events_named[region["id"].get<std::size_t>()]);
    std::size_t faces = 0;
    for (const json& side : region["faces"]) faces += side["ids"].size();
    EXPECT_EQ(region["face_count"], faces);
    face_total += faces;
    const json& track = *track_by_id.at(region["track"].get<std::size_t>());
    EXPECT_LE(track["first_frame"], region["frame"]);
    EXPECT_GE(track["last_frame"], region["frame"]);
    EXPECT_EQ(track["kind"], region["kind"]);
  }
  EXPECT_GT(face_total, 0u);
  EXPECT_EQ(report["summary"]["regions"], regions.size());
  EXPECT_EQ(report["summary"]["tracks"], open_tracks);
  std::size_t frame_regions = 0;
  for (const json& f : report["frames"]) frame_regions += f["regions"].get<std::size_t>();
  EXPECT_EQ(frame_regions, regions.size());
}

TEST(SnagScan, PrintsASummaryWhenNoReportGoesToStandardOutput) {
  const ProcessResult run = snag_scan(with(sample_pc2_inputs(), with({"--threads", "2"}, kWindow)));
  ASSERT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.out.find("cloth / body"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("largest tracks:"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("verdict: FAIL: events"), std::string::npos) << run.out;
  EXPECT_EQ(run.err, "");  // no progress: standard error is not a terminal
}

TEST(SnagScan, JsonSummaryIsTheTrailerRecord) {
  const ProcessResult run = snag_scan(with(sample_pc2_inputs(), with({"--threads", "2", "--json"}, kWindow)));
  ASSERT_EQ(run.exit_code, 1) << run.err;
  ASSERT_EQ(lines_of(run.out).size(), 1u) << run.out;
  const json summary = json::parse(run.out);
  EXPECT_EQ(summary["record"], "trailer");
  EXPECT_TRUE(summary["summary"] == window_scan().report["summary"]);
  EXPECT_EQ(summary["verdict"]["pass"], false);
}

TEST(SnagScan, EventsRegionsAndNoneListNoEventsButTheSameRegions) {
  const json& all = window_scan().report;
  const json& regions_only = scan(with(sample_pc2_inputs(), with({"--threads", "2", "--events", "regions"}, kWindow))).report;
  const json& none = scan(with(sample_pc2_inputs(), with({"--threads", "2", "--events", "none"}, kWindow))).report;
  EXPECT_TRUE(regions_only["events"].empty());
  EXPECT_TRUE(none["events"].empty());
  EXPECT_TRUE(regions_only["regions"] == all["regions"]);
  EXPECT_TRUE(regions_only["tracks"] == all["tracks"]);
  ASSERT_EQ(none["regions"].size(), all["regions"].size());
  for (std::size_t i = 0; i < all["regions"].size(); ++i) {
    EXPECT_FALSE(none["regions"][i].contains("faces"));
    EXPECT_EQ(none["regions"][i]["face_count"], all["regions"][i]["face_count"]);
  }
  EXPECT_EQ(regions_only["summary"]["listed"], 0);
  EXPECT_EQ(regions_only["summary"]["left_out"], all["summary"]["events"]);
  EXPECT_EQ(regions_only["summary"]["events"], all["summary"]["events"]);
}

TEST(SnagScan, MaxEventsListsTheFirstEventsAndCountsTheRest) {
  const json& all = window_scan().report;
  const std::size_t total = all["events"].size();
  ASSERT_GT(total, 20u);
  const json& capped = scan(with(sample_pc2_inputs(), with({"--threads", "2", "--max-events", "20"}, kWindow))).report;
  ASSERT_EQ(capped["events"].size(), 20u);
  for (std::size_t i = 0; i < 20; ++i) EXPECT_TRUE(capped["events"][i] == all["events"][i]) << i;
  EXPECT_EQ(capped["summary"]["listed"], 20);
  EXPECT_EQ(capped["summary"]["left_out"], total - 20);
  EXPECT_TRUE(capped["regions"] == all["regions"]);
}

TEST(SnagScan, JsonAndReportToStandardOutputConflict) {
  const ProcessResult run = snag_scan(with(sample_pc2_inputs(), {"--json", "-r", "-", "--frames", "0:1"}));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(lines_of(run.err).size(), 1u) << run.err;
}

/// The window's checked events of one kind and pair, counted from its report.
std::size_t count_pair(const json& report, const std::string& kind, const std::string& a, const std::string& b) {
  std::size_t n = 0;
  for (const json& e : report["events"]) {
    const std::set<std::string> objects{e["a"]["object"], e["b"]["object"]};
    n += e["kind"] == kind && objects == std::set<std::string>{a, b} && !e.contains("allowed");
  }
  return n;
}

// The sample's manifest allows the cloth's self-collisions and fails on
// collisions and intersections: the allowed events are counted, listed with
// their rule and in no region, and the verdict names the two thresholds.
TEST(SnagScan, SampleManifestAllowsSelfCollisionsAndFailsOnTheRest) {
  const json& plain = window_scan().report;
  const ScanRun& run = scan({"--manifest", kSampleDir + "/scene.yaml", "--threads", "2", "--frames", "24:26"});
  ASSERT_EQ(run.process.exit_code, 1) << run.process.err;
  const json& report = run.report;
  const std::size_t self_collisions = count_pair(plain, "collision", "cloth", "cloth");
  ASSERT_GT(self_collisions, 0u);
  EXPECT_EQ(report["summary"]["allowed"], self_collisions);
  EXPECT_EQ(report["trailer"]["allow"], json({self_collisions}));
  EXPECT_EQ(report["summary"]["collisions"], count_pair(plain, "collision", "cloth", "body"));
  EXPECT_EQ(report["summary"]["intersections"], plain["summary"]["intersections"]);
  std::size_t listed_allowed = 0;
  for (const json& e : report["events"]) {
    if (!e.contains("allowed")) continue;
    ++listed_allowed;
    EXPECT_EQ(e["allowed"], 0);
    EXPECT_TRUE(e["region"].is_null());
    EXPECT_EQ(e["a"]["object"], "cloth");
    EXPECT_EQ(e["b"]["object"], "cloth");
  }
  EXPECT_EQ(listed_allowed, self_collisions);
  for (const json& r : report["regions"]) EXPECT_FALSE(r["kind"] == "collision" && r["objects"] == json({"cloth", "cloth"}));
  const json& failed = report["trailer"]["verdict"]["failed"];
  ASSERT_EQ(failed.size(), 2u) << failed.dump();
  EXPECT_EQ(failed[0]["what"], "collisions");
  EXPECT_EQ(failed[1]["what"], "intersections");
  EXPECT_EQ(report["header"]["settings"]["manifest"], kSampleDir + "/scene.yaml");

  // The same manifest with both thresholds off on the command line passes.
  const ScanRun& relaxed = scan({"--manifest", kSampleDir + "/scene.yaml", "--threads", "2", "--frames", "24:26",
                                 "--fail-on-collisions", "0", "--fail-on-intersections", "0"});
  EXPECT_EQ(relaxed.process.exit_code, 0) << relaxed.process.err;
  EXPECT_EQ(relaxed.report["trailer"]["verdict"]["pass"], true);
}

TEST(SnagScan, RulesOnTheCommandLineDropUncheckedPairsAndJudgeRegionsAndTracks) {
  const json& plain = window_scan().report;
  // The cloth's self-contact not checked: only cloth / body events remain, counted as not checked.
  const ScanRun& run = scan(with(sample_pc2_inputs(), with({"--threads", "2", "--no-self", "cloth", "--fail-on", "0",
                                                            "--fail-on-tracks", "1"}, kWindow)));
  EXPECT_EQ(run.process.exit_code, 1) << run.process.err;
  const std::size_t body_events =
      count_pair(plain, "collision", "cloth", "body") + count_pair(plain, "intersection", "cloth", "body");
  ASSERT_GT(body_events, 0u);
  EXPECT_EQ(run.report["summary"]["events"], body_events);
  EXPECT_EQ(run.report["summary"]["not_checked"], plain["summary"]["events"].get<std::size_t>() - body_events);
  for (const json& e : run.report["events"]) EXPECT_NE(e["b"]["object"], e["a"]["object"]) << e.dump();
  const json& failed = run.report["trailer"]["verdict"]["failed"];
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed[0]["what"], "tracks");
  EXPECT_EQ(failed[0]["count"], run.report["summary"]["tracks"]);
  // An allow rule for the body's frames 24-25 collisions leaves frame 26's.
  const ScanRun& allowed = scan(with(sample_pc2_inputs(), with({"--threads", "2", "--no-self", "cloth", "--allow",
                                                                "cloth,body:collision:24-25", "--fail-on", "0"}, kWindow)));
  EXPECT_EQ(allowed.process.exit_code, 0) << allowed.process.err;
  for (const json& e : allowed.report["events"]) {
    const bool early_collision = e["kind"] == "collision" && e["frame"].get<std::size_t>() <= 25;
    EXPECT_EQ(e.contains("allowed"), early_collision) << e.dump();
  }
}

TEST(SnagScanRejects, ManifestProblemsNameTheFileAndLine) {
  TemporaryDirectory dir;
  const std::string manifest = dir.write("scene.yaml", "version: 1\nobjects:\n  - name: cloth\n    colour: red\n");
  const ProcessResult run = snag_scan({"--manifest", manifest, "-q"});
  EXPECT_EQ(run.exit_code, 2);
  const auto lines = lines_of(run.err);
  ASSERT_EQ(lines.size(), 1u) << run.err;
  EXPECT_NE(lines[0].find("scene.yaml:4"), std::string::npos) << lines[0];
  const ProcessResult unknown = snag_scan(with(sample_pc2_inputs(), {"--no-self", "cape", "-q", "--frames", "0:1"}));
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("cape"), std::string::npos) << unknown.err;
}

TEST(SnagScanRejects, CudaBackendWithAClearMessage) {
  const ProcessResult result = snag_scan(with(sample_pc2_inputs(), {"--backend", "cuda", "-q", "-r", "-"}));
  EXPECT_EQ(result.exit_code, 2);
  const auto lines = lines_of(result.err);
  ASSERT_EQ(lines.size(), 1u) << result.err;
  EXPECT_NE(lines[0].find("cuda"), std::string::npos) << lines[0];
  EXPECT_TRUE(result.out.empty());
}

TEST(SnagScanRejects, UnknownOptionAndBadValues) {
  EXPECT_EQ(snag_scan(with(sample_pc2_inputs(), {"--no-such-option"})).exit_code, 2);
  EXPECT_EQ(snag_scan(with(sample_pc2_inputs(), {"--mode", "both"})).exit_code, 2);
  EXPECT_EQ(snag_scan(with(sample_pc2_inputs(), {"--precision", "sloppy"})).exit_code, 2);
  EXPECT_EQ(snag_scan(with(sample_pc2_inputs(), {"--thickness", "-1"})).exit_code, 2);
}

TEST(SnagScanRejects, BadFrameSelection) {
  const ProcessResult result = snag_scan(with(sample_pc2_inputs(), {"--frames", "9:3", "-r", "-"}));
  EXPECT_EQ(result.exit_code, 2);
  const auto lines = lines_of(result.err);
  ASSERT_EQ(lines.size(), 1u) << result.err;
  EXPECT_NE(lines[0].find("frame"), std::string::npos);
}

TEST(SnagScanRejects, MissingInputNamesTheFile) {
  TemporaryDirectory dir;
  const ProcessResult result = snag_scan({dir.path("gone.obj"), "-r", "-"});
  EXPECT_EQ(result.exit_code, 2);
  const auto lines = lines_of(result.err);
  ASSERT_EQ(lines.size(), 1u) << result.err;
  EXPECT_NE(lines[0].find("gone.obj"), std::string::npos);
}

TEST(SnagScanRejects, UnwritableReportPath) {
  TemporaryDirectory dir;
  const ProcessResult result =
      snag_scan(with(sample_pc2_inputs(), {"--frames", "0:1", "-q", "-r", dir.path("no/such/dir/report.json")}));
  EXPECT_EQ(result.exit_code, 2) << result.err;
  EXPECT_EQ(lines_of(result.err).size(), 1u) << result.err;
}

}  // namespace
}  // namespace snag::test
