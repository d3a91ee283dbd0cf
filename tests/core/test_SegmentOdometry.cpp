// Laser odometry over the simulated maze run (the paper's experiment, one seed).
#include <cmath>
#include <iostream>

#include <gtest/gtest.h>

#include "lidarseg/core/SegmentOdometry.h"
#include "lidarseg/sim/Simulation.h"
#include "lidarseg/sim/WorldFile.h"
#include "SyntheticScenes.h"

namespace lidarseg {
namespace {

TEST(SegmentOdometry, DrivesTheMazeLoopWithSmallDrift) {
  const std::string dir = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/";
  const sim::World world = sim::loadWorldFile(dir + "maze.world");
  const sim::Trajectory traj = sim::loadTrajectoryFile(dir + "maze.traj");
  sim::SimulationParams sp;
  sp.seed = 1;
  sp.camera_every_scans = 0;
  sim::Simulation simulation(world, traj, sp);
  SegmentOdometry odometry;
  Pose2D gt0, gt_last;
  std::size_t failures = 0;
  for (std::size_t i = 0; i < simulation.numScans(); ++i) {
    const sim::SimulatedFrame f = simulation.next();
    const OdometryStep step = odometry.process(f.scan);
    if (i == 0) gt0 = f.T_world_robot;
    gt_last = f.T_world_robot;
    failures += !step.first && step.match.status == MatchStatus::kTooFewMatches;
  }
  const Pose2D truth = relative(gt_last, gt0);
  const double final_error = std::hypot(odometry.pose().x - truth.x, odometry.pose().y - truth.y);
  RecordProperty("final_error_m", std::to_string(final_error));
  EXPECT_EQ(failures, 0u);
  // 107 m loop; the paper's matcher ends 0.8 m off on average. A loose bound here (one
  // seed); the 50-run figures are in docs/results.md.
  EXPECT_LT(final_error, 1.0);
}

// Along a corridor whose only cross-corridor features are shallow pilasters (0.2 m
// faces across the corridor), the high-level match is degenerate (erosion removes the
// short faces); the fallback to cascade level 1 uses them.
double corridorErrorAlongX(CascadeLevel fallback, std::size_t* degenerate) {
  sim::World world;
  world.addWall({-10.0, 0.0}, {40.0, 0.0});
  world.addWall({-10.0, 2.0}, {40.0, 2.0});
  for (double x = -8.0; x < 38.0; x += 3.0) {
    world.addPolyline({{x, 2.0}, {x, 1.8}, {x + 0.25, 1.8}, {x + 0.25, 2.0}});
  }
  const auto sensor = testing::makeSensor(541, 270.0, 0.01);
  OdometryParams params;
  params.degenerate_fallback_level = fallback;
  params.keyframe_distance_m = 0.0;  // scan to scan: every match counts
  params.keyframe_angle_rad = 0.0;
  SegmentOdometry odometry(params);
  *degenerate = 0;
  double x = 0.0;
  OdometryStep step;
  for (int k = 0; k < 80; ++k) {
    Scan scan = testing::simulate(world, sensor, sim::Pose2{x, 1.0, 0.0}, 500 + k);
    scan.stamp_s = 0.02 * k;
    step = odometry.process(scan);
    if (!step.first && step.match.status == MatchStatus::kDegenerate) ++*degenerate;
    x += k < 40 ? 0.02 * k / 40.0 * 2.0 : 0.04;  // accelerating, then constant: the prior is wrong at first
  }
  const double true_x = x - 0.04;
  return std::abs(step.T_odom_sensor.x - true_x);
}

TEST(SegmentOdometry, DegenerateCorridorFallsBackToTheFinerLevel) {
  std::size_t degenerate_without = 0, degenerate_with = 0;
  const double without = corridorErrorAlongX(CascadeLevel::kFusedAgain, &degenerate_without);
  const double with = corridorErrorAlongX(CascadeLevel::kFused, &degenerate_with);
  EXPECT_GT(degenerate_without, 20u);
  EXPECT_LT(degenerate_with, degenerate_without / 2);
  std::cout << "error along the corridor: " << without << " m at level 3 only, " << with << " m with the fallback; degenerate " << degenerate_without << " -> " << degenerate_with << "\n";
  // Measured: 2.34 m -> 1.28 m over 2.4 m of scan-to-scan matching (the start, accelerating
  // from rest with a wrong prior, stays degenerate at both levels).
  EXPECT_LT(with, 0.7 * without);
}

TEST(SegmentOdometry, FirstScanIsTheOriginAndTimesAreReported) {
  const std::string dir = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/";
  const sim::World world = sim::loadWorldFile(dir + "maze.world");
  const sim::Trajectory traj = sim::loadTrajectoryFile(dir + "maze.traj");
  sim::SimulationParams sp;
  sp.camera_every_scans = 0;
  sim::Simulation simulation(world, traj, sp);
  SegmentOdometry odometry;
  const OdometryStep first = odometry.process(simulation.next().scan);
  EXPECT_TRUE(first.first);
  EXPECT_EQ(first.T_odom_sensor.x, 0.0);
  const OdometryStep second = odometry.process(simulation.next().scan);
  EXPECT_FALSE(second.first);
  EXPECT_NEAR(second.increment.x, 0.02, 0.01);  // 1 m/s at 50 Hz
  EXPECT_GT(second.wall_danielsson_us, 0.0);
  EXPECT_GT(second.matching_us, 0.0);
  OdometryParams bad;
  bad.keyframe_distance_m = -1;
  EXPECT_THROW(SegmentOdometry{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace lidarseg
