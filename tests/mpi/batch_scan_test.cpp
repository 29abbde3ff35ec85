// The batch list and the split of its scenes over ranks, against hand-made
// lists and hand-worked assignments.
#include <gtest/gtest.h>

#include <fstream>

#include "libcd/core/error.hpp"
#include "tests/tools/run_process.hpp"
#include "tools/common/batch_scan.hpp"

namespace snag::tools {
namespace {

std::string write(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

TEST(AssignBySize, LargestFirstToTheLeastLoadedRank) {
  // 5 -> r0 (5); 4 -> r1 (4); 3 -> r1 (7); 3 -> r0 (8); 2 -> r1 (9); 1 -> r0 (9).
  const auto assigned = assign_by_size({5, 4, 3, 3, 2, 1}, 2);
  ASSERT_EQ(assigned.size(), 2u);
  EXPECT_EQ(assigned[0], (std::vector<std::size_t>{0, 3, 5}));
  EXPECT_EQ(assigned[1], (std::vector<std::size_t>{1, 2, 4}));
}

TEST(AssignBySize, MoreRanksThanScenesLeavesRanksIdleAndEqualSizesKeepListOrder) {
  const auto assigned = assign_by_size({7, 7}, 3);
  EXPECT_EQ(assigned[0], (std::vector<std::size_t>{0}));
  EXPECT_EQ(assigned[1], (std::vector<std::size_t>{1}));
  EXPECT_TRUE(assigned[2].empty());
}

TEST(ReadBatchList, SkipsCommentsAndTakesPathsFromTheListsDirectory) {
  const test::TemporaryDirectory temporary;
  const std::string dir = temporary.path();
  const std::string list = write(dir + "/list.txt", "# shots\n\n  shot_a/scene.yaml  \n/abs/cloth_%04d.obj\r\n");
  const auto scenes = read_batch_list(list, "out");
  ASSERT_EQ(scenes.size(), 2u);
  EXPECT_EQ(scenes[0].input, dir + "/shot_a/scene.yaml");
  EXPECT_TRUE(scenes[0].manifest);
  EXPECT_EQ(scenes[0].report, "out/scene.jsonl");
  EXPECT_EQ(scenes[0].line, 3u);
  EXPECT_EQ(scenes[1].input, "/abs/cloth_%04d.obj");
  EXPECT_FALSE(scenes[1].manifest);
  EXPECT_EQ(scenes[1].report, "out/cloth__04d.jsonl");
}

TEST(ReadBatchList, RejectsTwoScenesOfOneReportNameAndAnEmptyList) {
  const test::TemporaryDirectory temporary;
  const std::string dir = temporary.path();
  const std::string clash = write(dir + "/clash.txt", "a/scene.yaml\nb/scene.yaml\n");
  try {
    read_batch_list(clash, "out");
    FAIL() << "two scenes named scene were accepted";
  } catch (const InputError& error) {
    EXPECT_EQ(error.where().file, clash);
    EXPECT_EQ(error.where().line, 2u);
    EXPECT_NE(std::string(error.what()).find("line 1"), std::string::npos) << error.what();
  }
  EXPECT_THROW(read_batch_list(write(dir + "/empty.txt", "# nothing\n"), "out"), InputError);
  EXPECT_THROW(read_batch_list(dir + "/missing.txt", "out"), InputError);
}

}  // namespace
}  // namespace snag::tools
