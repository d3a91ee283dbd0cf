#include <sstream>
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

// The reader numbers lines as an editor does (blank and comment lines counted, not given),
// finds columns by the header's names, and reads '#' as a comment only when asked.
TEST(CsvReader, GivesRowsWithTheirLineNumbersAndFindsColumnsByName) {
  std::istringstream in("frame,u_min , v_min\r\n\n# a note\n 3, 10,20\r\n \t\n4,11,21\n");
  CsvReader reader(in, "t.csv", true);
  Fields f;
  ASSERT_TRUE(reader.next(f));
  EXPECT_EQ(reader.lineNumber(), 1u);
  reader.setHeader(f);
  EXPECT_EQ(reader.column("u_min"), 1u);
  EXPECT_EQ(reader.column("v_min"), 2u);
  EXPECT_FALSE(reader.column("u_max").has_value());
  ASSERT_TRUE(reader.next(f));
  EXPECT_EQ(f, (Fields{"3", "10", "20"}));
  EXPECT_EQ(reader.where(), "t.csv:4");
  ASSERT_TRUE(reader.next(f));
  EXPECT_EQ(f, (Fields{"4", "11", "21"}));
  EXPECT_EQ(reader.lineNumber(), 6u);
  EXPECT_FALSE(reader.next(f));

  std::istringstream with_hash("a\n#b,c\n");
  CsvReader plain(with_hash, "p.csv");
  ASSERT_TRUE(plain.next(f));
  ASSERT_TRUE(plain.next(f));
  EXPECT_EQ(f, (Fields{"#b", "c"})) << "a '#' line is a row unless comments are asked for";
  EXPECT_EQ(plain.where(), "p.csv:2");
}

}  // namespace
}  // namespace lidarseg::eval
