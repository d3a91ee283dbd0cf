// The lidarseg method of the shared run: the record's scan reaches the odometry on the stamp
// policy's clock, whether the policy kept the log's stamp or repaired it, and the record is
// left as the log reader gave it.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "SyntheticScenes.h"
#include "lidarseg/core/StampPolicy.h"
#include "lidarseg/mrpt/LaserOdometry.h"
#include "lidarseg/report/Baselines.h"
#include "lidarseg/pipeline/OdometryMethods.h"
#include "lidarseg/pipeline/OdometryRun.h"

namespace lidarseg::pipeline {
namespace {

using lidarseg::testing::kDeg;

// A robot driving along an office corridor, its laser mounted off its origin; the log's
// stamps repeat once and jump back once, so that the policy repairs some of them.
std::vector<mrpt_adapter::LaserRecord> corridorLog() {
  const auto world = lidarseg::testing::officeScene();
  const auto sensor = lidarseg::testing::makeSensor(361, 270.0, 0.005);
  const Pose2D laser_on_robot{0.2, 0.05, 3 * kDeg};
  const std::vector<double> stamps = {100.0, 100.05, 100.1, 100.1, 100.2, 100.25, 100.2, 100.35,
                                      100.4, 100.45, 100.5, 100.55, 100.6, 100.65, 100.7};
  std::vector<mrpt_adapter::LaserRecord> log;
  Pose2D robot{1.0, 1.0, 0.0};
  for (std::size_t k = 0; k < stamps.size(); ++k) {
    mrpt_adapter::LaserRecord r;
    r.index = k;
    r.where = "corridor, entry " + std::to_string(k);
    r.stamp_s = stamps[k];
    r.scan = lidarseg::testing::simulate(world, sensor, compose(robot, laser_on_robot), 10 + k);
    r.scan.stamp_s = stamps[k];
    r.sensor_on_robot = laser_on_robot;
    log.push_back(std::move(r));
    robot = compose(robot, Pose2D{0.04, 0.0, 0.5 * kDeg});
  }
  return log;
}

TEST(LidarsegMethod, GivesTheOdometryOfTheScanOnTheModelClockAndKeepsTheRecord) {
  const auto log = corridorLog();
  StampPolicy stamps;
  LidarsegMethod method(OdometryParams{});
  // What the method must give: the odometry run on a copy of each scan stamped with the
  // model clock (how the method worked before it stopped copying every scan).
  mrpt_adapter::LaserOdometry reference(OdometryParams{});
  std::size_t repaired = 0, kept = 0;
  for (const auto& record : log) {
    const StampStep time = stamps.next(record.stamp_s);
    (time.model_stamp_s == record.scan.stamp_s ? kept : repaired)++;
    const MethodStep step = method.process(ScanInput{record, time, std::nullopt});
    Scan copy = record.scan;
    copy.stamp_s = time.model_stamp_s;
    const auto expected = reference.process(copy, record.sensor_on_robot);
    stamps.accept(time);

    const auto& got = method.lastStep();
    EXPECT_EQ(got.core.stamp_s, time.model_stamp_s) << record.where;
    EXPECT_EQ(got.core.status, expected.core.status) << record.where;
    EXPECT_EQ(got.robot_pose.mean.x(), expected.robot_pose.mean.x()) << record.where;
    EXPECT_EQ(got.robot_pose.mean.y(), expected.robot_pose.mean.y()) << record.where;
    EXPECT_EQ(got.robot_pose.mean.phi(), expected.robot_pose.mean.phi()) << record.where;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) EXPECT_EQ(got.robot_pose.cov(i, j), expected.robot_pose.cov(i, j)) << record.where;
    }
    // The step returned is the one the report records.
    const report::MethodReport& so_far = method.report();
    EXPECT_EQ(step.stamp_s, time.output_stamp_s) << record.where;
    EXPECT_EQ(step.pose.x, so_far.trajectory.back().pose.x) << record.where;
    EXPECT_EQ(step.pose.yaw, so_far.trajectory.back().pose.yaw) << record.where;
    EXPECT_EQ(step.time_us, so_far.time_us.back()) << record.where;
    EXPECT_EQ(step.status, &record == &log.front() ? std::string("first") : toString(got.core.status)) << record.where;
    // The record is the log reader's: its stamp is not the model clock's.
    EXPECT_EQ(record.scan.stamp_s, record.stamp_s) << record.where;
  }
  // Both ways through the method were taken.
  EXPECT_GT(kept, 2u);
  EXPECT_GT(repaired, 2u);
  const report::MethodReport& report = method.report();
  ASSERT_EQ(report.trajectory.size(), log.size());
  // The robot drove 0.04 m per scan: the trajectory ends near there.
  EXPECT_NEAR(report.trajectory.back().pose.x, 0.04 * static_cast<double>(log.size() - 1), 0.05);
}

// Each tracked scan's motion from its keyframe is recorded in the robot frame with its
// covariance (for the NEES against a ground truth): the motion between the reported robot
// poses of the scan and of the last keyframe (near the robot's true motion), and the core's
// covariance (laser frame) carried to the robot frame through the laser's mounting.
TEST(LidarsegMethod, RecordsEachScansMotionFromItsKeyframeInTheRobotFrame) {
  const auto log = corridorLog();
  StampPolicy stamps;
  OdometryParams params;
  params.keyframe_distance_m = 0.1;  // a new keyframe every third scan of this 0.56 m drive
  LidarsegMethod method(params);
  std::vector<Pose2D> truth;  // the robot's poses, as corridorLog() drove it
  Pose2D robot{1.0, 1.0, 0.0};
  std::vector<Eigen::Matrix3d> expected_covariance;
  std::vector<std::size_t> keyframe_of;
  std::size_t key = 0;
  for (const auto& record : log) {
    const StampStep time = stamps.next(record.stamp_s);
    method.process(ScanInput{record, time, std::nullopt});
    stamps.accept(time);
    truth.push_back(robot);
    robot = compose(robot, Pose2D{0.04, 0.0, 0.5 * kDeg});
    const OdometryStep& core = method.lastStep().core;
    if (!core.first) {
      ASSERT_NE(core.status, TrackStatus::kLost) << record.where;
      expected_covariance.push_back(mrpt_adapter::conjugateCovariance(record.sensor_on_robot, core.increment_covariance));
      keyframe_of.push_back(key);
    }
    if (core.keyframe) key = record.index;
  }
  const std::size_t keyframes = static_cast<std::size_t>(std::count(keyframe_of.begin(), keyframe_of.end(), 0u));
  EXPECT_LT(keyframes, keyframe_of.size() / 2) << "the keyframe must change during the drive";
  const report::MethodReport& report = method.report();
  ASSERT_EQ(report.keyframe_motions.size(), log.size() - 1);
  for (std::size_t k = 0; k < report.keyframe_motions.size(); ++k) {
    const eval::KeyframeMotion& m = report.keyframe_motions[k];
    const std::size_t i = k + 1, kf = keyframe_of[k];
    EXPECT_EQ(m.stamp_s, report.trajectory[i].stamp_s);
    EXPECT_EQ(m.keyframe_stamp_s, report.trajectory[kf].stamp_s);
    const Pose2D reported = relative(report.trajectory[i].pose, report.trajectory[kf].pose);
    EXPECT_NEAR(m.T_key_curr.x, reported.x, 1e-9);
    EXPECT_NEAR(m.T_key_curr.y, reported.y, 1e-9);
    EXPECT_NEAR(m.T_key_curr.yaw, reported.yaw, 1e-9);
    EXPECT_TRUE(m.covariance.isApprox(expected_covariance[k], 1e-12)) << "scan " << i;
    const Pose2D true_motion = relative(truth[i], truth[kf]);
    EXPECT_LT(std::hypot(m.T_key_curr.x - true_motion.x, m.T_key_curr.y - true_motion.y), 0.01) << "scan " << i;
    EXPECT_LT(std::abs(wrapAngle(m.T_key_curr.yaw - true_motion.yaw)), 0.2 * kDeg) << "scan " << i;
  }
}

// The run's baselines come from their names: reported in the registry's order whatever the
// order asked, each scan's steps lidarseg's first; an unknown name is refused naming the
// known ones.
TEST(OdometryRun, RunsTheBaselinesNamedInTheRegistrysOrder) {
  const auto log = corridorLog();
  RunSettings settings;
  settings.baselines = {"icp-s2s", "icp"};
  OdometryRun run(settings);
  for (const auto& record : log) {
    const RunStep step = run.process(record);
    ASSERT_TRUE(step.processed) << record.where;
    ASSERT_EQ(step.steps.size(), 3u);
    EXPECT_EQ(step.steps[1].stamp_s, step.steps[0].stamp_s);
    if (&record == &log.front()) {
      EXPECT_EQ(step.steps[1].status, "first");
    }
  }
  const report::OdometryReport report = run.finish(0.01);
  ASSERT_EQ(report.baselines.size(), 2u);
  EXPECT_EQ(report.baselines[0].name, "icp");
  EXPECT_EQ(report.baselines[1].name, "icp-s2s");
  ASSERT_NE(report.baseline("icp-s2s"), nullptr);
  EXPECT_EQ(report.baseline("icp-s2s")->trajectory.size(), log.size());
  EXPECT_EQ(report.baseline("csm"), nullptr);
  EXPECT_GT(report.speedup_median, 0.0) << "measured against the keyframed ICP";
  for (const report::MethodReport& b : report.baselines) {
    ASSERT_NE(report::baselineKind(b.name), nullptr) << b.name;
    EXPECT_GT(b.trajectory.back().pose.x, 0.1) << b.name << " did not follow the drive forward";
  }
  // The keyframed ICP follows the same 0.56 m corridor drive as lidarseg (scan to scan, it
  // falls short along the corridor: 0.31 m).
  EXPECT_NEAR(report.baseline("icp")->trajectory.back().pose.x, report.lidarseg.trajectory.back().pose.x, 0.05);

  settings.baselines = {"icp", "csm"};
  try {
    OdometryRun unknown(settings);
    FAIL() << "an unknown report::baseline was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "unknown report::baseline 'csm' (known: 'icp', 'icp-s2s')");
  }
}

// A scan the odometry refuses (its ranges not matching its layout) is skipped with its
// place, and its wheel-odometry prior is not counted as used: the summary's count of scans
// whose prior was the wheel odometry's counted it (issue 16).
TEST(OdometryRun, ARefusedScansPriorIsNotCounted) {
  auto log = corridorLog();
  Pose2D odometry{5.0, -2.0, 0.3};
  for (auto& record : log) {
    record.odometry = odometry;
    odometry = compose(odometry, Pose2D{0.04, 0.0, 0.5 * kDeg});
  }
  log[6].scan.ranges_m.pop_back();
  RunSettings settings;
  settings.use_odometry = true;
  OdometryRun run(settings);
  std::size_t processed = 0;
  for (const auto& record : log) {
    const RunStep step = run.process(record);
    if (&record == &log[6]) {
      EXPECT_FALSE(step.processed);
      EXPECT_NE(step.error.find("corridor, entry 6"), std::string::npos) << step.error;
    }
    if (step.processed) ++processed;
  }
  EXPECT_EQ(processed, log.size() - 1);
  const report::OdometryReport report = run.finish(0.01);
  EXPECT_EQ(report.odometry_priors, processed - 1) << "every used scan but the first, and not the refused one";
  EXPECT_EQ(report.odometry_jumps, 0u);
}

// A scan without wheel odometry (its reading dropped as not finite) breaks the chain: the
// next reading's increment would span two scans. With no two consecutive readings the summary
// says the prior was constant velocity, not "wheel odometry" (issue 16).
TEST(OdometryRun, AScanWithoutOdometryBreaksThePriorsChain) {
  auto log = corridorLog();
  Pose2D odometry{5.0, -2.0, 0.3};
  for (auto& record : log) {
    record.odometry = odometry;
    odometry = compose(odometry, Pose2D{0.04, 0.0, 0.5 * kDeg});
  }
  log[6].odometry.reset();
  RunSettings settings;
  settings.use_odometry = true;
  OdometryRun run(settings);
  for (const auto& record : log) ASSERT_TRUE(run.process(record).processed) << record.where;
  const report::OdometryReport report = run.finish(0.01);
  EXPECT_EQ(report.odometry_priors, log.size() - 3) << "not the first, the one without, nor the one after it";
  EXPECT_EQ(report.prior, "wheel odometry");

  for (std::size_t k = 1; k < log.size(); ++k) log[k].odometry.reset();
  OdometryRun none(settings);
  for (const auto& record : log) ASSERT_TRUE(none.process(record).processed) << record.where;
  const report::OdometryReport r2 = none.finish(0.01);
  EXPECT_EQ(r2.odometry_priors, 0u);
  EXPECT_EQ(r2.prior, "constant velocity (no usable wheel odometry between scans)");
}

}  // namespace
}  // namespace lidarseg::pipeline
