// snag-volume end to end on the cloth_ball sample (frames 24 to 32, where the
// ball pushes through the folded cloth): every intersection region gets the
// measure its objects call for, everything else of the report is copied, the
// .vdb files read back with OpenVDB's reader, --frames limits the work, and
// bad input exits 2 with one line.
#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <filesystem>
#include <set>
#include <nlohmann/json.hpp>

#include "tests/tools/report_json.hpp"
#include "tests/tools/run_process.hpp"
#include "tests/tools/sample_paths.hpp"

namespace snag::test {
namespace {

using nlohmann::json;

std::vector<std::string> with(std::vector<std::string> first, const std::vector<std::string>& then) {
  first.insert(first.end(), then.begin(), then.end());
  return first;
}

class SnagVolumeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    openvdb::initialize();
    dir_ = new TemporaryDirectory;
    const ProcessResult scan = run_process(
        SNAG_SCAN_EXE, with(sample_pc2_inputs(), {"--frames", "24:32", "-q", "--fail-on", "0", "-r", report()}));
    ASSERT_EQ(scan.exit_code, 0) << scan.err;
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string report() { return dir_->path("scan.jsonl"); }

  static TemporaryDirectory* dir_;
};
TemporaryDirectory* SnagVolumeTest::dir_ = nullptr;

TEST_F(SnagVolumeTest, MeasuresEveryIntersectionRegionAndCopiesTheRest) {
  const std::string out = dir_->path("volume.jsonl"), vdb = dir_->path("vdb");
  const ProcessResult run =
      run_process(SNAG_VOLUME_EXE, with({report()}, with(sample_pc2_inputs(), {"-o", out, "--vdb", vdb})));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json scanned = load_report(report()), measured = load_report(out);
  EXPECT_EQ(measured["header"]["tool"], "snag-volume");
  EXPECT_EQ(measured["events"], scanned["events"]);
  EXPECT_EQ(measured["tracks"], scanned["tracks"]);
  EXPECT_EQ(measured["frames"], scanned["frames"]);
  ASSERT_EQ(measured["regions"].size(), scanned["regions"].size());

  std::size_t penetrations = 0, curves = 0;
  std::set<std::size_t> body_frames;
  for (std::size_t i = 0; i < measured["regions"].size(); ++i) {
    json region = measured["regions"][i];
    const bool intersection = region["kind"] == "intersection";
    ASSERT_EQ(region.contains("measures"), intersection) << region.dump();
    if (!intersection) continue;
    const json m = region["measures"];
    region.erase("measures");
    EXPECT_EQ(region, scanned["regions"][i]) << "the region itself is copied";
    if (region["objects"] == json::array({"cloth", "body"})) {
      // The cloth is open, the ball closed: the cloth's penetration.
      EXPECT_EQ(m["measure"], "penetration");
      EXPECT_NE(m["reason"].get<std::string>().find("cloth is open"), std::string::npos) << m.dump();
      EXPECT_NE(m["reason"].get<std::string>().find("body is closed"), std::string::npos) << m.dump();
      EXPECT_GT(m["depth"].get<double>(), 0);
      EXPECT_GT(m["area"].get<double>(), 0);
      EXPECT_GT(m["voxel_size"].get<double>(), 0);
      EXPECT_LT(m["depth_error"].get<double>(), m["depth"].get<double>()) << m.dump();
      body_frames.insert(region["frame"].get<std::size_t>());
      ++penetrations;
    } else {
      EXPECT_EQ(m["measure"], "curve_length");
      EXPECT_GT(m["curve_length"].get<double>(), 0);
      EXPECT_GT(m["segments"].get<std::size_t>(), 0u);
      ++curves;
    }
  }
  EXPECT_GT(penetrations, 3u);
  EXPECT_GT(curves, 10u);
  EXPECT_NE(run.out.find("penetration"), std::string::npos);

  // One .vdb per frame with a body region, the ball's level set in it.
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(vdb)) {
    ++files;
    openvdb::io::File file(entry.path().string());
    file.open();
    openvdb::GridBase::Ptr body = file.readGrid("body");
    const std::size_t frame = static_cast<std::size_t>(file.getMetadata()->metaValue<openvdb::Int64>("snag_frame"));
    file.close();
    EXPECT_EQ(body->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_GT(body->activeVoxelCount(), 0u);
    EXPECT_EQ(body_frames.count(frame), 1u) << entry.path();
  }
  EXPECT_EQ(files, body_frames.size());
}

TEST_F(SnagVolumeTest, FramesLimitWhichRegionsAreMeasured) {
  const std::string out = dir_->path("frame30.jsonl");
  const ProcessResult run =
      run_process(SNAG_VOLUME_EXE, with({report()}, with(sample_pc2_inputs(), {"-o", out, "--frames", "30", "-q"})));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out, "");
  std::size_t measured = 0;
  const json written = load_report(out);
  for (const json& region : written["regions"]) {
    if (!region.contains("measures")) continue;
    EXPECT_EQ(region["frame"], 30);
    ++measured;
  }
  EXPECT_GT(measured, 0u);
}

TEST_F(SnagVolumeTest, BadInputExitsTwoWithOneLine) {
  const ProcessResult missing = run_process(SNAG_VOLUME_EXE, with({dir_->path("none.jsonl")}, sample_pc2_inputs()));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("none.jsonl"), std::string::npos) << missing.err;
  EXPECT_EQ(lines_of(missing.err).size(), 1u) << missing.err;

  // The cloth alone is not the report's cache.
  const ProcessResult wrong = run_process(SNAG_VOLUME_EXE, {report(), kClothPc2, "-t", kClothRest});
  EXPECT_EQ(wrong.exit_code, 2);
  EXPECT_NE(wrong.err.find("not the cache of this report"), std::string::npos) << wrong.err;
  EXPECT_EQ(lines_of(wrong.err).size(), 1u) << wrong.err;

  const ProcessResult voxel = run_process(SNAG_VOLUME_EXE, with({report()}, with(sample_pc2_inputs(), {"--voxel-size", "-1"})));
  EXPECT_EQ(voxel.exit_code, 2);
}

}  // namespace
}  // namespace snag::test
