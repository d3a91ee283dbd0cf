#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "lidarseg/eval/Csv.h"

namespace lidarseg::eval {
namespace {

using Fields = std::vector<std::string>;

TEST(Csv, SplitsTrimsAndKeepsEmptyFields) {
  EXPECT_EQ(splitCsvLine("a,b,c"), (Fields{"a", "b", "c"}));
  EXPECT_EQ(splitCsvLine(" a ,\tb,c\r"), (Fields{"a", "b", "c"}));
  EXPECT_EQ(splitCsvLine("a,,c"), (Fields{"a", "", "c"}));
  EXPECT_EQ(splitCsvLine("a,b,"), (Fields{"a", "b", ""}));
  EXPECT_EQ(splitCsvLine(",a"), (Fields{"", "a"}));
  EXPECT_EQ(splitCsvLine("single"), (Fields{"single"}));
}

TEST(Csv, ABlankLineHasNoField) {
  EXPECT_TRUE(splitCsvLine("").empty());
  EXPECT_TRUE(splitCsvLine(" \t\r").empty());
}

}  // namespace
}  // namespace lidarseg::eval
