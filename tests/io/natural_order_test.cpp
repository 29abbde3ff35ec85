#include <gtest/gtest.h>

#include <algorithm>

#include "io/mesh_scene.hpp"
#include "io/reader_support.hpp"

namespace snag::io {

TEST(NaturalOrder, ComparesDigitRunsAsNumbers) {
  std::vector<std::string> names = {"f_10.obj", "f_9.obj", "f_1.obj", "f_010a.obj", "f_100.obj", "e.obj"};
  std::sort(names.begin(), names.end(), natural_less);
  EXPECT_EQ(names, (std::vector<std::string>{"e.obj", "f_1.obj", "f_9.obj", "f_10.obj", "f_010a.obj", "f_100.obj"}));
  EXPECT_FALSE(natural_less("a", "a"));
  EXPECT_NE(natural_less("f_01", "f_1"), natural_less("f_1", "f_01"));  // total order
}

TEST(UniqueNames, RenamesRepeatsDeterministically) {
  std::vector<std::string> names = {"cloth", "body", "cloth", "cloth_2", "cloth"};
  make_names_unique(names);
  EXPECT_EQ(names, (std::vector<std::string>{"cloth", "body", "cloth_3", "cloth_2", "cloth_4"}));
}

TEST(Thousands, GroupsDigits) {
  EXPECT_EQ(with_thousands(4210), "4,210");
  EXPECT_EQ(with_thousands(999), "999");
  EXPECT_EQ(with_thousands(1234567), "1,234,567");
}

}  // namespace snag::io
