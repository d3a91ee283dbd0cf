// Reading real MRPT rawlogs, and what a damaged one gets.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/mrpt/RawlogScanReader.h"
#include "lidarseg/mrpt/ScanConverter.h"

namespace lidarseg::mrpt_adapter {
namespace {
namespace fs = std::filesystem;

const std::string kTelecom =
    std::string(LIDARSEG_MRPT_DATASETS_DIR) + "/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
const std::string kIntel = std::string(LIDARSEG_SHARED_DATASETS_DIR) + "/intel-mrpt/intel.rawlog";

TEST(RawlogScanReader, EveryScanOfTheRealTelecomLogSegments) {
  if (!fs::exists(kTelecom)) GTEST_SKIP() << "missing " << kTelecom << " (Debian mrpt-common)";
  RawlogScanReader reader(kTelecom);
  ScanConverter converter;
  const ScanSegmenter segmenter;
  Segmentation seg;
  std::size_t scans = 0;
  std::array<double, kNumCascadeLevels> totals{};
  while (auto item = reader.next()) {
    const Scan scan = converter.convert(*item->observation);
    ASSERT_NO_THROW(segmenter.process(scan, seg)) << "scan " << scans;
    for (std::size_t l = 0; l < kNumCascadeLevels; ++l) {
      totals[l] += static_cast<double>(seg.levels[l].segments.size());
      if (l > 0) {
        EXPECT_LE(seg.levels[l].segments.size(), seg.levels[l - 1].segments.size());
      }
    }
    EXPECT_GT(seg.levels[3].segments.size(), 0u) << "scan " << scans << " has no high-level segment";
    ++scans;
  }
  EXPECT_EQ(scans, 225u);
  EXPECT_EQ(reader.labelsSeen().size(), 1u);
  // The cascade reduces the number of segments (paper Fig. 4: fewer, longer segments).
  EXPECT_LT(totals[3], totals[0]);
  for (std::size_t l = 0; l < kNumCascadeLevels; ++l) {
    RecordProperty("mean_segments_level" + std::to_string(l),
                   std::to_string(totals[l] / static_cast<double>(scans)));
  }
}

// The share of the (gzip) file read, a progress's time left: from 0, never back, a small
// share after the first of 225 scans, about half at the middle one (uncompressed bytes
// against the trailer's size: MRPT's position and size of a gzip stream are in different
// units, and gave 1 at a third of the log), all of it at the end.
TEST(RawlogScanReader, TheShareReadGrowsToOne) {
  if (!fs::exists(kTelecom)) GTEST_SKIP() << "missing " << kTelecom << " (Debian mrpt-common)";
  RawlogScanReader reader(kTelecom);
  EXPECT_EQ(reader.fractionRead(), 0.0);
  double last = 0.0, after_first = -1.0, middle = -1.0;
  std::size_t n = 0;
  while (reader.next()) {
    const double f = reader.fractionRead();
    EXPECT_GE(f, last) << "scan " << n;
    if (n == 0) after_first = f;
    if (n == 112) middle = f;
    ++n;
    last = f;
  }
  EXPECT_EQ(n, 225u);
  EXPECT_GT(after_first, 0.0);
  EXPECT_LT(after_first, 0.05);
  EXPECT_GT(middle, 0.35);
  EXPECT_LT(middle, 0.65);
  EXPECT_GT(last, 0.99);
}

TEST(RawlogScanReader, ReadsTheSensoryFrameLayoutOfTheIntelLog) {
  if (!fs::exists(kIntel)) GTEST_SKIP() << "missing " << kIntel;
  RawlogScanReader reader(kIntel);
  std::size_t scans = 0;
  while (scans < 200) {
    auto item = reader.next();
    ASSERT_TRUE(item.has_value());
    EXPECT_EQ(item->observation->getScanSize(), 180u);
    ++scans;
  }
  EXPECT_GT(reader.entriesRead(), scans);  // actions and sensory frames alternate
}

// Decision 49: a label no scan has is an error at the end, naming the file and the labels.
TEST(RawlogScanReader, UnknownLabelIsAnErrorListingTheLogsLabels) {
  if (!fs::exists(kTelecom)) GTEST_SKIP() << "missing " << kTelecom;
  RawlogScanReader reader(kTelecom, "NO_SUCH_LASER");
  try {
    reader.next();
    FAIL() << "an unknown label read without error";
  } catch (const std::runtime_error& e) {
    ASSERT_EQ(reader.labelsSeen().size(), 1u);
    EXPECT_NE(std::string(e.what()).find("rawlog '" + kTelecom + "': no laser scan labelled 'NO_SUCH_LASER' (its laser "
                                         "labels: '" + reader.labelsSeen()[0] + "')"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(reader.next().has_value());
}

TEST(RawlogScanReader, TruncatedFileKeepsEarlierScansThenNamesFileAndEntry) {
  if (!fs::exists(kTelecom)) GTEST_SKIP() << "missing " << kTelecom;
  std::ifstream in(kTelecom, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/truncated.rawlog";
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<long>(bytes.size() / 2));
  RawlogScanReader reader(path);
  std::size_t scans = 0;
  try {
    while (reader.next()) ++scans;
    FAIL() << "no error for a truncated file";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("truncated.rawlog"), std::string::npos) << msg;
    EXPECT_NE(msg.find("entry"), std::string::npos) << msg;
  }
  EXPECT_GT(scans, 50u);
  EXPECT_LT(scans, 225u);
}

TEST(RawlogScanReader, GarbageAndMissingFilesAreClearErrors) {
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/garbage.rawlog";
  std::ofstream(path, std::ios::binary) << std::string(1000, '\x5a');
  RawlogScanReader reader(path);
  try {
    reader.next();
    FAIL() << "no error for garbage";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("garbage.rawlog', entry 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(RawlogScanReader("/nonexistent/x.rawlog"), std::runtime_error);
  const std::string empty = std::string(LIDARSEG_TEST_TMP_DIR) + "/empty.rawlog";
  std::ofstream(empty, std::ios::binary).close();
  RawlogScanReader empty_reader(empty);
  EXPECT_FALSE(empty_reader.next().has_value());
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
