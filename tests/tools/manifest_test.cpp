// The scene manifest reader against hand-made manifests: a full one, paths
// relative to the manifest's directory, and one bad case per check, each an
// InputError naming the file and the line of the problem.
#include "tools/common/manifest.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "libcd/core/error.hpp"

namespace snag::tools {
namespace {

namespace fs = std::filesystem;

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / ("snag-manifest-" + std::string(info->test_suite_name()) + "-" + info->name() +
                                         "-" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string path(const std::string& name) const { return (path_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    fs::create_directories(fs::path(path(name)).parent_path());
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }

 private:
  fs::path path_;
};

const char* const kGoodManifest = R"(# a garment on a walking body
version: 1
objects:
  - name: cloth
    input: cache/cloth_%04d.obj
    thickness: 0.002
  - name: body
    input: cache/body.pc2
    topology: cache/body.obj
    self: false
  - name: prop
    files: [prop/t0.ply, /abs/prop_t1.ply]
    self: true
pairs: [[cloth, body], [cloth, prop]]
neighbourhood: 2
frames: "10:"
weld: exact
thickness: 0.001
fps: 30
allow:
  - objects: [cloth, body]
    kind: collision
    frames: [10, 20]
    box: [[-1, 0, -1.5], [1, 2, 1e-1]]
    note: "hand rests on hip"
  - objects: [cloth]
    kind: any
    frames: 7
  - objects: ["*", prop]
    frames: [30, end]
  - kind: intersection
fail:
  events: 0
  collisions: 1
  intersections: 2
  regions: 3
  tracks: 4
)";

TEST(Manifest, ReadsEveryKey) {
  const TempDir dir;
  const std::string path = dir.write("shot/scene.yaml", kGoodManifest);
  const Manifest m = read_manifest(path);
  EXPECT_EQ(m.path, path);
  const std::string shot = dir.path("shot");
  ASSERT_EQ(m.inputs.size(), 3u);
  EXPECT_EQ(m.inputs[0].name, "cloth");
  EXPECT_EQ(m.inputs[0].path, shot + "/cache/cloth_%04d.obj");
  EXPECT_TRUE(m.inputs[0].topology.empty());
  EXPECT_EQ(m.inputs[1].name, "body");
  EXPECT_EQ(m.inputs[1].path, shot + "/cache/body.pc2");
  EXPECT_EQ(m.inputs[1].topology, shot + "/cache/body.obj");
  EXPECT_EQ(m.inputs[2].name, "prop");
  EXPECT_EQ(m.inputs[2].frame_files, (std::vector<std::string>{shot + "/prop/t0.ply", "/abs/prop_t1.ply"}));
  EXPECT_EQ(m.frames, "10:");
  EXPECT_EQ(m.weld, "exact");
  EXPECT_EQ(m.thickness, 0.001);
  EXPECT_EQ(m.fps, 30.0);

  const report::ScanRules& r = m.rules;
  ASSERT_EQ(r.thickness.size(), 1u);
  EXPECT_EQ(r.thickness[0].first, "cloth");
  EXPECT_EQ(r.thickness[0].second, 0.002);
  EXPECT_EQ(r.no_self, std::vector<std::string>{"body"});
  ASSERT_EQ(r.pairs.size(), 2u);
  EXPECT_EQ(r.pairs[1], (std::pair<std::string, std::string>{"cloth", "prop"}));
  EXPECT_EQ(r.neighbourhood, 2u);

  ASSERT_EQ(r.allow.size(), 4u);
  const report::AllowRule& hip = r.allow[0];
  EXPECT_EQ(hip.object_a, "cloth");
  EXPECT_EQ(hip.object_b, "body");
  EXPECT_EQ(hip.kind, EventKind::kCollision);
  EXPECT_EQ(hip.first_frame, 10u);
  EXPECT_EQ(hip.last_frame, 20u);
  ASSERT_TRUE(hip.box.has_value());
  EXPECT_EQ((*hip.box)[0], (Vec3{-1, 0, -1.5}));
  EXPECT_EQ((*hip.box)[1], (Vec3{1, 2, 0.1}));
  EXPECT_EQ(hip.note, "hand rests on hip");
  EXPECT_EQ(r.allow[1].object_a, "cloth");
  EXPECT_EQ(r.allow[1].object_b, "");  // one name: that object against any
  EXPECT_FALSE(r.allow[1].kind.has_value());
  EXPECT_EQ(r.allow[1].first_frame, 7u);
  EXPECT_EQ(r.allow[1].last_frame, 7u);
  EXPECT_EQ(r.allow[2].object_a, "");
  EXPECT_EQ(r.allow[2].object_b, "prop");
  EXPECT_EQ(r.allow[2].first_frame, 30u);
  EXPECT_EQ(r.allow[2].last_frame, static_cast<std::size_t>(-1));
  EXPECT_EQ(r.allow[3].object_a, "");
  EXPECT_EQ(r.allow[3].kind, EventKind::kIntersection);
  EXPECT_FALSE(r.allow[3].box.has_value());

  EXPECT_EQ(r.fail.events, 0u);
  EXPECT_EQ(r.fail.collisions, 1u);
  EXPECT_EQ(r.fail.intersections, 2u);
  EXPECT_EQ(r.fail.regions, 3u);
  EXPECT_EQ(r.fail.tracks, 4u);
}

TEST(Manifest, RulesOnlyManifestNamesNoInputsAndKeepsDefaults) {
  const Manifest m = parse_manifest("version: 1\nobjects:\n  - name: cloth\n    self: false\n", "rules.yaml");
  EXPECT_TRUE(m.inputs.empty());
  EXPECT_EQ(m.rules.no_self, std::vector<std::string>{"cloth"});
  EXPECT_FALSE(m.frames.has_value());
  EXPECT_FALSE(m.thickness.has_value());
  EXPECT_EQ(m.rules.fail.events, 1u);
  EXPECT_EQ(m.rules.fail.collisions, 0u);
}

TEST(Manifest, PathsBesideAManifestInTheWorkingDirectoryStayAsWritten) {
  const Manifest m = parse_manifest("version: 1\nobjects:\n  - {name: a, input: a.obj}\n", "scene.yaml");
  ASSERT_EQ(m.inputs.size(), 1u);
  EXPECT_EQ(m.inputs[0].path, "a.obj");
}

struct BadCase {
  const char* text;
  std::size_t line;
  const char* fragment;
};

TEST(Manifest, EachProblemIsAnInputErrorAtItsLine) {
  const BadCase cases[] = {
      {"version: 1\nobject: []\n", 2, "unknown key 'object'"},
      {"objects: []\n", 1, "missing 'version: 1'"},
      {"version: 2\n", 1, "version 1"},
      {"- 1\n- 2\n", 1, "expected a map"},
      {"", 0, "expected a map"},
      {"version: 1\nthickness: thin\n", 2, "thickness: expected a finite number, found 'thin'"},
      {"version: 1\nthickness: .nan\n", 2, "finite number"},
      {"version: 1\nthickness: -1\n", 2, "must be 0 or more"},
      {"version: 1\nobjects:\n  - name: a\n    thickness: -0.1\n", 4, "must be 0 or more"},
      {"version: 1\nobjects:\n  - input: a.obj\n", 3, "needs a 'name'"},
      {"version: 1\nobjects:\n  - name: a\n  - name: a\n", 4, "'a' is given twice"},
      {"version: 1\nobjects:\n  - name: a\n    colour: red\n", 4, "unknown key 'colour'"},
      {"version: 1\nobjects:\n  - name: a\n    input: a.pc2\n", 4, "needs a 'topology'"},
      {"version: 1\nobjects:\n  - name: a\n    input: a.obj\n    topology: t.obj\n", 5, "goes with a point cache"},
      {"version: 1\nobjects:\n  - name: a\n    input: a.obj\n    files: [b.obj]\n", 3, "both 'input' and 'files'"},
      {"version: 1\nobjects:\n  - name: a\n    input: a.obj\n  - name: b\n", 5, "name the inputs of every object"},
      {"version: 1\nobjects:\n  - name: a\n    self: maybe\n", 4, "expected true or false"},
      {"version: 1\nobjects:\n  - name: a\n    files: []\n", 4, "the list is empty"},
      {"version: 1\nobjects: {name: a}\n", 2, "expected a list"},
      {"version: 1\npairs: [[a]]\n", 2, "two object names"},
      {"version: 1\npairs: [[a, a]]\n", 2, "'a' twice"},
      {"version: 1\nneighbourhood: 65\n", 2, "at most 64"},
      {"version: 1\nneighbourhood: -1\n", 2, "whole number"},
      {"version: 1\nframes: \"x:y\"\n", 2, "frames:"},
      {"version: 1\nweld: glue\n", 2, "weld:"},
      {"version: 1\nfps: 0\n", 2, "more than 0"},
      {"version: 1\nallow:\n  - objects: [a, b, c]\n", 3, "one or two object names"},
      {"version: 1\nallow:\n  - kind: contact\n", 3, "collision, intersection or any"},
      {"version: 1\nallow:\n  - frames: [5, 2]\n", 3, "first frame is after the last"},
      {"version: 1\nallow:\n  - frames: [1, 2, 3]\n", 3, "[FIRST, LAST]"},
      {"version: 1\nallow:\n  - box: [[0, 0, 0], [1, 1]]\n", 3, "two corners"},
      {"version: 1\nallow:\n  - box: [[1, 0, 0], [0, 1, 1]]\n", 3, "low one"},
      {"version: 1\nallow:\n  -\n    note: a\n    reason: b\n", 5, "unknown key 'reason'"},
      {"version: 1\nfail:\n  events: -1\n", 3, "fail: events: expected a whole number"},
      {"version: 1\nfail:\n  contacts: 1\n", 3, "unknown key 'contacts'"},
      {"version: 1\nfail:\n  events: 1\n  events: 2\n", 4, "given twice"},
      {"version: 1\nobjects: [a, b\n", 3, ""},
      {"version: 1\n  bad: indentation\n", 2, ""},
  };
  for (const BadCase& c : cases) {
    try {
      parse_manifest(c.text, "shot/scene.yaml");
      ADD_FAILURE() << "no error for:\n" << c.text;
    } catch (const InputError& error) {
      const std::string what = error.what();
      EXPECT_EQ(error.where().file, "shot/scene.yaml") << what;
      EXPECT_EQ(error.where().line, c.line) << what << "\nfor:\n" << c.text;
      EXPECT_NE(what.find(c.fragment), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
      if (c.line != 0) EXPECT_NE(what.find("shot/scene.yaml:" + std::to_string(c.line) + ": column "), std::string::npos) << what;
    }
  }
}

TEST(Manifest, RefusesFilesOverOneMebibyteBeforeParsing) {
  const TempDir dir;
  std::string text = "version: 1\n";
  text += "# " + std::string(kMaxManifestBytes, 'x') + "\n";
  const std::string path = dir.write("big.yaml", text);
  try {
    read_manifest(path);
    ADD_FAILURE() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("1 MiB"), std::string::npos) << error.what();
  }
}

TEST(Manifest, MissingFileOrFolderIsAnInputError) {
  const TempDir dir;
  EXPECT_THROW(read_manifest(dir.path("none.yaml")), InputError);
  EXPECT_THROW(read_manifest(dir.path("")), InputError);
}

}  // namespace
}  // namespace snag::tools
