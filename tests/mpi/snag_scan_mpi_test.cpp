// snag-scan under mpirun on one host (loopback, CPU back end): at 2 and 3
// ranks the report is the one a single process writes, byte for byte but
// for the times and working-set estimates in the trailer (man snag-scan(1));
// the oracle is that single run.
// A rank that fails ends the run with its message and rank number, and no
// report is left where the full one is expected.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "tests/tools/run_process.hpp"
#include "tests/tools/sample_paths.hpp"

namespace snag::test {
namespace {

// Open MPI refuses root unless told; a 2-core machine needs oversubscription
// for 3 ranks; containers that forbid one process reading another's memory
// make shared memory's single copy warn (the ranks' messages are a few bytes).
void allow_mpirun() {
  setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  setenv("OMPI_MCA_btl_vader_single_copy_mechanism", "none", 1);
}

ProcessResult mpirun(int ranks, const std::vector<std::string>& arguments) {
  allow_mpirun();
  std::vector<std::string> all = {"-q", "--oversubscribe", "-n", std::to_string(ranks), SNAG_SCAN_EXE};
  all.insert(all.end(), arguments.begin(), arguments.end());
  ProcessOptions limits;
  limits.timeout_seconds = 120;
  return run_process(MPIEXEC_EXE, all, limits);
}

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// The report without what may differ (man snag-scan(1)): the trailer's
// "timing" value, and the stages' working-set estimates, which depend on
// what each process's buffers held before.
std::string without_process_measures(const std::string& report) {
  const std::size_t trailer = report.rfind("{\"record\":\"trailer\"");
  const std::size_t timing = report.find(",\"timing\":", trailer);
  EXPECT_NE(trailer, std::string::npos);
  EXPECT_NE(timing, std::string::npos);
  EXPECT_EQ(report.back(), '\n');
  static const std::regex peak("\"peak_memory_bytes\":[0-9]+");
  return report.substr(0, trailer) +
         std::regex_replace(report.substr(trailer, timing - trailer), peak, "\"peak_memory_bytes\":N");
}

// Nothing but `expected` in `dir`: no parts, no temporary report.
void expect_only(const std::string& dir, const std::vector<std::string>& expected) {
  std::vector<std::string> found;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) found.push_back(entry.path().filename());
  std::sort(found.begin(), found.end());
  std::vector<std::string> sorted = expected;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(found, sorted);
}

// One process, then mpirun at each count: same exit code, same report.
void expect_same_report(const std::vector<std::string>& arguments, const std::vector<int>& rank_counts) {
  TemporaryDirectory dir;
  const ProcessResult one = run_process(SNAG_SCAN_EXE, with(arguments, {"-q", "-r", dir.path("one.jsonl")}));
  ASSERT_TRUE(one.exit_code == 0 || one.exit_code == 1) << one.err;
  const std::string expected = without_process_measures(read_file(dir.path("one.jsonl")));
  for (int ranks : rank_counts) {
    const std::string name = std::to_string(ranks) + ".jsonl";
    const ProcessResult run = mpirun(ranks, with(arguments, {"-q", "-r", dir.path(name)}));
    EXPECT_EQ(run.exit_code, one.exit_code) << ranks << " ranks: " << run.err;
    EXPECT_EQ(run.err, "") << ranks << " ranks";
    const std::string report = read_file(dir.path(name));
    EXPECT_EQ(without_process_measures(report), expected) << ranks << " ranks";
    // Rank 0's time once the other ranks were done, among the times.
    static const std::regex after_last("\"timing\":\\{.*\"after_last_rank\":[0-9.e-]+");
    EXPECT_TRUE(std::regex_search(report.substr(report.rfind("{\"record\":\"trailer\"")), after_last)) << ranks;
  }
  std::vector<std::string> reports = {"one.jsonl"};
  for (int ranks : rank_counts) reports.push_back(std::to_string(ranks) + ".jsonl");
  expect_only(dir.path(), reports);
}

// The manifest's allow and fail rules and an event cap that falls in the
// last range. (Collisions re-decided at a pair's thickness: range_scan_test.)
TEST(SnagScanMpi, SampleReportIsTheSingleProcessOnesAtTwoAndThreeRanks) {
  expect_same_report({"--manifest", kSampleDir + "/scene.yaml", "-b", "cpu", "-j", "1", "--frames", "12:36",
                      "--max-events", "6000"},
                     {2, 3});
}

// A long synthetic cache: the problems move slowly, so tracks run across
// every range boundary.
TEST(SnagScanMpi, LongCacheReportIsTheSingleProcessOnesAtThreeRanks) {
  TemporaryDirectory cache;
  const ProcessResult made = run_process(
      "/usr/bin/env", {"python3", std::string(SNAG_SOURCE_DIR) + "/bench/report/make_long_cache.py", cache.path(), "90", "24"});
  ASSERT_EQ(made.exit_code, 0) << made.err;
  expect_same_report({cache.path("sheet.pc2"), "-t", cache.path("sheet.obj"), cache.path("floor.pc2"), "-t",
                      cache.path("floor.obj"), "-b", "cpu", "-j", "1", "--events", "regions"},
                     {3});
}

// Rank 0 merging at half a scan's cost: ranges of 2, 6 and 12 of the
// sample's 20 steps, each merged while its rank writes it.
TEST(SnagScanMpi, UnevenRangesForRankZerosMergeGiveTheSingleProcessReport) {
  setenv("SNAG_MPI_MERGE_COST", "0.5", 1);
  expect_same_report({"--manifest", kSampleDir + "/scene.yaml", "-b", "cpu", "-j", "1", "--frames", "16:36",
                      "--max-events", "6000"},
                     {3});
  unsetenv("SNAG_MPI_MERGE_COST");
}

// The merge cost set for rank 0 alone (as on several hosts, where mpirun
// passes on no variable it is not told to): every rank splits as rank 0 does.
TEST(SnagScanMpi, RankZerosMergeCostIsEveryRanks) {
  const std::vector<std::string> arguments = {"--manifest", kSampleDir + "/scene.yaml", "-b", "cpu", "-j", "1",
                                              "--frames", "16:36", "--max-events", "6000", "-q", "-r"};
  TemporaryDirectory dir;
  const ProcessResult one = run_process(SNAG_SCAN_EXE, with(arguments, {dir.path("one.jsonl")}));
  ASSERT_TRUE(one.exit_code == 0 || one.exit_code == 1) << one.err;
  allow_mpirun();
  std::vector<std::string> launch = {"-q", "--oversubscribe", "-n", "1", "/usr/bin/env", "SNAG_MPI_MERGE_COST=0.5",
                                     SNAG_SCAN_EXE};
  launch = with(with(launch, arguments), {dir.path("3.jsonl"), ":", "-n", "2", "/usr/bin/env", "-u",
                                          "SNAG_MPI_MERGE_COST", SNAG_SCAN_EXE});
  launch = with(with(launch, arguments), {dir.path("3.jsonl")});
  ProcessOptions limits;
  limits.timeout_seconds = 120;
  const ProcessResult run = run_process(MPIEXEC_EXE, launch, limits);
  EXPECT_EQ(run.exit_code, one.exit_code) << run.err;
  EXPECT_EQ(run.err, "");
  EXPECT_EQ(without_process_measures(read_file(dir.path("3.jsonl"))),
            without_process_measures(read_file(dir.path("one.jsonl"))));
}

TEST(SnagScanMpi, BadMergeCostIsAUsageError) {
  setenv("SNAG_MPI_MERGE_COST", "1.5", 1);
  TemporaryDirectory dir;
  const ProcessResult run = mpirun(2, with(sample_pc2_inputs(), {"-b", "cpu", "-q", "-r", dir.path("r.jsonl")}));
  unsetenv("SNAG_MPI_MERGE_COST");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err, "snag-scan: error: rank 0: SNAG_MPI_MERGE_COST: expected a number from 0 to 0.9, not '1.5'\n");
  expect_only(dir.path(), {});
}

// Two steps over three ranks: the third has nothing to scan.
TEST(SnagScanMpi, MoreRanksThanStepsGiveTheSingleProcessReport) {
  expect_same_report(with(sample_pc2_inputs(), {"-b", "cpu", "-j", "1", "--frames", "24:26"}), {3});
}

// The last frame of an OBJ sequence is broken: the last rank fails reading it.
TEST(SnagScanMpi, FailingRankEndsTheRunWithItsMessageAndLeavesNoReport) {
  TemporaryDirectory dir;
  for (const auto& entry : std::filesystem::directory_iterator(kObjSequenceDir)) {
    std::filesystem::copy_file(entry.path(), dir.path(entry.path().filename()));
  }
  const std::string broken = dir.path("cloth_ball_0040.obj");
  ASSERT_TRUE(std::filesystem::exists(broken));
  dir.write("cloth_ball_0040.obj", "v 1 2 three\n");
  const std::string earlier = dir.write("report.jsonl", "an earlier report\n");
  const ProcessResult run = mpirun(3, {dir.path("cloth_ball_%04d.obj"), "-b", "cpu", "-j", "1", "-q", "-r", earlier});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err, "snag-scan: error: rank 2: " + broken + ":1: expected a number\n");
  EXPECT_EQ(read_file(earlier), "an earlier report\n");
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    const std::string name = entry.path().filename();
    files += 1;
    EXPECT_TRUE(name == "report.jsonl" || name.rfind("cloth_ball_", 0) == 0) << name << " was left behind";
  }
  EXPECT_EQ(files, 41u);
}

// Two scenes at two ranks (one each): the reports of a single-process batch,
// and a summary listing them in list order.
TEST(SnagScanMpi, BatchAtTwoRanksWritesTheSingleProcessReports) {
  TemporaryDirectory dir;
  const std::string list = dir.write("list.txt", "# the sample twice\n" + kSampleDir + "/scene.yaml\n" + kObjPattern + "\n");
  const std::vector<std::string> arguments = {"--batch", list, "-b", "cpu", "-j", "1", "--frames", "20:30", "-q", "-r"};
  const ProcessResult one = run_process(SNAG_SCAN_EXE, with(arguments, {dir.path("one")}));
  ASSERT_EQ(one.exit_code, 1) << one.err;
  const ProcessResult two = mpirun(2, with(arguments, {dir.path("two")}));
  EXPECT_EQ(two.exit_code, 1) << two.err;
  EXPECT_EQ(two.err, "");
  for (const std::string name : {"scene.jsonl", "cloth_ball__04d.jsonl"}) {
    EXPECT_EQ(without_process_measures(read_file(dir.path("two/" + name))),
              without_process_measures(read_file(dir.path("one/" + name))))
        << name;
  }
  EXPECT_EQ(read_file(dir.path("two/batch.txt")), "scene.jsonl\ncloth_ball__04d.jsonl\n");
}

// A scene that cannot be read: the rank that had it names itself, and no batch summary is written.
TEST(SnagScanMpi, BatchWithABadSceneFailsWithTheRankAndNoSummary) {
  TemporaryDirectory dir;
  const std::string broken = dir.write("broken.obj", "v 1 2 three\n");
  const std::string list = dir.write("list.txt", kSampleDir + "/scene.yaml\nbroken.obj\n");
  const ProcessResult run =
      mpirun(2, {"--batch", list, "-b", "cpu", "-j", "1", "--frames", "20:22", "-q", "-r", dir.path("out")});
  EXPECT_EQ(run.exit_code, 2);
  // The larger scene (the sample) goes to rank 0, the broken file to rank 1.
  EXPECT_EQ(run.err, "snag-scan: error: rank 1: " + broken + ":1: expected a number\n");
  EXPECT_FALSE(std::filesystem::exists(dir.path("out/batch.txt")));
  EXPECT_FALSE(std::filesystem::exists(dir.path("out/broken.jsonl")));
}

// Every rank parses the command line; only rank 0 says what is wrong with it.
TEST(SnagScanMpi, UsageErrorIsPrintedOnce) {
  const ProcessResult run = mpirun(2, {"--no-such-option"});
  EXPECT_EQ(run.exit_code, 2);
  const std::string message = "--no-such-option";
  const std::size_t first = run.err.find(message);
  ASSERT_NE(first, std::string::npos) << run.err;
  EXPECT_EQ(run.err.find(message, first + 1), std::string::npos) << run.err;
}

}  // namespace
}  // namespace snag::test
