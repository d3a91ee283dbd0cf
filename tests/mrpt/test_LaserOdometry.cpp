// Laser odometry on MRPT observations: robot poses for a laser mounted off the robot's
// origin, and what the log readers give it.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>
#include <zlib.h>

#include "SyntheticScenes.h"
#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/LaserOdometry.h"
#include "lidarseg/mrpt/ScanConverter.h"

namespace lidarseg::mrpt_adapter {
namespace {

using lidarseg::testing::kDeg;
namespace fs = std::filesystem;

TEST(LaserOdometry, RobotTrajectoryOfAnOffsetLaserFollowsTheTruth) {
  const auto world = lidarseg::testing::officeScene();
  const auto sensor = lidarseg::testing::makeSensor(541, 270.0, 0.005);
  const Pose2D laser_on_robot{0.3, 0.1, 5 * kDeg};
  LaserOdometry odometry;
  Pose2D robot{1.0, 1.0, 0.0};
  const Pose2D start = robot;
  for (int k = 0; k < 60; ++k) {
    const Pose2D laser = compose(robot, laser_on_robot);
    const Scan scan = lidarseg::testing::simulate(world, sensor, laser, 100 + k);
    auto obs = makeRangeScanObservation(
        scan, "LIDAR", mrpt::poses::CPose3D(laser_on_robot.x, laser_on_robot.y, 0, laser_on_robot.yaw, 0, 0), 0.005);
    obs->timestamp = mrpt::Clock::fromDouble(1000.0 + 0.05 * k);
    const auto step = odometry.process(*obs);
    const Pose2D truth = relative(robot, start);  // robot pose in the first robot frame
    // Within 3 cm (single matches against a keyframe) plus 2.5 % of the distance driven.
    const double tol = 0.03 + 0.025 * 0.04 * k;
    EXPECT_NEAR(step.robot_pose.mean.x(), truth.x, tol) << "scan " << k;
    EXPECT_NEAR(step.robot_pose.mean.y(), truth.y, tol) << "scan " << k;
    EXPECT_NEAR(step.robot_pose.mean.phi(), truth.yaw, 0.5 * kDeg) << "scan " << k;
    if (k > 0) {
      EXPECT_GT(step.robot_pose.cov(0, 0), 0.0);
      EXPECT_GT(step.increment.cov(2, 2), 0.0);
    }
    robot = compose(robot, Pose2D{0.04, 0.0, k > 20 && k < 40 ? 0.5 * kDeg : 0.0});
  }
}

TEST(LaserOdometry, ConjugateCovarianceOfAPureRotationRotatesTheTranslation) {
  Eigen::Matrix3d c = Eigen::Vector3d(4.0, 1.0, 0.0).asDiagonal();
  const Eigen::Matrix3d r = conjugateCovariance(Pose2D{0, 0, M_PI / 2}, c);
  EXPECT_NEAR(r(0, 0), 1.0, 1e-12);
  EXPECT_NEAR(r(1, 1), 4.0, 1e-12);
}

TEST(LaserLogReader, RawlogRecordsCarryOdometryAndStamps) {
  const std::string path =
      std::string(LIDARSEG_MRPT_DATASETS_DIR) + "/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
  if (!fs::exists(path)) GTEST_SKIP() << "missing " << path;
  LaserLogReader reader(path);
  EXPECT_EQ(reader.format(), LogFormat::kRawlog);
  std::size_t n = 0, with_odometry = 0;
  double last = -1.0;
  while (auto r = reader.next()) {
    EXPECT_EQ(r->index, n);
    EXPECT_GT(r->stamp_s, last);
    last = r->stamp_s;
    if (r->odometry) ++with_odometry;
    EXPECT_NE(r->where.find("entry"), std::string::npos);
    ++n;
  }
  EXPECT_GT(n, 200u);
  EXPECT_GE(with_odometry, n - 1);  // the actions come before the sensory frames
}

TEST(LaserLogReader, CarmenLinesBecomeObservationsWithTheRightBeamBearings) {
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/geometry.clf";
  {
    std::ofstream out(path);
    out << "PARAM robot_frontlaser_offset 0.2 h 0\n";
    out << "FLASER 180";
    for (int i = 0; i < 180; ++i) out << " " << (i == 5 ? 90.0 : 2.0);  // beam 5: beyond max range
    out << " 1 2 0.3 4 5 0.6 12.5 h 12.5\n";
  }
  EXPECT_EQ(detectLogFormat(path), LogFormat::kCarmen);
  LaserLogReader reader(path);
  auto r = reader.next();
  ASSERT_TRUE(r);
  EXPECT_EQ(reader.sensor(), "FLASER");
  EXPECT_DOUBLE_EQ(r->stamp_s, 12.5);
  ASSERT_TRUE(r->odometry);
  EXPECT_DOUBLE_EQ(r->odometry->x, 4.0);  // no ODOM lines: the laser line's odometry fields
  ASSERT_TRUE(r->log_pose);
  // The laser pose (1, 2, 0.3) minus the 0.2 m offset along the heading.
  EXPECT_NEAR(r->log_pose->x, 1.0 - 0.2 * std::cos(0.3), 1e-9);
  // The line is read into the core types with no MRPT observation (issue 15)...
  EXPECT_EQ(r->observation, nullptr);
  EXPECT_EQ(r->sensor, "FLASER");
  EXPECT_NEAR(r->sensor_on_robot.x, 0.2, 1e-9);
  // Robot-frame bearing of beam i: -90 + i degrees (180 beams, 1 degree apart).
  const double yaw = r->sensor_on_robot.yaw;
  EXPECT_NEAR(r->scan.layout->angle(0) + yaw, -90 * kDeg, 1e-6);
  EXPECT_NEAR(r->scan.layout->angle(179) + yaw, 89 * kDeg, 1e-6);
  EXPECT_FALSE(r->scan.beamValid(5));
  EXPECT_TRUE(r->scan.beamValid(6));
  EXPECT_DOUBLE_EQ(r->scan.ranges_m[6], 2.0);
  // ...and an MRPT consumer gets the same scan as an observation.
  const auto obs = observationOf(*r);
  ASSERT_NE(obs, nullptr);
  EXPECT_EQ(obs->sensorLabel, "FLASER");
  EXPECT_NEAR(obs->sensorPose.x(), 0.2, 1e-9);
  EXPECT_NEAR(obs->sensorPose.yaw(), yaw, 1e-12);
  EXPECT_NEAR(mrpt::Clock::toDouble(obs->timestamp), 12.5, 1e-6);
  ScanConverter converter;
  const Scan scan = converter.convert(*obs);
  ASSERT_EQ(scan.size(), r->scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    EXPECT_DOUBLE_EQ(scan.layout->angle(i), r->scan.layout->angle(i)) << i;
    EXPECT_EQ(scan.beamValid(i), r->scan.beamValid(i)) << i;
  }
  EXPECT_FALSE(reader.next());
}

// A record whose scan was made by a program (no per-beam flags, as the simulator's and the
// synthetic scenes' scans) becomes an observation by the core's own validity test; the
// flags were read beyond their (empty) end, a crash of the ICP baseline.
TEST(LaserLogReader, AScanWithoutValidityFlagsBecomesAnObservationByTheCoresTest) {
  LaserRecord r;
  r.sensor = "LASER";
  r.stamp_s = 5.0;
  r.scan = lidarseg::testing::simulate(lidarseg::testing::officeScene(), lidarseg::testing::makeSensor(181, 180.0, 0.0),
                                       Pose2D{1.0, 1.0, 0.0}, 3);
  r.scan.ranges_m[7] = std::numeric_limits<double>::quiet_NaN();
  ASSERT_TRUE(r.scan.valid.empty());
  const auto obs = observationOf(r);
  ASSERT_EQ(obs->getScanSize(), r.scan.size());
  std::size_t valid = 0;
  for (std::size_t i = 0; i < r.scan.size(); ++i) {
    EXPECT_EQ(obs->getScanRangeValidity(i), r.scan.beamValid(i)) << i;
    valid += r.scan.beamValid(i);
  }
  EXPECT_FALSE(obs->getScanRangeValidity(7));
  EXPECT_GT(valid, 150u);
}

TEST(LaserLogReader, ScansWithTooFewBeamsAreSkippedAndNamed) {
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/onebeam.log";
  {
    std::ofstream out(path);
    out << "FLASER 1 2.0 0 0 0 0 0 0 1 h 1\n";
    out << "FLASER 3 2.0 2.0 2.0 0 0 0 0 0 0 2 h 2\n";
  }
  LaserLogReader reader(path);
  auto r = reader.next();
  ASSERT_TRUE(r);
  EXPECT_DOUBLE_EQ(r->stamp_s, 2.0);
  EXPECT_EQ(reader.skipped(), 1u);
  ASSERT_EQ(reader.issues().size(), 1u);
  EXPECT_NE(reader.issues()[0].find("onebeam.log:1"), std::string::npos) << reader.issues()[0];
}

// Issue 16, class 5: a log whose name says nothing is sniffed; CARMEN lines after blank
// lines or indented are still CARMEN, whatever the whitespace.
TEST(LaserLogReader, ACarmenLogWithLeadingWhitespaceIsSniffedAsCarmen) {
  const std::string flaser = "FLASER 3 2.0 2.0 2.0 0 0 0 0 0 0 7.5 h 7.5\n";
  int k = 0;
  for (const std::string& lead : {std::string("  "), std::string("\t"), std::string("\n\n"), std::string("\r\n  \t"),
                                  std::string(" \n# a comment\n")}) {
    const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/indented-" + std::to_string(k++) + ".txt";
    std::ofstream(path, std::ios::binary) << lead << flaser << "   " << flaser;
    EXPECT_EQ(detectLogFormat(path), LogFormat::kCarmen) << path;
    LaserLogReader reader(path);
    EXPECT_EQ(reader.format(), LogFormat::kCarmen);
    std::size_t scans = 0;
    while (auto r = reader.next()) {
      EXPECT_DOUBLE_EQ(r->stamp_s, 7.5);
      ++scans;
    }
    EXPECT_EQ(scans, 2u) << path;
  }
  // Whitespace before anything else than a line type or a comment is no CARMEN log.
  const std::string binary = std::string(LIDARSEG_TEST_TMP_DIR) + "/indented-binary.bin";
  std::ofstream(binary, std::ios::binary) << "  \n" << '\x8d' << "CSensoryFrame";
  EXPECT_EQ(detectLogFormat(binary), LogFormat::kRawlog);
  // Real rawlogs (gzip; plain, starting with MRPT's object header) under names that say
  // nothing are still sniffed as rawlogs.
  for (const char* name : {"2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog", "RO-SLAM_demo.rawlog"}) {
    const std::string rawlog = std::string(LIDARSEG_MRPT_DATASETS_DIR) + "/" + name;
    if (!fs::exists(rawlog)) GTEST_SKIP() << "MRPT's " << name << " is not installed (mrpt-common)";
    const std::string renamed = std::string(LIDARSEG_TEST_TMP_DIR) + "/rawlog-without-extension";
    fs::copy_file(rawlog, renamed, fs::copy_options::overwrite_existing);
    EXPECT_EQ(detectLogFormat(renamed), LogFormat::kRawlog) << name;
  }
}

// A gzip file may hold either format: its content decides, not its first bytes (a gzip CARMEN
// log named .txt was read as a rawlog, "entry 0: truncated or corrupt"); an editor's
// byte-order mark before a CARMEN log's first line is skipped (issue 16).
TEST(LaserLogReader, AGzipOrMarkedCarmenLogUnderAnyNameIsSniffedAsCarmen) {
  const std::string flaser = "FLASER 3 2.0 2.0 2.0 0 0 0 0 0 0 7.5 h 7.5\n";
  const std::string gz = std::string(LIDARSEG_TEST_TMP_DIR) + "/carmen-gzip.txt";
  {
    gzFile f = gzopen(gz.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    const std::string text = flaser + flaser;
    gzwrite(f, text.data(), static_cast<unsigned>(text.size()));
    gzclose(f);
  }
  EXPECT_EQ(detectLogFormat(gz), LogFormat::kCarmen);
  const std::string marked = std::string(LIDARSEG_TEST_TMP_DIR) + "/carmen-bom.txt";
  std::ofstream(marked, std::ios::binary) << "\xEF\xBB\xBF" << flaser;
  EXPECT_EQ(detectLogFormat(marked), LogFormat::kCarmen);
  for (const std::string& path : {gz, marked}) {
    LaserLogReader reader(path);
    std::size_t scans = 0;
    while (reader.next()) ++scans;
    EXPECT_GE(scans, 1u) << path;
  }
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
