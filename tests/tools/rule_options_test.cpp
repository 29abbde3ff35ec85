// The rule options: --allow specs, and how the command line and a manifest
// merge into what a scan runs with.
#include "tools/common/rule_options.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "libcd/core/error.hpp"

namespace snag::tools {
namespace {

namespace fs = std::filesystem;

TEST(AllowSpec, ParsesObjectsKindFramesBoxAndNote) {
  report::AllowRule r = parse_allow_spec("cloth,body:collision:10-20");
  EXPECT_EQ(r.object_a, "cloth");
  EXPECT_EQ(r.object_b, "body");
  EXPECT_EQ(r.kind, EventKind::kCollision);
  EXPECT_EQ(r.first_frame, 10u);
  EXPECT_EQ(r.last_frame, 20u);
  EXPECT_FALSE(r.box.has_value());

  r = parse_allow_spec("*,body:5:box=-1,0,-1,1,2.5,1:note=hand: on hip");
  EXPECT_EQ(r.object_a, "");
  EXPECT_EQ(r.object_b, "body");
  EXPECT_FALSE(r.kind.has_value());
  EXPECT_EQ(r.first_frame, 5u);
  EXPECT_EQ(r.last_frame, 5u);
  ASSERT_TRUE(r.box.has_value());
  EXPECT_EQ((*r.box)[0], (Vec3{-1, 0, -1}));
  EXPECT_EQ((*r.box)[1], (Vec3{1, 2.5, 1}));
  EXPECT_EQ(r.note, "hand: on hip");

  r = parse_allow_spec("cloth:intersection:30-");
  EXPECT_EQ(r.object_a, "cloth");
  EXPECT_EQ(r.object_b, "");
  EXPECT_EQ(r.kind, EventKind::kIntersection);
  EXPECT_EQ(r.first_frame, 30u);
  EXPECT_EQ(r.last_frame, static_cast<std::size_t>(-1));

  r = parse_allow_spec("*");
  EXPECT_EQ(r.object_a, "");
  EXPECT_EQ(r.object_b, "");
  EXPECT_EQ(r.first_frame, 0u);
}

TEST(AllowSpec, RefusesMalformedSpecs) {
  for (const char* spec : {"", ":collision", "a,b,c", "a,", "a:contact", "a:20-10", "a:1-2:3", "a:x1",
                           "a:box=0,0,0,1,1", "a:box=1,0,0,0,1,1", "a:collision:any", "a:box=0,0,0,1,1,1:box=0,0,0,1,1,1"}) {
    EXPECT_THROW(parse_allow_spec(spec), UsageError) << spec;
  }
}

/// Parses a command line with the cache and rule options, as snag-scan does.
struct CommandLine {
  CLI::App app{"test"};
  CacheArguments cache;
  RuleArguments rules;
  explicit CommandLine(std::vector<std::string> args) {
    add_cache_options(app, cache);
    add_rule_options(app, rules);
    std::reverse(args.begin(), args.end());
    app.parse(args);
  }
};

TEST(RuleOptions, ParseAndMergeWithoutAManifest) {
  CommandLine line({"a.obj", "b.obj", "--pair", "a,b", "--pair", "b,c", "--no-self", "a", "--object-thickness",
                    "a=0.5", "--neighbourhood", "2", "--allow", "a,b:collision", "--fail-on", "0",
                    "--fail-on-regions", "3"});
  const ScanSetup setup = resolve_scan_setup(line.cache, line.rules, std::nullopt);
  ASSERT_EQ(setup.cache.inputs.size(), 2u);
  EXPECT_EQ(setup.cache.inputs[1].path, "b.obj");
  EXPECT_EQ(setup.thickness, 0.0);
  EXPECT_EQ(setup.weld, "auto");
  EXPECT_TRUE(setup.manifest.empty());
  const report::ScanRules& r = setup.rules;
  EXPECT_EQ(r.pairs.size(), 2u);
  EXPECT_EQ(r.no_self, std::vector<std::string>{"a"});
  ASSERT_EQ(r.thickness.size(), 1u);
  EXPECT_EQ(r.thickness[0].second, 0.5);
  EXPECT_EQ(r.neighbourhood, 2u);
  ASSERT_EQ(r.allow.size(), 1u);
  EXPECT_EQ(r.fail.events, 0u);
  EXPECT_EQ(r.fail.regions, 3u);
  EXPECT_EQ(r.fail.collisions, 0u);
}

TEST(RuleOptions, DefaultsFailOnOneEvent) {
  CommandLine line({"a.obj"});
  const ScanSetup setup = resolve_scan_setup(line.cache, line.rules, 0.25);
  EXPECT_EQ(setup.rules.fail.events, 1u);
  EXPECT_EQ(setup.thickness, 0.25);
}

TEST(RuleOptions, RefusesBadPairsAndThicknesses) {
  for (std::vector<std::string> args : {std::vector<std::string>{"a.obj", "--pair", "a"},
                                        {"a.obj", "--pair", "a,a"},
                                        {"a.obj", "--object-thickness", "a"},
                                        {"a.obj", "--object-thickness", "a=-1"},
                                        {"a.obj", "--object-thickness", "=1"},
                                        {"a.obj", "--allow", "a:bogus"}}) {
    CommandLine line(args);
    EXPECT_THROW(resolve_scan_setup(line.cache, line.rules, std::nullopt), UsageError) << args[1] << " " << args[2];
  }
  EXPECT_THROW(CommandLine({"a.obj", "--neighbourhood", "65"}), CLI::ValidationError);
}

TEST(RuleOptions, NoInputsIsAUsageError) {
  CommandLine line({"--pair", "a,b"});
  try {
    resolve_scan_setup(line.cache, line.rules, std::nullopt);
    ADD_FAILURE() << "no error";
  } catch (const UsageError& error) {
    EXPECT_NE(std::string(error.what()).find("no inputs"), std::string::npos) << error.what();
  }
}

class ManifestDir : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("snag-rule-options-" + std::string(info->name()) + "-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& text) {
    const std::string path = (dir_ / "scene.yaml").string();
    std::ofstream(path) << text;
    return path;
  }
  fs::path dir_;
};

const char* const kManifest = R"(version: 1
objects:
  - {name: cloth, input: cloth_%04d.obj, thickness: 0.002}
  - {name: body, input: body.pc2, topology: body.obj, self: false}
pairs: [[cloth, body]]
neighbourhood: 1
frames: "2:9"
weld: exact
thickness: 0.001
fps: 30
allow:
  - {objects: [cloth, body], frames: [1, 2]}
fail: {events: 5, tracks: 2}
)";

TEST_F(ManifestDir, ManifestGivesInputsAndCommandLineAddsAndOverrides) {
  const std::string path = write(kManifest);
  CommandLine line({"--manifest", path, "--frames", "3:", "--pair", "cloth,pin", "--object-thickness", "cloth=0.004",
                    "--allow", "*:intersection", "--neighbourhood", "0", "--fail-on", "1"});
  const ScanSetup setup = resolve_scan_setup(line.cache, line.rules, std::nullopt);
  EXPECT_EQ(setup.manifest, path);
  ASSERT_EQ(setup.cache.inputs.size(), 2u);
  EXPECT_EQ(setup.cache.inputs[0].path, (dir_ / "cloth_%04d.obj").string());
  EXPECT_EQ(setup.cache.inputs[1].topology, (dir_ / "body.obj").string());
  EXPECT_EQ(setup.cache.inputs[1].name, "body");
  EXPECT_EQ(setup.frames, "3:");  // the command line's
  EXPECT_EQ(setup.cache.frames.first, 3u);
  EXPECT_EQ(setup.weld, "exact");  // the manifest's
  EXPECT_EQ(setup.cache.sample_rate, 30.0);
  EXPECT_EQ(setup.thickness, 0.001);
  const report::ScanRules& r = setup.rules;
  ASSERT_EQ(r.pairs.size(), 2u);
  EXPECT_EQ(r.pairs[1].second, "pin");
  ASSERT_EQ(r.thickness.size(), 2u);  // the command line's comes later and wins in RuleSet
  EXPECT_EQ(r.thickness[1].second, 0.004);
  EXPECT_EQ(r.no_self, std::vector<std::string>{"body"});
  ASSERT_EQ(r.allow.size(), 2u);
  EXPECT_EQ(r.allow[0].object_a, "cloth");  // the manifest's rules first
  EXPECT_EQ(r.allow[1].kind, EventKind::kIntersection);
  EXPECT_EQ(r.neighbourhood, 0u);
  EXPECT_EQ(r.fail.events, 1u);
  EXPECT_EQ(r.fail.tracks, 2u);

  const ScanSetup thick = resolve_scan_setup(line.cache, line.rules, 0.5);
  EXPECT_EQ(thick.thickness, 0.5);
}

TEST_F(ManifestDir, ManifestInputsAndCommandLineInputsAreAUsageError) {
  const std::string path = write(kManifest);
  for (std::vector<std::string> args : {std::vector<std::string>{"--manifest", path, "x.obj"},
                                        {"--manifest", path, "--name", "x"},
                                        {"--manifest", path, "--topology", "t.obj"},
                                        {"--manifest", path, "--sequence"}}) {
    CommandLine line(args);
    EXPECT_THROW(resolve_scan_setup(line.cache, line.rules, std::nullopt), UsageError) << args[2];
  }
}

TEST_F(ManifestDir, RulesOnlyManifestTakesTheCommandLinesInputs) {
  const std::string path = write("version: 1\nobjects:\n  - {name: a, self: false}\n");
  CommandLine line({"--manifest", path, "a.obj", "--name", "a"});
  const ScanSetup setup = resolve_scan_setup(line.cache, line.rules, std::nullopt);
  ASSERT_EQ(setup.cache.inputs.size(), 1u);
  EXPECT_EQ(setup.cache.inputs[0].name, "a");
  EXPECT_EQ(setup.rules.no_self, std::vector<std::string>{"a"});

  CommandLine none({"--manifest", path});
  EXPECT_THROW(resolve_scan_setup(none.cache, none.rules, std::nullopt), UsageError);
}

TEST_F(ManifestDir, BadManifestIsAnInputError) {
  const std::string path = write("version: 1\nfail: {events: many}\n");
  CommandLine line({"--manifest", path, "a.obj"});
  EXPECT_THROW(resolve_scan_setup(line.cache, line.rules, std::nullopt), InputError);
}

}  // namespace
}  // namespace snag::tools
