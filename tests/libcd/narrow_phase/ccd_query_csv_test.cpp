// The CCD query reader against hand-made files.
#include "io/ccd_query_csv.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "libcd/core/error.hpp"

namespace snag {
namespace {

namespace fs = std::filesystem;

class CcdQueryCsv : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::path(SNAG_BINARY_DIR) / "test-data" / "ccd_query_csv" /
            ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  std::string write(const std::string& name, const std::string& text) {
    const fs::path path = root_ / name;
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path.string();
  }
  static std::string query(int truth, const std::string& first_row = "1,2,-3,4,5,1") {
    std::string text;
    for (int row = 0; row < 8; ++row) {
      text += (row == 0 ? first_row : "0,1,0,1,0,1") + "," + std::to_string(truth) + "\n";
    }
    return text;
  }
  fs::path root_;
};

TEST_F(CcdQueryCsv, ReadsExactCoordinatesAndTruth) {
  const std::string huge_denominator = "2596148429267413814265248164610048";  // 2^111
  const std::string path = write("q.csv", query(1, "1,2,-3,4,7," + huge_denominator) + query(0));
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_csv(path, true);
  ASSERT_EQ(queries.size(), 2u);
  EXPECT_TRUE(queries[0].is_edge_edge);
  EXPECT_TRUE(queries[0].truth);
  EXPECT_FALSE(queries[1].truth);
  EXPECT_EQ(queries[0].line, 1u);
  EXPECT_EQ(queries[1].line, 9u);
  EXPECT_EQ(queries[0].points[0].x, 0.5);
  EXPECT_EQ(queries[0].points[0].y, -0.75);
  EXPECT_EQ(queries[0].points[0].z, std::ldexp(7.0, -111));
  EXPECT_EQ(queries[0].exact[0][2].numerator, 7);
  EXPECT_EQ(queries[0].exact[0][2].denominator_log2, 111);
  EXPECT_EQ(queries[0].exact[0][2].denominator_text, huge_denominator);
  EXPECT_EQ(queries[0].exact[0][1].numerator_text, "-3");
}

void expect_error_at_line(const std::string& path, std::size_t line) {
  try {
    io::read_ccd_query_csv(path, false);
    ADD_FAILURE() << "no InputError for " << path;
  } catch (const InputError& error) {
    EXPECT_EQ(error.where().file, path);
    EXPECT_EQ(error.where().line, line) << error.what();
  }
}

TEST_F(CcdQueryCsv, RejectsAWrongColumnCount) { expect_error_at_line(write("q.csv", query(0) + "1,1,1\n"), 9); }

TEST_F(CcdQueryCsv, RejectsADenominatorThatIsNotAPowerOfTwo) {
  expect_error_at_line(write("q.csv", query(0, "1,3,0,1,0,1")), 1);
  expect_error_at_line(write("z.csv", query(0, "1,0,0,1,0,1")), 1);
}

TEST_F(CcdQueryCsv, RejectsANumeratorThatIsNotExactAsADouble) {
  expect_error_at_line(write("q.csv", query(0, "9007199254740993,1,0,1,0,1")), 1);  // 2^53 + 1
  expect_error_at_line(write("r.csv", query(0, "99999999999999999999,1,0,1,0,1")), 1);
  expect_error_at_line(write("s.csv", query(0, "x1,1,0,1,0,1")), 1);
}

TEST_F(CcdQueryCsv, RejectsATruthThatChangesWithinAQuery) {
  std::string text = query(1);
  text.replace(text.rfind('1'), 1, "0");  // the last row says 0
  expect_error_at_line(write("q.csv", text), 8);
}

TEST_F(CcdQueryCsv, RejectsATruncatedQuery) {
  const std::string text = query(0) + "0,1,0,1,0,1,0\n0,1,0,1,0,1,0\n";
  expect_error_at_line(write("q.csv", text), 10);
}

TEST_F(CcdQueryCsv, WalksAFolderTreeAndTakesTheKindFromTheFolder) {
  write("scene/vertex-face/data_0.csv", query(1));
  write("scene/edge-edge/data_0.csv", query(0) + query(1));
  write("scene/other/data_0.csv", "not a query file");
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(root_.string());
  ASSERT_EQ(queries.size(), 3u);
  EXPECT_TRUE(queries[0].is_edge_edge);  // sorted: edge-edge before vertex-face
  EXPECT_TRUE(queries[1].is_edge_edge);
  EXPECT_FALSE(queries[2].is_edge_edge);
  EXPECT_THROW(io::read_ccd_query_tree((root_ / "missing").string()), InputError);
}

}  // namespace
}  // namespace snag
