// The ScanSource interface (lidarseg/logs/ScanSource.h): the checks every format shares, and
// the CARMEN source read with no MRPT linked (this test links lidarseg::logs alone).
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "lidarseg/logs/CarmenScanSource.h"
#include "lidarseg/logs/ScanSource.h"

namespace lidarseg::logs {
namespace {

std::string tmp(const std::string& name) { return std::string(LIDARSEG_TEST_TMP_DIR) + "/" + name; }

// A format that hands out prepared records: what the base class does with them.
class ListedSource final : public ScanSource {
 public:
  explicit ListedSource(std::vector<ScanRecord> records) : ScanSource("listed"), records_(std::move(records)) {}
  std::string sensor() const override { return "LASER"; }
  double fractionRead() const override { return static_cast<double>(at_) / static_cast<double>(records_.size()); }

 protected:
  std::optional<ScanRecord> read() override {
    while (at_ < records_.size()) {
      ScanRecord r = records_[at_++];
      if (r.scan.size() == 0) {  // a record this format cannot use
        note(r.where + ": no beams; scan skipped");
        continue;
      }
      return r;
    }
    return std::nullopt;
  }

 private:
  std::vector<ScanRecord> records_;
  std::size_t at_ = 0;
};

ScanRecord record(const std::string& where, std::size_t beams, double mount_x = 0.0) {
  ScanRecord r;
  r.where = where;
  r.sensor = "LASER";
  if (beams > 0) {
    r.scan.layout = std::make_shared<BeamLayout>(BeamLayout::centred(beams, 2.0));
    r.scan.ranges_m.assign(beams, 2.0);
  }
  r.sensor_on_robot.x = mount_x;
  r.odometry = Pose2D{1.0, 2.0, 0.1};
  return r;
}

TEST(ScanSource, SharedChecksIndexSkipAndWarnWhateverTheFormat) {
  std::vector<ScanRecord> records = {record("listed:1", 181), record("listed:2", 0), record("listed:3", 181),
                                     record("listed:4", 181, 0.2), record("listed:5", 361)};
  records[2].odometry->yaw = std::numeric_limits<double>::quiet_NaN();
  ListedSource source(records);
  std::vector<std::size_t> indices;
  std::vector<bool> with_odometry;
  while (auto r = source.next()) {
    indices.push_back(r->index);
    with_odometry.push_back(r->odometry.has_value());
  }
  EXPECT_EQ(indices, (std::vector<std::size_t>{0, 1, 2, 3}));  // counted over the records returned
  EXPECT_EQ(with_odometry, (std::vector<bool>{true, false, true, true}));
  EXPECT_EQ(source.skipped(), 1u);
  ASSERT_EQ(source.issues().size(), 1u);
  EXPECT_EQ(source.issues()[0], "listed:2: no beams; scan skipped");
  const std::vector<std::string> w = source.warnings();
  ASSERT_EQ(w.size(), 2u);  // the non-finite odometry, and the first change of geometry only
  EXPECT_EQ(w[0], "listed:3: wheel odometry is not finite; not used");
  EXPECT_EQ(w[1].rfind("listed:4: the laser 'LASER' changes its beam count, aperture or mounting (181 -> 181 beams)", 0), 0u)
      << w[1];
  EXPECT_EQ(source.warningTally().total(), 2u);
}

TEST(ScanSource, ACarmenLogIsReadWithNoMrptInBetween) {
  const std::string path = tmp("scan_source.log");
  std::ofstream out(path);
  out << "# a comment\n"
      << "ODOM 1 2 0.1 0 0 0 10.0 host 10.0\n"
      << "FLASER 3 1.0 2.0 3.0 5 6 0.2 5 6 0.2 10.05 host 10.05\n"
      << "NOTATYPE 1 2 3\n"
      << "FLASER 1 1.0 5 6 0.2 5 6 0.2 10.1 host 10.1\n"
      << "FLASER 3 1.0 2.0 3.0 5.1 6 0.2 5.1 6 0.2 10.15 host 10.15\n";
  out.close();
  CarmenScanSource source(path, "");
  auto a = source.next();
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(a->where, path + ":3");
  EXPECT_EQ(a->index, 0u);
  EXPECT_EQ(a->sensor, "FLASER");
  EXPECT_DOUBLE_EQ(a->stamp_s, 10.05);
  ASSERT_EQ(a->scan.size(), 3u);
  EXPECT_DOUBLE_EQ(a->scan.ranges_m[2], 3.0);
  ASSERT_TRUE(a->odometry.has_value());
  EXPECT_DOUBLE_EQ(a->odometry->x, 1.0);  // the ODOM line's, not the laser line's own fields
  ASSERT_TRUE(a->log_pose.has_value());
  EXPECT_DOUBLE_EQ(a->log_pose->x, 5.0);
  auto b = source.next();
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->where, path + ":6");  // line 5's one-beam scan skipped with its place
  EXPECT_EQ(b->index, 1u);
  EXPECT_FALSE(source.next().has_value());
  EXPECT_EQ(source.sensor(), "FLASER");
  EXPECT_EQ(source.skipped(), 1u);
  ASSERT_EQ(source.issues().size(), 1u);
  EXPECT_EQ(source.issues()[0], path + ":5: FLASER: 1 beam(s) (need 2 or more) (line skipped)");  // the reader's own
  ASSERT_EQ(source.unknownTypes().size(), 1u);
  EXPECT_EQ(source.unknownTypes()[0], path + ": 1 line(s) of unknown type 'NOTATYPE' skipped");
  EXPECT_DOUBLE_EQ(source.fractionRead(), 1.0);
}

// ROBOTLASER1 gives the mounting only as the difference of the laser's and the robot's
// poses, each rounded to its printed digits: compared exactly, it "changed" as soon as the
// robot turned, a false warning on every such log (issue 16). Within 5 mm and 0.25 degree it
// is the same; a real change (10 cm) is still warned.
TEST(ScanSource, ARobotlaserMountingRoundedAsTheRobotTurnsIsNoChange) {
  const std::string path = tmp("robotlaser_turning.log");
  std::ofstream out(path);
  out << std::fixed << std::setprecision(3);
  for (int k = 0; k < 40; ++k) {
    const double x = 10.0 + 0.3 * k, y = 5.0 - 0.1 * k, yaw = std::remainder(0.37 * k, 2.0 * M_PI);
    const double ahead = k < 39 ? 0.1 : 0.2;  // the last line: the laser moved 10 cm
    out << "ROBOTLASER1 0 -1.570796 3.141593 0.785398 30 0.01 0 5 2 2 2 2 2 0 " << x + ahead * std::cos(yaw) << ' '
        << y + ahead * std::sin(yaw) << ' ' << yaw << ' ' << x << ' ' << y << ' ' << yaw << " 0 0 0.5 0.5 0 "
        << 100.0 + k << " host " << 100.0 + k << "\n";
  }
  out.close();
  CarmenScanSource source(path, "");
  std::size_t scans = 0;
  while (source.next()) ++scans;
  EXPECT_EQ(scans, 40u);
  const std::vector<std::string> w = source.warnings();
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].rfind(path + ":40: the laser 'ROBOTLASER1' changes its beam count, aperture or mounting", 0), 0u) << w[0];
}

// The worst of the rounding: the difference of two 3-decimal poses is off by up to 1.4 mm
// and 0.001 rad, so two mountings of one laser may differ by about 3 mm and 0.11 degree
// (the first two lines of a turning robot: 2.4 mm; the third: 0.11 degree). A tolerance of
// 2 mm and 0.1 degree warned here.
TEST(ScanSource, TwoRobotlaserMountingsAtTheRoundingsExtremesAreTheSame) {
  const std::string path = tmp("robotlaser_rounding_extremes.log");
  std::ofstream out(path);
  const char* poses[] = {"5.341 27.875 3.012 5.441 27.863 3.012", "22.868 30.738 1.520 22.862 30.639 1.520",
                         "22.868 30.738 1.519 22.862 30.639 1.521"};
  for (int k = 0; k < 3; ++k) {
    out << "ROBOTLASER1 0 -1.570796 3.141593 0.785398 30 0.01 0 5 2 2 2 2 2 0 " << poses[k] << " 0 0 0.5 0.5 0 "
        << 100.0 + k << " host " << 100.0 + k << "\n";
  }
  out.close();
  CarmenScanSource source(path, "");
  std::size_t scans = 0;
  while (source.next()) ++scans;
  EXPECT_EQ(scans, 3u);
  EXPECT_TRUE(source.warnings().empty()) << source.warnings().front();
}

}  // namespace
}  // namespace lidarseg::logs
