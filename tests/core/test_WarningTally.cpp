// WarningTally: every warning counted under its kind in full, the messages and the kinds
// bounded (issue 16: a log of a million odd lines gives a bounded summary with true counts).
#include <string>

#include <gtest/gtest.h>

#include "lidarseg/core/WarningTally.h"

namespace lidarseg {
namespace {

// A kind name without digits, different for each i.
std::string letters(std::size_t i) {
  std::string s;
  do {
    s += static_cast<char>('a' + i % 26);
    i /= 26;
  } while (i > 0);
  return s;
}

TEST(WarningTally, AKindIsTheTextAfterThePlaceWithItsNumbersAsHashes) {
  EXPECT_EQ(WarningTally::kindOf("log.clf:7: time gap of 4.900000 s; the prior restarts"),
            "time gap of #.# s; the prior restarts");
  EXPECT_EQ(WarningTally::kindOf("rawlog 'a.rawlog', entry 12: a robot movement is not finite; not used"),
            "a robot movement is not finite; not used");
  EXPECT_EQ(WarningTally::kindOf("F:3: wheel odometry jumps by 2.5 m / -0.5 rad"),
            WarningTally::kindOf("F:9: wheel odometry jumps by 0.1 m / 3.1 rad"));
  EXPECT_EQ(WarningTally::kindOf("no place here 42"), "no place here #");
  EXPECT_LE(WarningTally::kindOf("F:1: " + std::string(10000, 'x')).size(), 120u);
}

// The cut at 120 bytes never splits a UTF-8 character (a sensor label or line type in
// another script): the JSON writers refuse an invalid sequence.
TEST(WarningTally, AKindIsNeverCutInsideAUtf8Character) {
  const std::string e_acute = "\xC3\xA9", han = "\xE6\xBC\xA2";
  for (std::size_t pad = 110; pad < 125; ++pad) {
    for (const std::string& ch : {e_acute, han}) {
      std::string text;
      for (int i = 0; i < 20; ++i) text += ch;
      const std::string kind = WarningTally::kindOf("F:1: " + std::string(pad, 'x') + text);
      ASSERT_LE(kind.size(), 121u);
      // Every character whole: lead bytes followed by their continuation bytes.
      std::size_t i = 0;
      while (i < kind.size()) {
        const unsigned char b = static_cast<unsigned char>(kind[i]);
        const std::size_t n = b < 0x80 ? 1 : b >= 0xE0 ? 3 : 2;
        ASSERT_LE(i + n, kind.size()) << "pad " << pad << ": a character cut at the end";
        i += n;
      }
    }
  }
}

TEST(WarningTally, EveryKindIsCountedInFullWhileTheMessagesAreCapped) {
  WarningTally t;
  for (int i = 0; i < 1000; ++i) t.add("log:" + std::to_string(i) + ": time gap of 2." + std::to_string(i) + " s");
  t.add("log:5000: the laser 'LMS' changes its beam count (181 -> 361 beams)");
  EXPECT_EQ(t.total(), 1001u);
  EXPECT_EQ(t.messages().size(), WarningTally::kKeptMessages);
  EXPECT_EQ(t.messages().front(), "log:0: time gap of 2.0 s");
  ASSERT_EQ(t.kinds().size(), 2u);
  EXPECT_EQ(t.kinds()[0].kind, "time gap of #.# s");
  EXPECT_EQ(t.kinds()[0].count, 1000u);
  EXPECT_EQ(t.kinds()[0].first, "log:0: time gap of 2.0 s");
  EXPECT_EQ(t.kinds()[1].count, 1u);
  EXPECT_EQ(t.kinds()[1].first, "log:5000: the laser 'LMS' changes its beam count (181 -> 361 beams)");
}

TEST(WarningTally, KindsBeyondTheCapAreCountedTogetherAsOtherKinds) {
  WarningTally t;
  const std::size_t distinct = 3 * WarningTally::kMaxKinds;
  for (std::size_t i = 0; i < distinct; ++i) {
    for (int k = 0; k < 2; ++k) t.add("log:1: line of unknown type '" + letters(i) + "' skipped");
  }
  const auto kinds = t.kinds();
  ASSERT_EQ(kinds.size(), WarningTally::kMaxKinds + 1);
  EXPECT_EQ(kinds.back().kind, WarningTally::kOtherKinds);
  EXPECT_EQ(kinds.back().count, 2 * (distinct - WarningTally::kMaxKinds));
  EXPECT_EQ(kinds.front().count, 2u);
  std::size_t sum = 0;
  for (const auto& k : kinds) sum += k.count;
  EXPECT_EQ(sum, 2 * distinct) << "no warning lost";
  EXPECT_EQ(t.total(), 2 * distinct);
  EXPECT_EQ(t.countOf(WarningTally::kOtherKinds), 2 * (distinct - WarningTally::kMaxKinds));
  // A kind already counted by name keeps being counted by name after the cap is reached.
  t.add("log:9: line of unknown type 'a' skipped");
  EXPECT_EQ(t.countOf("line of unknown type 'a' skipped"), 3u);
}

TEST(WarningTally, MergeAddsTheCountsAndKeepsTheBound) {
  WarningTally a, b;
  for (int i = 0; i < 150; ++i) a.add("F:" + std::to_string(i) + ": time gap of 3 s");
  for (int i = 0; i < 70; ++i) b.add("F:" + std::to_string(i) + ": time gap of 4 s");
  b.count("an odometry reading is not finite; not used", 500, "rawlog 'r', entry 3: an odometry reading is not finite; not used");
  a.merge(b);
  EXPECT_EQ(a.countOf("time gap of # s"), 220u);
  EXPECT_EQ(a.countOf("an odometry reading is not finite; not used"), 500u);
  EXPECT_EQ(a.total(), 720u);
  EXPECT_EQ(a.messages().size(), WarningTally::kKeptMessages);
  EXPECT_EQ(a.kinds()[1].first, "rawlog 'r', entry 3: an odometry reading is not finite; not used");
}

}  // namespace
}  // namespace lidarseg
