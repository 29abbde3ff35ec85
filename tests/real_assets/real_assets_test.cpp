// snag-scan and snag-info, run as a user would, on the assets that
// make_real_assets.py builds in Blender (data/<scene>/): each scene exported
// as FBX, Collada and glTF, which snag evaluates itself (node animation,
// skinning) and welds by default, and as an OBJ-sequence twin holding
// Blender's own evaluated mesh of each frame.
//
// Checks: every run ends within a time limit; the rigid closed box and
// cylinder have no collision and no intersection in any format; each
// animated file gives the same events, the same welded vertex count and the
// same bounds as its twin (the twin scanned with --weld exact, which joins
// the garment's unmerged seams); snag-info says what the weld joined.
//
// Events are compared as multisets: vertex and face ids differ between
// formats (FBX and Collada split every triangle corner, glTF splits where
// normals differ), so an event is its kind, type, frame, position and toi.
// The twin is printed with six decimals (up to 5e-7 m off) and every format
// stores float32; across formats the events of these scenes move by at most
// 4.2e-6 m and 1.7e-5 frames. The tolerances, 2e-5 m (6e-6 of the largest
// scene, 3.3 m across) and 1e-4 frames, leave room for that, while the two
// closest events of one kind, type and frame lie 4.5e-4 m apart, so no event
// can be matched to its neighbour.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <tuple>
#include <vector>

#include "tests/tools/report_json.hpp"
#include "tests/tools/run_process.hpp"

namespace snag::test {
namespace {

using nlohmann::json;

constexpr double kTimeLimit = 60;  ///< seconds per run: a hang fails the test instead of blocking it
constexpr std::size_t kFrames = 17;  ///< Blender frames 0 to 16
constexpr double kPositionTol = 2e-5;  ///< metres, per coordinate
constexpr double kToiTol = 1e-4;       ///< frames
constexpr double kBoundsTol = 1e-5;    ///< metres: the twin's six decimals plus float32

const std::string kData = std::string(SNAG_SOURCE_DIR) + "/tests/real_assets/data/";

const std::vector<std::string> kScenes{"rigid_box", "rigid_cylinder", "bent_tube", "garment", "box_through_box"};
const std::vector<std::string> kContactFreeScenes{"rigid_box", "rigid_cylinder", "bent_tube", "garment"};
const std::vector<std::string> kRigidScenes{"rigid_box", "rigid_cylinder"};
const std::vector<std::string> kFormats{"fbx", "dae", "glb"};

std::string animated_file(const std::string& scene, const std::string& format) {
  return kData + scene + "/" + scene + "." + format;
}

std::string obj_twin(const std::string& scene) { return kData + scene + "/obj_%04d.obj"; }

const std::vector<std::string> kTwinOptions{"--weld", "exact"};

/// A finished run and the JSON it wrote (null when it did not finish properly).
struct ToolRun {
  ProcessResult process;
  json output;
};

bool finished(const ProcessResult& p) { return !p.timed_out && (p.exit_code == 0 || p.exit_code == 1); }

/// snag-scan --mode all on `input` with `options`, under the time limit, and
/// the report it wrote. Runs are remembered: tests that need the same run share it.
const ToolRun& scan(const std::string& input, const std::vector<std::string>& options) {
  static std::map<std::vector<std::string>, ToolRun> runs;
  std::vector<std::string> arguments{input, "--mode", "all"};
  arguments.insert(arguments.end(), options.begin(), options.end());
  auto found = runs.find(arguments);
  if (found != runs.end()) return found->second;
  TemporaryDirectory dir;
  std::vector<std::string> full = arguments;
  full.insert(full.end(), {"-q", "-r", dir.path("report.json")});
  ToolRun run;
  run.process = run_process(SNAG_SCAN_EXE, full, {kTimeLimit});
  EXPECT_FALSE(run.process.timed_out) << "snag-scan " << input << " ran past " << kTimeLimit << " s";
  EXPECT_TRUE(finished(run.process)) << "snag-scan " << input << " exited " << run.process.exit_code << ": "
                                     << run.process.err;
  if (finished(run.process)) run.output = load_report(dir.path("report.json"));
  return runs.emplace(arguments, std::move(run)).first->second;
}

/// snag-info on `input` with `options`, under the time limit.
ToolRun info(const std::string& input, const std::vector<std::string>& options) {
  std::vector<std::string> arguments{input};
  arguments.insert(arguments.end(), options.begin(), options.end());
  ToolRun run;
  run.process = run_process(SNAG_INFO_EXE, arguments, {kTimeLimit});
  EXPECT_FALSE(run.process.timed_out) << "snag-info " << input << " ran past " << kTimeLimit << " s";
  EXPECT_EQ(run.process.exit_code, 0) << "snag-info " << input << ": " << run.process.err;
  return run;
}

/// snag-info --json on `input`.
json info_json(const std::string& input, const std::vector<std::string>& options) {
  std::vector<std::string> with_json = options;
  with_json.push_back("--json");
  const ToolRun run = info(input, with_json);
  return run.process.exit_code == 0 ? json::parse(run.process.out) : json();
}

/// How far apart two events are in units of the tolerances (at most 1: a
/// match), or infinity when their kind, type or frame differ.
double mismatch(const json& a, const json& b) {
  if (a.at("kind") != b.at("kind") || a.value("type", "") != b.value("type", "") || a.at("frame") != b.at("frame"))
    return INFINITY;
  double worst = 0;
  for (int i = 0; i < 3; ++i) {
    worst = std::max(worst, std::abs(a["position"][i].get<double>() - b["position"][i].get<double>()) / kPositionTol);
  }
  if (a.contains("toi") || b.contains("toi")) {
    worst = std::max(worst, std::abs(a.at("toi").get<double>() - b.at("toi").get<double>()) / kToiTol);
  }
  return worst;
}

/// The events of `a` that find no partner in `b`: each event of `b` partners
/// at most one of `a`, the nearest unmatched one within the tolerances.
std::vector<json> unmatched_events(const json& a, const json& b) {
  std::vector<bool> taken(b.size(), false);
  std::vector<json> missing;
  for (const json& event : a) {
    std::size_t best = b.size();
    double best_mismatch = 1;
    for (std::size_t i = 0; i < b.size(); ++i) {
      if (taken[i]) continue;
      const double m = mismatch(event, b[i]);
      if (m <= best_mismatch) {
        best = i;
        best_mismatch = m;
      }
    }
    if (best == b.size()) {
      missing.push_back(event);
    } else {
      taken[best] = true;
    }
  }
  return missing;
}

/// Vertex and triangle counts per object name.
std::map<std::string, std::pair<std::size_t, std::size_t>> object_sizes(const json& objects) {
  std::map<std::string, std::pair<std::size_t, std::size_t>> sizes;
  for (const json& o : objects) {
    sizes[o.at("name").get<std::string>()] = {o.at("vertices").get<std::size_t>(), o.at("triangles").get<std::size_t>()};
  }
  return sizes;
}

using SceneFormat = std::tuple<std::string, std::string>;

std::string scene_format_name(const ::testing::TestParamInfo<SceneFormat>& info) {
  return std::get<0>(info.param) + "_" + std::get<1>(info.param);
}

std::string scene_name(const ::testing::TestParamInfo<std::string>& info) { return info.param; }

/// One scene in one animated format (FBX, Collada or glTF).
class AnimatedAsset : public ::testing::TestWithParam<SceneFormat> {
 protected:
  std::string scene() const { return std::get<0>(GetParam()); }
  std::string file() const { return animated_file(std::get<0>(GetParam()), std::get<1>(GetParam())); }
};

TEST_P(AnimatedAsset, ScanFinishesWithinTheTimeLimit) {
  const ToolRun& run = scan(file(), {});
  ASSERT_TRUE(finished(run.process));
  EXPECT_EQ(run.output.at("frames").size(), kFrames);
}

TEST_P(AnimatedAsset, GivesTheSameEventsAsItsObjTwin) {
  const ToolRun& file_run = scan(file(), {});
  const ToolRun& twin_run = scan(obj_twin(scene()), kTwinOptions);
  ASSERT_TRUE(finished(file_run.process) && finished(twin_run.process));
  const json& file_summary = file_run.output.at("summary");
  const json& twin_summary = twin_run.output.at("summary");
  for (const char* count : {"collisions", "vf", "ee", "intersections", "uncertain"}) {
    EXPECT_EQ(file_summary.at(count), twin_summary.at(count)) << count;
  }
  const json& file_events = file_run.output.at("events");
  const json& twin_events = twin_run.output.at("events");
  ASSERT_EQ(file_events.size(), twin_events.size());
  for (const json& event : unmatched_events(file_events, twin_events)) {
    ADD_FAILURE() << "not in the twin: " << event.dump();
  }
}

TEST_P(AnimatedAsset, WeldsToTheVertexCountOfItsObjTwin) {
  const ToolRun& file_run = scan(file(), {});
  const ToolRun& twin_run = scan(obj_twin(scene()), kTwinOptions);
  ASSERT_TRUE(finished(file_run.process) && finished(twin_run.process));
  EXPECT_EQ(object_sizes(file_run.output.at("objects")), object_sizes(twin_run.output.at("objects")));
}

TEST_P(AnimatedAsset, HasTheFramesAndBoundsOfItsObjTwin) {
  const json file_info = info_json(file(), {});
  const json twin_info = info_json(obj_twin(scene()), kTwinOptions);
  ASSERT_FALSE(file_info.is_null() || twin_info.is_null());
  EXPECT_EQ(file_info.at("frames"), twin_info.at("frames"));
  EXPECT_EQ(file_info.at("time_range"), twin_info.at("time_range"));
  for (const char* end : {"min", "max"}) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(file_info["bounds"][end][i].get<double>(), twin_info["bounds"][end][i].get<double>(), kBoundsTol)
          << end << " " << i;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(RealAssets, AnimatedAsset,
                         ::testing::Combine(::testing::ValuesIn(kScenes), ::testing::ValuesIn(kFormats)),
                         scene_format_name);

/// A rigidly moving closed box or cylinder: nothing can touch.
class RigidAsset : public ::testing::TestWithParam<SceneFormat> {};

TEST_P(RigidAsset, HasNoCollisionsOrIntersections) {
  const ToolRun& run = scan(animated_file(std::get<0>(GetParam()), std::get<1>(GetParam())), {});
  ASSERT_TRUE(finished(run.process));
  EXPECT_EQ(run.process.exit_code, 0);
  EXPECT_EQ(run.output.at("settings").at("precision"), "certified");
  EXPECT_EQ(run.output.at("summary").at("collisions"), 0);
  EXPECT_EQ(run.output.at("summary").at("intersections"), 0);
  EXPECT_TRUE(run.output.at("events").empty()) << run.output.at("events").size() << " events";
}

INSTANTIATE_TEST_SUITE_P(RealAssets, RigidAsset,
                         ::testing::Combine(::testing::ValuesIn(kRigidScenes), ::testing::ValuesIn(kFormats)),
                         scene_format_name);

/// The OBJ-sequence twin of a scene, Blender's own evaluated meshes.
class ObjTwin : public ::testing::TestWithParam<std::string> {};

TEST_P(ObjTwin, ScanWithExactWeldFinishesWithinTheTimeLimit) {
  const ToolRun& run = scan(obj_twin(GetParam()), kTwinOptions);
  ASSERT_TRUE(finished(run.process));
  EXPECT_EQ(run.output.at("frames").size(), kFrames);
}

INSTANTIATE_TEST_SUITE_P(RealAssets, ObjTwin, ::testing::ValuesIn(kScenes), scene_name);

/// The scenes built without any contact: the twin, welded, has no event (the
/// garment's coincident seam vertices become one and stop touching).
class ContactFreeTwin : public ::testing::TestWithParam<std::string> {};

TEST_P(ContactFreeTwin, HasNoEvents) {
  const ToolRun& run = scan(obj_twin(GetParam()), kTwinOptions);
  ASSERT_TRUE(finished(run.process));
  EXPECT_EQ(run.process.exit_code, 0);
  EXPECT_TRUE(run.output.at("events").empty()) << run.output.at("events").size() << " events";
}

INSTANTIATE_TEST_SUITE_P(RealAssets, ContactFreeTwin, ::testing::ValuesIn(kContactFreeScenes), scene_name);

// The twin comparison is only as good as the events it compares: the scene
// with contact has collisions of both types and intersections.
TEST(RealAssets, BoxThroughBoxTwinHasCollisionsOfBothTypesAndIntersections) {
  const ToolRun& run = scan(obj_twin("box_through_box"), kTwinOptions);
  ASSERT_TRUE(finished(run.process));
  EXPECT_EQ(run.process.exit_code, 1);
  const json& summary = run.output.at("summary");
  EXPECT_GT(summary.at("vf").get<std::size_t>(), 0u);
  EXPECT_GT(summary.at("ee").get<std::size_t>(), 0u);
  EXPECT_GT(summary.at("intersections").get<std::size_t>(), 0u);
  EXPECT_EQ(summary.at("uncertain"), 0);
}

/// The "welded N file vertices into M (exact)" line of snag-info's summary, as (N, M).
std::vector<std::pair<int, int>> welded_lines(const std::string& text) {
  static const std::regex welded(R"(welded (\d+) (?:file )?vertices into (\d+) \(exact\))");
  std::vector<std::pair<int, int>> found;
  for (const std::string& line : lines_of(text)) {
    std::smatch m;
    if (std::regex_search(line, m, welded)) found.emplace_back(std::stoi(m[1]), std::stoi(m[2]));
  }
  return found;
}

// FBX gives one vertex per triangle corner: the box's 12 triangles come as 36
// vertices, welded back into Blender's 8.
TEST(RealAssets, SnagInfoOnFbxBoxSaysItWelded36VerticesInto8) {
  const ToolRun run = info(animated_file("rigid_box", "fbx"), {});
  EXPECT_EQ(welded_lines(run.process.out), (std::vector<std::pair<int, int>>{{36, 8}})) << run.process.out;
}

// The garment's 160 triangles come as 480 vertices; welded they are Blender's
// 120 less the 24 seam vertices that coincide with another panel's.
TEST(RealAssets, SnagInfoOnFbxGarmentSaysItWelded480VerticesInto96) {
  const ToolRun run = info(animated_file("garment", "fbx"), {});
  EXPECT_EQ(welded_lines(run.process.out), (std::vector<std::pair<int, int>>{{480, 96}})) << run.process.out;
}

}  // namespace
}  // namespace snag::test
