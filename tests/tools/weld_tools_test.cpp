// The tools on caches whose vertices are split per face corner, as FBX and
// Collada deliver them: without welding every pair of neighbouring faces is an
// event; welded, only the real contacts remain, reports name the file's
// vertex ids, snag-verify maps them back, and snag-info says what was joined.
// Also: an interrupted scan leaves an earlier report as it was.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/tools/report_json.hpp"
#include "tests/tools/run_process.hpp"
#include "tests/tools/sample_paths.hpp"

namespace snag::test {
namespace {

using nlohmann::json;

constexpr double kTimeout = 120;

/// A unit cube as an OBJ object with its own 4 vertices per face (24 "v"
/// lines, 12 triangles), turned about z by `angle` and moved by `offset`.
std::string split_cube_obj(const std::string& name, double angle, const double offset[3], int first_vertex) {
  const int faces[6][4][3] = {{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
                              {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},
                              {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}};
  std::ostringstream out;
  out.precision(17);
  out << "o " << name << "\n";
  const double c = std::cos(angle), s = std::sin(angle);
  for (const auto& face : faces) {
    for (const auto& p : face) {
      out << "v " << c * p[0] - s * p[1] + offset[0] << " " << s * p[0] + c * p[1] + offset[1] << " "
          << p[2] + offset[2] << "\n";
    }
  }
  for (int f = 0; f < 6; ++f) {
    const int v = first_vertex + 4 * f;
    out << "f " << v << " " << v + 1 << " " << v + 2 << "\nf " << v << " " << v + 2 << " " << v + 3 << "\n";
  }
  return out.str();
}

/// Three frames: cube "mover" turns and slides along x into cube "wall",
/// which stands still; in frame 2 they overlap.
class SplitCubes : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TemporaryDirectory;
    for (int f = 0; f < 3; ++f) {
      const double mover[3] = {1.25 * f, 0.05, 0.1}, wall[3] = {3, 0.3, 0.2};
      dir_->write("cubes_" + std::to_string(f) + ".obj",
                  split_cube_obj("mover", 0.2 * f, mover, 1) + split_cube_obj("wall", 0.1, wall, 25));
    }
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string pattern() { return dir_->path("cubes_%d.obj"); }

  /// snag-scan on the cubes with `options`; the report it wrote.
  static json scan(const std::vector<std::string>& options, const std::string& report) {
    std::vector<std::string> arguments{pattern(), "-q", "-r", report};
    arguments.insert(arguments.end(), options.begin(), options.end());
    const ProcessResult run = run_process(SNAG_SCAN_EXE, arguments, {kTimeout});
    EXPECT_FALSE(run.timed_out);
    EXPECT_TRUE(run.exit_code == 0 || run.exit_code == 1) << run.err;
    return load_report(report);
  }

  static std::size_t self_events(const json& report) {
    std::size_t count = 0;
    for (const json& e : report["events"]) count += e["a"]["object"] == e["b"]["object"];
    return count;
  }

  static TemporaryDirectory* dir_;
};

TemporaryDirectory* SplitCubes::dir_ = nullptr;

TEST_F(SplitCubes, FloodWithoutWelding) {
  const json report = scan({"--weld", "none"}, dir_->path("none.json"));
  EXPECT_GT(self_events(report), 100u);
  EXPECT_EQ(report["objects"][0]["weld"], "none");
  EXPECT_EQ(report["objects"][0]["vertices"], 24);
}

TEST_F(SplitCubes, ExactWeldLeavesOnlyTheRealContacts) {
  const json report = scan({"--weld", "exact"}, dir_->path("exact.json"));
  EXPECT_EQ(self_events(report), 0u);
  EXPECT_GT(report["summary"]["collisions"].get<std::size_t>(), 0u);
  EXPECT_GT(report["summary"]["intersections"].get<std::size_t>(), 0u);
  EXPECT_EQ(report["settings"]["weld"], "exact");
  for (const json& object : report["objects"]) {
    EXPECT_EQ(object["weld"], "exact");
    EXPECT_EQ(object["vertices"], 8);
    EXPECT_EQ(object["file_vertices"], 24);
    EXPECT_EQ(object["edges"], 18);
  }
  // Vertices are named by file ids (a welded vertex by the smallest of the
  // file vertices joined into it): below 24, edges smaller id first.
  for (const json& e : report["events"]) {
    for (const char* side : {"a", "b"}) {
      if (e[side].contains("vertex")) EXPECT_LT(e[side]["vertex"].get<int>(), 24);
      if (e[side].contains("edge")) {
        EXPECT_LT(e[side]["edge"][0].get<int>(), e[side]["edge"][1].get<int>());
        EXPECT_LT(e[side]["edge"][1].get<int>(), 24);
      }
    }
  }
}

TEST_F(SplitCubes, WeldWithinADistanceEqualsTheExactWeldHere) {
  const json exact = scan({"--weld", "exact"}, dir_->path("exact2.json"));
  const json distance = scan({"--weld", "1e-9"}, dir_->path("distance.json"));
  EXPECT_EQ(distance["objects"][0]["weld"], "distance 1e-09");
  EXPECT_EQ(distance["events"], exact["events"]);
}

TEST_F(SplitCubes, VerifyConfirmsAWeldedReportAndFindsNothingMissed) {
  const std::string report = dir_->path("verified.json");
  scan({"--weld", "exact"}, report);
  const ProcessResult run =
      run_process(SNAG_VERIFY_EXE, {report, pattern(), "--exhaustive"}, {kTimeout});  // the report's --weld
  EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
}

TEST_F(SplitCubes, VerifyRefusesAReportWeldedDifferently) {
  const std::string report = dir_->path("other.json");
  scan({"--weld", "exact"}, report);
  const ProcessResult run = run_process(SNAG_VERIFY_EXE, {report, pattern(), "--weld", "none"}, {kTimeout});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("give the same --weld"), std::string::npos) << run.err;
}

TEST_F(SplitCubes, InfoSaysWhatWasWelded) {
  const ProcessResult run = run_process(SNAG_INFO_EXE, {pattern(), "--weld", "exact"}, {kTimeout});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("welded 24 file vertices into 8 (exact)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("0 boundary edges, 0 non-manifold edges"), std::string::npos) << run.out;
  const ProcessResult plain = run_process(SNAG_INFO_EXE, {pattern()}, {kTimeout});
  EXPECT_EQ(plain.out.find("welded"), std::string::npos) << plain.out;
  EXPECT_NE(plain.out.find("24 boundary edges"), std::string::npos) << plain.out;
}

TEST(ReportFile, AnInterruptedScanLeavesTheEarlierReport) {
  TemporaryDirectory dir;
  const std::string report = dir.write("report.json", "the earlier report\n");
  // A scan far longer than the half second before the signal on any machine:
  // the cloth-ball step (92,230 triangles, about a second per step on one
  // thread) as a 20-frame sequence. The sample cache alone now scans in less.
  const std::string meshes = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/";
  std::vector<std::string> arguments = {"-s"};
  for (int step = 0; step < 10; ++step) {
    arguments.push_back(meshes + "cloth_ball92.ply");
    arguments.push_back(meshes + "cloth_ball93.ply");
  }
  arguments.insert(arguments.end(), {"-q", "--threads", "1", "-r", report});
  ProcessOptions options;
  options.timeout_seconds = kTimeout;
  options.signal_after_seconds = 0.5;
  for (int signal : {2, 15}) {  // SIGINT, SIGTERM
    options.signal = signal;
    const ProcessResult run = run_process(SNAG_SCAN_EXE, arguments, options);
    EXPECT_EQ(run.exit_code, 128 + signal) << run.err;
    EXPECT_EQ(read_file(report), "the earlier report\n");
    std::size_t files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir.path())) files += entry.exists();
    EXPECT_EQ(files, 1u) << "the temporary report was left behind";
  }
}

TEST_F(SplitCubes, AReportToAPipeIsWrittenIntoThePipe) {
  // A destination that is not a regular file (a pipe here; /dev/null or a
  // shell's process substitution alike) cannot be replaced: the report goes
  // into it, and the pipe stays a pipe.
  const std::string fifo = dir_->path("report.fifo");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const int reader = open(fifo.c_str(), O_RDONLY | O_NONBLOCK);  // lets the writer open it at once
  ASSERT_GE(reader, 0);
  const ProcessResult run =
      run_process(SNAG_SCAN_EXE, {pattern(), "--weld", "exact", "-q", "--fail-on", "0", "-r", fifo}, {kTimeout});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  std::string text;
  char buffer[4096];
  for (ssize_t n; (n = read(reader, buffer, sizeof buffer)) > 0;) text.append(buffer, static_cast<std::size_t>(n));
  close(reader);
  struct stat after {};
  ASSERT_EQ(stat(fifo.c_str(), &after), 0);
  EXPECT_TRUE(S_ISFIFO(after.st_mode));
  ASSERT_FALSE(text.empty()) << "nothing came through the pipe";
  EXPECT_EQ(parse_report_text(text)["summary"]["intersections"].get<std::size_t>(),
            scan({"--weld", "exact"}, dir_->path("plain.json"))["summary"]["intersections"].get<std::size_t>());
}

TEST_F(SplitCubes, AReportThroughASymbolicLinkReplacesItsTarget) {
  const std::string target = dir_->write("reports/target.json", "the earlier report\n");
  const std::string link = dir_->path("link.json");
  ASSERT_EQ(symlink(target.c_str(), link.c_str()), 0);
  const json report = scan({"--weld", "exact"}, link);
  struct stat after {};
  ASSERT_EQ(lstat(link.c_str(), &after), 0);
  EXPECT_TRUE(S_ISLNK(after.st_mode));
  EXPECT_EQ(load_report(target), report);
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir_->path("reports"))) files += entry.exists();
  EXPECT_EQ(files, 1u);
}

TEST(ReportFile, AReportThatCannotBeWrittenFailsBeforeTheScan) {
  std::vector<std::string> arguments = sample_pc2_inputs();
  arguments.insert(arguments.end(), {"-q", "-r", "/nonexistent-directory/report.json"});
  const ProcessResult run = run_process(SNAG_SCAN_EXE, arguments, {kTimeout});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("/nonexistent-directory/report.json"), std::string::npos) << run.err;
  EXPECT_EQ(lines_of(run.err).size(), 1u) << run.err;
}

}  // namespace
}  // namespace snag::test
