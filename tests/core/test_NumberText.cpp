// Reading and writing numbers as text (core/NumberText.h).
#include "lidarseg/core/NumberText.h"

#include <gtest/gtest.h>

#include <clocale>
#include <cmath>

namespace lidarseg {
namespace {

using Status = ParsedNumber::Status;

TEST(ParseNumber, ReadsTheDecimalFormsTheProjectsFilesWrite) {
  EXPECT_EQ(parseNumber("1.5").value, 1.5);
  EXPECT_EQ(parseNumber("-0.25").value, -0.25);
  EXPECT_EQ(parseNumber("+2").value, 2.0);
  EXPECT_EQ(parseNumber(".5").value, 0.5);
  EXPECT_EQ(parseNumber("5.").value, 5.0);
  EXPECT_EQ(parseNumber("1e+05").value, 1e5);
  EXPECT_EQ(parseNumber("-1.5E-3").value, -1.5e-3);
  EXPECT_EQ(parseNumber("81.910000").value, 81.91);
  for (const char* t : {"1.5", "+2", ".5", "5.", "1e+05", "-1.5E-3"}) EXPECT_TRUE(parseNumber(t).ok()) << t;
}

TEST(ParseNumber, RefusesHexadecimalFloatsAndStrayCharacters) {
  // strtod reads all of these, or a prefix of them, as a number.
  for (const char* t : {"0x1p0", "0X1.8P1", "0x10", "-0x1p-3", "1.5abc", " 1", "1 ", "", "+", "-", "+-1",
                        "1e", "1e+", "1,5", "1.5.2", "--1"}) {
    const ParsedNumber r = parseNumber(t);
    EXPECT_EQ(r.status, Status::not_a_number) << "'" << t << "'";
    EXPECT_FALSE(r.ok()) << t;
    EXPECT_EQ(r.value, 0.0) << t;
  }
}

TEST(ParseNumber, SaysWhenAMagnitudeDoesNotFitADouble) {
  const ParsedNumber big = parseNumber("1e400");
  EXPECT_EQ(big.status, Status::out_of_range);
  EXPECT_TRUE(std::isinf(big.value));
  const ParsedNumber negative_big = parseNumber("-1e400");
  EXPECT_EQ(negative_big.status, Status::out_of_range);
  EXPECT_EQ(negative_big.value, -HUGE_VAL);
  const ParsedNumber tiny = parseNumber("1e-400");
  EXPECT_EQ(tiny.status, Status::out_of_range);
  EXPECT_EQ(tiny.value, 0.0);
  // The largest double still fits.
  EXPECT_TRUE(parseNumber("1.7976931348623157e308").ok());
}

TEST(ParseNumber, KeepsInfinityAndNanForTheCallersFinitenessChecks) {
  EXPECT_TRUE(parseNumber("inf").ok());
  EXPECT_EQ(parseNumber("-inf").value, -HUGE_VAL);
  EXPECT_TRUE(std::isnan(parseNumber("nan").value));
}

TEST(ParseNumber, DoesNotDependOnTheCLocalesDecimalPoint) {
  // A locale whose decimal point is a comma makes strtod stop at "1"; the parser reads
  // the files' '.' whatever the process's locale. The test runs only where such a locale
  // is installed.
  const char* const previous = std::setlocale(LC_NUMERIC, nullptr);
  const std::string saved = previous ? previous : "C";
  bool comma = false;
  for (const char* name : {"de_DE.UTF-8", "fr_FR.UTF-8", "de_DE", "fr_FR"}) {
    if (std::setlocale(LC_NUMERIC, name) != nullptr) { comma = true; break; }
  }
  if (!comma) GTEST_SKIP() << "no locale with a decimal comma installed";
  EXPECT_EQ(parseNumber("1.5").value, 1.5);
  EXPECT_TRUE(parseNumber("1.5").ok());
  std::setlocale(LC_NUMERIC, saved.c_str());
}

TEST(NumberText, WritesTheShortestTextThatReadsBack) {
  EXPECT_EQ(numberText(-1.0), "-1");
  EXPECT_EQ(numberText(0.3), "0.3");
  EXPECT_EQ(numberText(1e-9), "1e-09");
  EXPECT_EQ(parseNumber(numberText(0.1 + 0.2)).value, 0.1 + 0.2);
}

}  // namespace
}  // namespace lidarseg
