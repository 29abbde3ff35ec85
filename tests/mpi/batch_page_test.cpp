// A batch's summary becomes one page: snag-scan --batch writes DIR/batch.txt,
// snag-report --list reads it (paths from the list's directory). The oracle
// is the batch itself: the page shows every report it made, with the
// verdicts snag-report prints for the same reports given one by one; a
// list line naming no report is exit 2 with the list, the line and why.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/tools/run_process.hpp"
#include "tests/tools/sample_paths.hpp"

namespace snag::test {
namespace {

class BatchPage : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TemporaryDirectory;
    const std::string list =
        dir_->write("list.txt", "# the sample twice\n" + kSampleDir + "/scene.yaml\n\n" + kObjPattern + "\n");
    const ProcessResult batch = run_process(
        SNAG_SCAN_EXE, {"--batch", list, "-b", "cpu", "-j", "1", "--frames", "20:24", "-q", "-r", dir_->path("out")});
    ASSERT_EQ(batch.exit_code, 1) << batch.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static TemporaryDirectory* dir_;
};
TemporaryDirectory* BatchPage::dir_ = nullptr;

TEST_F(BatchPage, TheSummaryListBecomesOnePageOfEveryReport) {
  const std::vector<std::string> reports = {dir_->path("out/scene.jsonl"), dir_->path("out/cloth_ball__04d.jsonl")};
  ASSERT_EQ(read_file(dir_->path("out/batch.txt")), "scene.jsonl\ncloth_ball__04d.jsonl\n");
  // Run from the test's directory, not out/: the list's paths are taken from its own.
  const ProcessResult page =
      run_process(SNAG_REPORT_EXE, {"--list", dir_->path("out/batch.txt"), "--html", dir_->path("page.html")});
  EXPECT_EQ(page.exit_code, 1) << page.err;  // the sample fails its manifest's rules
  const ProcessResult one_by_one = run_process(SNAG_REPORT_EXE, {reports[0], reports[1], "--html", dir_->path("args.html")});
  EXPECT_EQ(one_by_one.exit_code, 1) << one_by_one.err;
  EXPECT_EQ(page.out, one_by_one.out);  // a verdict line per report, in list order
  EXPECT_EQ(lines_of(page.out).size(), 2u) << page.out;
  const std::string html = read_file(dir_->path("page.html"));
  EXPECT_NE(html.find("</html>"), std::string::npos);
  for (const std::string& report : reports) EXPECT_NE(html.find(report), std::string::npos) << report;
  // Reports given as arguments come first, then the list's.
  const ProcessResult both = run_process(SNAG_REPORT_EXE, {reports[1], "--list", dir_->path("out/batch.txt")});
  EXPECT_EQ(both.exit_code, 1) << both.err;
  EXPECT_EQ(both.out.find("report: " + reports[1]), 0u) << both.out;
}

TEST_F(BatchPage, AListLineNamingNoReportIsExitTwoWithTheLine) {
  const std::string list = dir_->write("out/bad.txt", "scene.jsonl\n# a comment\n\nmissing.jsonl\n");
  ProcessResult r = run_process(SNAG_REPORT_EXE, {"--list", list, "--html", dir_->path("bad.html")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "snag-report: error: " + list + ":4: " + dir_->path("out/missing.jsonl") + ": no such report\n");
  EXPECT_EQ(r.out, "");
  const std::string directory = dir_->write("out/directory.txt", dir_->path("out") + "\n");
  r = run_process(SNAG_REPORT_EXE, {"--list", directory});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "snag-report: error: " + directory + ":1: " + dir_->path("out") + ": not a file\n");
  const std::string empty = dir_->write("out/empty.txt", "# nothing\n");
  r = run_process(SNAG_REPORT_EXE, {"--list", empty});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "snag-report: error: " + empty + ": the list names no report\n");
  r = run_process(SNAG_REPORT_EXE, {"--list", dir_->path("out/none.txt")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "snag-report: error: " + dir_->path("out/none.txt") + ": cannot read the list\n");
  r = run_process(SNAG_REPORT_EXE, {});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("REPORT... or --list FILE"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace snag::test
