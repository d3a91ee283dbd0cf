// Laser odometry over the simulated maze run (the paper's experiment, one seed).
#include <cmath>
#include <limits>
#include <utility>
#include <iostream>
#include <optional>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include "lidarseg/core/SegmentOdometry.h"
#include "lidarseg/sim/Simulation.h"
#include "lidarseg/sim/WorldFile.h"
#include "SyntheticScenes.h"

namespace lidarseg {
namespace {

// The paper's maze run (config/worlds/maze.*), LMS100 at 50 Hz, no camera.
struct MazeRun {
  explicit MazeRun(std::uint64_t seed, ScanStamp stamp = ScanStamp::kFirst,
                   const sim::SensorModel& sensor = sim::SensorModel::lms100())
      : world(sim::loadWorldFile(std::string(LIDARSEG_CONFIG_DIR) + "/worlds/maze.world")),
        trajectory(sim::loadTrajectoryFile(std::string(LIDARSEG_CONFIG_DIR) + "/worlds/maze.traj")),
        simulation(world, trajectory, params(seed, stamp, sensor)) {}
  static sim::SimulationParams params(std::uint64_t seed, ScanStamp stamp, const sim::SensorModel& sensor) {
    sim::SimulationParams sp;
    sp.seed = seed;
    sp.camera_every_scans = 0;
    sp.scan_stamp = stamp;
    sp.sensor = sensor;
    return sp;
  }
  sim::World world;
  sim::Trajectory trajectory;
  sim::Simulation simulation;
};

TEST(SegmentOdometry, DrivesTheMazeLoopWithSmallDrift) {
  MazeRun maze(1);
  sim::Simulation& simulation = maze.simulation;
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
// short faces). The point-to-segment refinement uses the pilasters' faces; without it, the
// fallback to cascade level 1 is all there is.
double corridorErrorAlongX(bool refine, std::size_t* degenerate) {
  sim::World world;
  world.addWall({-10.0, 0.0}, {40.0, 0.0});
  world.addWall({-10.0, 2.0}, {40.0, 2.0});
  for (double x = -8.0; x < 38.0; x += 3.0) {
    world.addPolyline({{x, 2.0}, {x, 1.8}, {x + 0.25, 1.8}, {x + 0.25, 2.0}});
  }
  const auto sensor = testing::makeSensor(541, 270.0, 0.01);
  OdometryParams params;
  params.refiner.enabled = refine;
  params.keyframe_distance_m = 0.0;  // scan to scan: every match counts
  params.keyframe_angle_rad = 0.0;
  SegmentOdometry odometry(params);
  *degenerate = 0;
  double x = 0.0;
  OdometryStep step;
  for (int k = 0; k < 80; ++k) {
    Scan scan = testing::simulate(world, sensor, Pose2D{x, 1.0, 0.0}, 500 + k);
    scan.stamp_s = 0.02 * k;
    step = odometry.process(scan);
    if (!step.first && step.status == TrackStatus::kDegenerate) ++*degenerate;
    x += k < 40 ? 0.02 * k / 40.0 * 2.0 : 0.04;  // accelerating, then constant: the prior is wrong at first
  }
  const double true_x = x - 0.04;
  return std::abs(step.T_odom_sensor.x - true_x);
}

// A non-finite odometry increment is refused before anything changes (it reached the
// recovery search's grid indices: SIGSEGV); the next scan with a good one goes on as if the
// bad call had not been made.
TEST(SegmentOdometry, ANonFiniteOdometryIncrementIsRefusedAndChangesNothing) {
  const sim::World world = testing::officeScene();
  const auto sensor = testing::makeSensor(541, 270.0, 0.01);
  const Scan a = testing::simulate(world, sensor, Pose2D{1.0, 1.0, 0.0}, 1);
  const Scan b = testing::simulate(world, sensor, Pose2D{1.1, 1.0, 0.0}, 2);
  SegmentOdometry with_bad, without;
  with_bad.process(a);
  without.process(a);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const Pose2D bad : {Pose2D{nan, 0.0, 0.0}, Pose2D{0.0, inf, 0.0}, Pose2D{0.0, 0.0, -inf}}) {
    try {
      with_bad.process(b, bad);
      FAIL() << "a non-finite odometry increment was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("the odometry increment ("), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(") is not finite"), std::string::npos) << e.what();
    }
  }
  const OdometryStep s1 = with_bad.process(b, Pose2D{0.1, 0.0, 0.0});
  const OdometryStep s2 = without.process(b, Pose2D{0.1, 0.0, 0.0});
  EXPECT_EQ(s1.index, s2.index);
  EXPECT_EQ(s1.T_odom_sensor.x, s2.T_odom_sensor.x);
  EXPECT_EQ(s1.T_odom_sensor.y, s2.T_odom_sensor.y);
  EXPECT_NEAR(s1.T_odom_sensor.x, 0.1, 0.01);
}

// A malformed scan (its ranges not matching its layout) is refused before anything changes:
// the rate of the last sweep was forgotten first, so a turning 360-degree scanner's next
// scan was deskewed differently after the refused call (issue 16).
TEST(SegmentOdometry, AMalformedScanIsRefusedAndChangesNothing) {
  const sim::World world = testing::officeScene();
  const auto sensor = testing::makeFullTurnSensor(720, 0.01);
  OdometryParams params;
  params.scanner_rotation_hz = 10.0;  // beam times: the sweep rate is estimated at each scan
  SegmentOdometry with_bad(params), without(params);
  for (int k = 0; k < 4; ++k) {
    Scan scan = testing::simulate(world, sensor, Pose2D{1.0 + 0.05 * k, 1.0, 0.2 * k}, 10 + k);
    scan.stamp_s = 0.1 * k;
    if (k == 3) {
      Scan bad = scan;
      bad.ranges_m.pop_back();
      EXPECT_THROW(with_bad.process(bad), std::invalid_argument);
    }
    const OdometryStep s1 = with_bad.process(scan);
    const OdometryStep s2 = without.process(scan);
    EXPECT_EQ(s1.index, s2.index) << k;
    EXPECT_EQ(s1.T_odom_sensor.x, s2.T_odom_sensor.x) << k;
    EXPECT_EQ(s1.T_odom_sensor.y, s2.T_odom_sensor.y) << k;
    EXPECT_EQ(s1.T_odom_sensor.yaw, s2.T_odom_sensor.yaw) << k;
  }
}

TEST(SegmentOdometry, PilasterCorridorIsConstrainedByTheRefinement) {
  std::size_t degenerate_without = 0, degenerate_with = 0;
  const double without = corridorErrorAlongX(false, &degenerate_without);
  const double with = corridorErrorAlongX(true, &degenerate_with);
  std::cout << "error along the corridor: " << without << " m without refinement (" << degenerate_without
            << " degenerate), " << with << " m with it (" << degenerate_with << " degenerate)\n";
  EXPECT_GT(degenerate_without, 20u);
  EXPECT_EQ(degenerate_with, 0u);
  // Measured: 1.28 m without the refinement (level-1 fallback only), 0.03-0.05 m with it,
  // over 2.4 m of scan-to-scan matching that starts with a wrong prior.
  EXPECT_LT(with, 0.1);
  EXPECT_LT(with, 0.25 * without);
}

// A turn that reverses (the constant-velocity prior is then wrong by twice the rate) and a
// 1 m / 30 degree unpredicted jump: both are recovered, no scan is lost.
TEST(SegmentOdometry, TurnReversalAndUnpredictedJumpAreRecovered) {
  const sim::World world = testing::officeScene();
  const auto sensor = testing::makeSensor(541, 270.0, 0.01, 30.0);
  SegmentOdometry odometry;
  std::vector<Pose2D> truth;
  double yaw = 0.0;
  for (int k = 0; k < 20; ++k) {  // 10 Hz, +0.1 rad per scan, then -0.1 rad per scan
    yaw += k == 0 ? 0.0 : (k <= 10 ? 0.1 : -0.1);
    truth.push_back({0.5, 1.0, yaw});
  }
  truth.push_back({1.3, 1.6, yaw + 0.52});  // the jump
  for (int k = 0; k < 3; ++k) truth.push_back(truth.back());
  std::size_t lost = 0;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    Scan scan = testing::simulate(world, sensor, truth[k], 900 + k);
    scan.stamp_s = 0.1 * static_cast<double>(k);
    const OdometryStep step = odometry.process(scan);
    lost += step.status == TrackStatus::kLost;
    const Pose2D expected = relative(truth[k], truth[0]);
    EXPECT_NEAR(step.T_odom_sensor.x, expected.x, 0.05) << "scan " << k << " " << toString(step.status) << " match " << toString(step.match.status) << " ratio " << step.refine.inlier_ratio << " got " << step.T_odom_sensor.x << "," << step.T_odom_sensor.y << "," << step.T_odom_sensor.yaw << " want " << expected.x << "," << expected.y << "," << expected.yaw;
    EXPECT_NEAR(step.T_odom_sensor.y, expected.y, 0.05) << "scan " << k;
    // 2 rad of turning in 0.1 rad steps: the yaw may drift by about 1 mrad per keyframe.
    EXPECT_NEAR(wrapAngle(step.T_odom_sensor.yaw - expected.yaw), 0.0, 0.02) << "scan " << k;
  }
  EXPECT_EQ(lost, 0u);
}

// A 2.3 m / 52 degree unpredicted jump, beyond the first search's window (1.2 m, 0.6 rad):
// with wide_search_factor = 1 the scan is lost (the prediction kept, 2.3 m off); the wider
// second search recovers it (decision 83). Returns the lost count; the jump scan's position
// error in `jump_error_m`.
std::size_t lostOverAWideJump(double wide_search_factor, double* jump_error_m) {
  const sim::World world = testing::officeScene();
  const auto sensor = testing::makeSensor(541, 270.0, 0.01, 30.0);
  OdometryParams params;
  params.wide_search_factor = wide_search_factor;
  SegmentOdometry odometry(params);
  std::vector<Pose2D> truth(5, Pose2D{0.5, 1.0, 0.0});
  truth.push_back({2.8, 0.8, -0.9});  // 2.31 m and 52 degrees from the prior (at rest)
  truth.push_back(truth.back());
  std::size_t lost = 0;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    Scan scan = testing::simulate(world, sensor, truth[k], 1200 + k);
    scan.stamp_s = 0.1 * static_cast<double>(k);
    const OdometryStep step = odometry.process(scan);
    lost += step.status == TrackStatus::kLost;
    const Pose2D expected = relative(truth[k], truth[0]);
    const double error = std::hypot(step.T_odom_sensor.x - expected.x, step.T_odom_sensor.y - expected.y);
    if (k == 5) *jump_error_m = error;
    if (k < 5) {
      EXPECT_LT(error, 0.02) << "scan " << k;  // at rest: nothing to recover yet
    }
  }
  return lost;
}

TEST(SegmentOdometry, AJumpBeyondTheSearchWindowIsRecoveredByTheWiderSearch) {
  double with_error = 0.0, without_error = 0.0;
  const std::size_t lost_with = lostOverAWideJump(2.0, &with_error);
  const std::size_t lost_without = lostOverAWideJump(1.0, &without_error);
  std::cout << "jump scan error: " << with_error << " m with the wider search, " << without_error
            << " m without (" << lost_without << " lost)\n";
  EXPECT_EQ(lost_with, 0u);
  EXPECT_LT(with_error, 0.05);  // measured 2.4 mm
  EXPECT_EQ(lost_without, 1u);
  EXPECT_GT(without_error, 2.0);  // measured 2.30 m
}

// wide_search_factor is validated, and the wider window it makes is one the search accepts:
// with a 14 mm grid, 1.2 m x 5 rounded to 400.00000000000006 cells and the odometry could not
// be built, naming a key the user never wrote.
TEST(SegmentOdometry, TheWideSearchFactorIsValidatedAndItsWindowIsOneTheSearchAccepts) {
  OdometryParams p;
  p.search.resolution_m = 0.014;
  p.wide_search_factor = 5.0;
  EXPECT_NO_THROW(SegmentOdometry{p});
  for (const double bad : {0.5, 11.0, std::nan("")}) {
    p.wide_search_factor = bad;
    try {
      SegmentOdometry odometry(p);
      ADD_FAILURE() << "wide_search_factor = " << bad << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("wide_search_factor"), std::string::npos) << e.what();
    }
  }
}

// The position error after the first `scans` scans of a simulated run (world "maze" or
// "hospital" of config/worlds), first poses made equal.
// The odometry's final pose and the truth (both from the first scan's pose) after `scans`
// scans of a world's loop.
std::pair<Pose2D, Pose2D> runFinalPoses(const char* world_name, const sim::SensorModel& sensor, std::uint64_t seed,
                                        std::size_t scans, const OdometryParams& params) {
  const std::string base = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/" + world_name;
  const sim::World world = sim::loadWorldFile(base + ".world");  // the simulation keeps references
  const sim::Trajectory trajectory = sim::loadTrajectoryFile(base + ".traj");
  sim::Simulation simulation(world, trajectory, MazeRun::params(seed, ScanStamp::kFirst, sensor));
  SegmentOdometry odometry(params);
  Pose2D gt0, gt_last;
  for (std::size_t i = 0; i < std::min(scans, simulation.numScans()); ++i) {
    const sim::SimulatedFrame f = simulation.next();
    odometry.process(f.scan);
    if (i == 0) gt0 = f.T_world_robot;
    gt_last = f.T_world_robot;
  }
  return {odometry.pose(), relative(gt_last, gt0)};
}

// The final position error (m).
double runError(const char* world_name, const sim::SensorModel& sensor, std::uint64_t seed, std::size_t scans,
                const OdometryParams& params) {
  const auto [estimate, truth] = runFinalPoses(world_name, sensor, seed, scans, params);
  return std::hypot(estimate.x - truth.x, estimate.y - truth.y);
}

// The first 6 m of the maze's corridor with the 181-beam, 75 Hz SICK (seed 1): as the robot
// leaves the keyframe, fewer points pair and the refinement turns doubtful; the correlative
// search then finds a pose about 1 m back along the corridor that pairs more points. The
// constant-velocity prior cannot be 1 m wrong after 13 ms, and its own refinement holds: the
// gate of the prior keeps it. That hypothesis is also degenerate along the corridor, so
// since decision 76 it is refused twice: without the gate (an unbounded acceleration) the
// run no longer jumps either (0.96 m before decision 76). Both must hold.
double corridorRunError(double accel_m_s2) {
  OdometryParams params;
  params.prior_accel_m_s2 = accel_m_s2;
  return runError("maze", sim::SensorModel::sick180(), 1, 520, params);
}

TEST(SegmentOdometry, ASearchResultOneCorridorBayAwayDoesNotReplaceAPriorThatHolds) {
  const double gated = corridorRunError(OdometryParams{}.prior_accel_m_s2);
  const double ungated = corridorRunError(1e9);
  std::cout << "error after 520 scans: " << gated << " m with the prior's gate, " << ungated << " m without\n";
  EXPECT_LT(gated, 0.05);
  EXPECT_LT(ungated, 0.05);  // measured 0.022 m, as gated; 0.96 m with neither defence
}

// The hospital's y = 12 m corridor with the UTM-30LX (seed 2): after the square pillar the
// segment match pairs the walls as well one pillar face further and its refinement converges
// there, 0.25 m from a constant-velocity prior that is right to millimetres (decision 75).
// Checked against the prior, the match loses to the prior's refinement.
TEST(SegmentOdometry, AMatchThatDisagreesWithAnExactPriorDoesNotWin) {
  const std::size_t kHospitalScans = 2620;  // the match converges off at scan 2573 (x = 29.56 m)
  OdometryParams unchecked;
  unchecked.check_match_against_prior = false;
  const double with = runError("hospital", sim::SensorModel::utm30lx(), 2, kHospitalScans, OdometryParams{});
  const double without = runError("hospital", sim::SensorModel::utm30lx(), 2, kHospitalScans, unchecked);
  std::cout << "hospital, UTM-30LX, seed 2, " << kHospitalScans << " scans: " << with << " m checked against the prior, "
            << without << " m unchecked\n";
  // Measured: 0.077 m checked, 0.367 m unchecked (a 0.27 m jump at scan 2573).
  EXPECT_LT(with, 0.15);
  EXPECT_GT(without, 0.25);
}

// The hospital's y = 0 corridor with the UTM-30LX (seed 4): at x = 27 m the prior's
// refinement pairs fewer points than usual, the correlative search runs and finds a pose
// 0.25 m back along the corridor that pairs more, but whose refinement is degenerate along
// it: that pose says nothing about the position along the corridor and must not replace a
// refinement that is constrained.
TEST(SegmentOdometry, ADegenerateHypothesisDoesNotReplaceAConstrainedOne) {
  const std::size_t kScans = 1150;  // the search ran at scan 1084
  const double error = runError("hospital", sim::SensorModel::utm30lx(), 4, kScans, OdometryParams{});
  std::cout << "hospital, UTM-30LX, seed 4, " << kScans << " scans: " << error << " m\n";
  // Measured: 0.049 m; 0.298 m when the degenerate hypothesis may win.
  EXPECT_LT(error, 0.15);
}

// A slow scanner in fast turns (decision 90): the maze with the 181-beam SICK at 5 Hz
// instead of 75 Hz, so that a turn that starts between two scans turns the robot by up to
// 0.33 rad more than the constant-velocity prior says, and one sweep skews the scan by up to
// 0.17 rad. The prior's refinement then pairs clearly fewer points than the last scans did,
// and the search finds the turn beyond the prior's gate (4 rad/s^2: 0.24 rad after 0.2 s);
// a prior so refuted does not gate it. After a turn the scan is deskewed again with the
// rotation rate its refinement measured. Measured over seeds 1 and 2, 400 scans (four turns):
// 0.65 m; 1.70 m before decision 90.
TEST(SegmentOdometry, ATurnBetweenTwoScansOfASlowScannerIsFollowed) {
  sim::SensorModel slow = sim::SensorModel::sick180();
  slow.frequency_hz = 5.0;
  OdometryParams params;
  params.scanner_rotation_hz = 5.0;
  const double error = 0.5 * (runError("maze", slow, 1, 400, params) + runError("maze", slow, 2, 400, params));
  std::cout << "maze, 181-beam SICK at 5 Hz, seeds 1-2, 400 scans: mean error " << error << " m\n";
  EXPECT_LT(error, 1.0);
}

// The maze with the LMS100 (seed 6): at the stub corridor the refinement from the
// constant-velocity prior runs out of iterations while sliding along it, the match's
// converges; the prior comes from the last estimates, so an unconverged refinement from it
// must not win, or the error feeds itself (2 m in one corridor before decision 75).
TEST(SegmentOdometry, AnUnconvergedRefinementFromAnEstimatedPriorLosesToAConvergedOne) {
  const std::size_t kMazeScans = 400;  // the stub at x = 6 m is passed at scans 300-310
  const double error = runError("maze", sim::SensorModel::lms100(), 6, kMazeScans, OdometryParams{});
  std::cout << "maze, LMS100, seed 6, " << kMazeScans << " scans: " << error << " m\n";
  // Measured: 0.015 m; 2.0 m when the unconverged reference may win (scans 302-307).
  EXPECT_LT(error, 0.1);
}

// The other side of that rule: a converged hypothesis that pairs fewer points than the
// unconverged reference does not replace it. With the 360-degree scanner at 5.5 Hz the
// prior's refinement along a corridor often creeps (in the batch run of the maze's seed 4,
// scan 362: 0.678 -> 0.733 m in 10 iterations, 324 inliers) while the segment match
// converges one bay back (0.8 m, 302 inliers); taken, it turns the velocity estimate
// negative and the run ends metres off. Measured, seeds 1-3, whole runs: 0.20 / 0.10 /
// 0.14 m; 7.9 / 5.0 / 16.0 m when the converged hypothesis wins on convergence alone
// (decision 96).
TEST(SegmentOdometry, AConvergedHypothesisPairingFewerPointsDoesNotReplaceTheReference) {
  const std::size_t kWholeRun = std::numeric_limits<std::size_t>::max();  // about 590 scans
  double sum = 0.0;
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const double error = runError("maze", sim::SensorModel::rplidar360(), seed, kWholeRun, OdometryParams{});
    std::cout << "maze, 360-degree scanner at 5.5 Hz, seed " << seed << ": final error " << error << " m\n";
    sum += error;
    EXPECT_LT(error, 0.6) << "seed " << seed;
  }
  EXPECT_LT(sum / 3.0, 0.5);
}

// The maze with the 181-beam SICK slowed to 5 Hz, scans taken at once (no rolling shutter,
// no beam times), seed 1: in the y = 20 m corridor, at scan 272, the segment match put the
// scan 0.59 m ahead where the robot moved 0.2 m, one bay of the corridor off, where its walls
// pair as well and the fit is degenerate along it. A degenerate fit keeps along its weak
// direction the value its hypothesis started from, so that step stood, and the
// constant-velocity prior carried 0.59 m per scan on: 26 degenerate scans (each one bay off)
// and 9.7 m off at the end. Refined again from the prior's value along the weak direction
// (decision 98), the fit is constrained there: 1 degenerate scan, 0.13 m. Decision 111 (the
// degenerate step's motion along its free axis kept out of the velocity) is a second defence
// against the same run-away (0.29 m alone), so the defect is shown with both off; the last
// checks keep the scenario honest: they fail if something else cures the defect first.
TEST(SegmentOdometry, ADegenerateFitTakesItsPoseAlongTheCorridorFromThePrior) {
  sim::SensorModel slow = sim::SensorModel::sick180();
  slow.frequency_hz = 5.0;
  const auto finalError = [&](bool along_prior, bool keeps_velocity) {
    MazeRun maze(1, ScanStamp::kFirst, slow);
    sim::SimulationParams sp = MazeRun::params(1, ScanStamp::kFirst, slow);
    sp.rolling_shutter = false;
    sim::Simulation simulation(maze.world, maze.trajectory, sp);
    OdometryParams params;
    params.degenerate_along_prior = along_prior;
    params.degenerate_keeps_velocity = keeps_velocity;
    SegmentOdometry odometry(params);
    Pose2D gt0, gt_last;
    std::size_t degenerate = 0;
    for (std::size_t i = 0; i < simulation.numScans(); ++i) {
      sim::SimulatedFrame f = simulation.next();
      f.scan.time_offsets_s.clear();
      degenerate += odometry.process(f.scan).status == TrackStatus::kDegenerate;
      if (i == 0) gt0 = f.T_world_robot;
      gt_last = f.T_world_robot;
    }
    const Pose2D truth = relative(gt_last, gt0);
    const double error = std::hypot(odometry.pose().x - truth.x, odometry.pose().y - truth.y);
    std::cout << "maze, SICK at 5 Hz without rolling shutter, seed 1, degenerate_along_prior = " << along_prior
              << ", degenerate_keeps_velocity = " << keeps_velocity << ": final error " << error << " m, " << degenerate << " degenerate scans\n";
    return std::make_pair(error, degenerate);
  };
  const auto [with, degenerate] = finalError(true, true);
  const auto [without, degenerate_without] = finalError(false, false);
  EXPECT_LT(with, 0.3);
  EXPECT_LT(finalError(true, false).first, 0.3);  // decision 98 alone (measured 0.13 m)
  EXPECT_LT(degenerate, 5u);             // measured 1
  EXPECT_GT(degenerate_without, 10u);    // measured 26: one bay off, scan after scan
  EXPECT_GT(without, 2.0);               // the defect this guards against (measured 9.7 m)
}

// The maze with the 181-beam SICK slowed to 5 Hz (rolling shutter, the simulator's beam
// times), keyframes every 0.3 rad: after a turn one scan was placed ahead in a featureless
// corridor, and its motion set the constant-velocity prior, which every later degenerate
// step reproduced (the scan cannot say otherwise along the corridor): metres off at the end
// (seed 1, 23 m, when decision 111 was made; since decision 115 the defect shows on seed 8,
// 19 m). A degenerate step's motion along its free axis is kept out of the velocity
// (decision 111): the one scan's error stays its own. The last check keeps the scenario
// honest: it fails if something else cures the defect.
TEST(SegmentOdometry, ADegenerateStepDoesNotTeachTheVelocityAlongItsFreeAxis) {
  sim::SensorModel slow = sim::SensorModel::sick180();
  slow.frequency_hz = 5.0;
  const auto finalError = [&](bool keeps_velocity) {
    OdometryParams params;
    params.keyframe_angle_rad = 0.3;
    params.degenerate_keeps_velocity = keeps_velocity;
    const double error = runError("maze", slow, 8, std::numeric_limits<std::size_t>::max(), params);
    std::cout << "maze, SICK at 5 Hz, keyframes every 0.3 rad, seed 8, degenerate_keeps_velocity = " << keeps_velocity
              << ": final error " << error << " m\n";
    return error;
  };
  EXPECT_LT(finalError(true), 1.5);
  EXPECT_GT(finalError(false), 5.0);
}

// hospital.world with the 181-beam SICK at 5 Hz, seed 1: the robot moves at 1 m/s from the
// first scan, and the constant-velocity prior, knowing no motion yet, says "still". The
// refinements from it came to rest near that guess (the corridor's along-axis cues, shallow
// recesses, pull little from 0.2 m off), constrained, so the velocity stayed zero and 12
// scans in a row lost their 0.2 m: 2.4 m after 20 scans, most of the run's 2.6 m final error.
// Until a step has measured the motion, the refinements start from a wider loss (decision
// 112). The last check keeps the scenario honest: it fails if something else cures it.
TEST(SegmentOdometry, ARunThatStartsInMotionIsFollowedFromItsFirstScans) {
  sim::SensorModel slow = sim::SensorModel::sick180();
  slow.frequency_hz = 5.0;
  const auto errorAfter20Scans = [&](double initial_scale_m) {
    OdometryParams params;
    params.refiner.initial_scale_m = initial_scale_m;
    const double error = runError("hospital", slow, 1, 20, params);
    std::cout << "hospital, SICK at 5 Hz, seed 1, 20 scans (3.8 m), initial_scale_m = " << initial_scale_m
              << ": error " << error << " m\n";
    return error;
  };
  EXPECT_LT(errorAfter20Scans(OdometryParams{}.refiner.initial_scale_m), 0.2);
  EXPECT_GT(errorAfter20Scans(0.0), 1.0);
}

// The maze with the 181-beam SICK at 5 Hz stamped at its first beam, seed 1: each sweep lies
// in the interval to the next scan, and is deskewed with the rate of the interval before.
// At a turn's onset or end the two differ by up to 1.67 rad/s, the sweep's last beam is bent
// by up to 0.17 rad, and the keyframe's pose takes part of that bend. Revised at the next
// scan with the rate measured over its sweep's interval (decision 114), the keyframes'
// headings relative to the scan before are closer to the truth. The poses reported stay
// causal: the increments chain into them. Stamped at the last beam, no keyframe is revised
// (its sweep lies in the interval before, whose rate is known).
TEST(SegmentOdometry, AKeyframeIsRevisedWithTheRateMeasuredOverItsSweep) {
  sim::SensorModel slow = sim::SensorModel::sick180();
  slow.frequency_hz = 5.0;
  struct Outcome {
    std::size_t revisions = 0;
    double reported_error_rad = 0.0, revised_error_rad = 0.0;  // sums of |relative heading error|
    std::size_t closer = 0;  // revisions whose relative heading is closer to the truth
    double chain_error_m = 0.0;  // the largest gap between the chained increments and the poses
  };
  const auto run = [&](ScanStamp stamp, std::size_t scans) {
    const std::string base = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/maze";
    const sim::World world = sim::loadWorldFile(base + ".world");
    const sim::Trajectory trajectory = sim::loadTrajectoryFile(base + ".traj");
    sim::Simulation simulation(world, trajectory, MazeRun::params(1, stamp, slow));
    SegmentOdometry odometry;
    Outcome out;
    std::vector<Pose2D> truth, reported;
    Pose2D chained;
    for (std::size_t i = 0; i < std::min(scans, simulation.numScans()); ++i) {
      const sim::SimulatedFrame f = simulation.next();
      const OdometryStep step = odometry.process(f.scan);
      truth.push_back(f.T_world_robot);
      reported.push_back(step.T_odom_sensor);
      chained = i == 0 ? step.T_odom_sensor : compose(chained, step.increment);
      out.chain_error_m = std::max(out.chain_error_m, std::hypot(chained.x - step.T_odom_sensor.x,
                                                                 chained.y - step.T_odom_sensor.y));
      if (!step.keyframe_revision) continue;
      if (i < 2) {  // the first scan has no reference to be revised against
        ADD_FAILURE() << "scan " << i << " revised a keyframe";
        continue;
      }
      ++out.revisions;
      // The previous scan's heading relative to the one before it, against the truth.
      const double true_turn = wrapAngle(truth[i - 1].yaw - truth[i - 2].yaw);
      const double before = std::abs(wrapAngle(reported[i - 1].yaw - reported[i - 2].yaw - true_turn));
      const double after =
          std::abs(wrapAngle(step.keyframe_revision->T_odom_sensor.yaw - reported[i - 2].yaw - true_turn));
      out.reported_error_rad += before;
      out.revised_error_rad += after;
      out.closer += after < before;
      EXPECT_NE(step.keyframe_revision->segmentation, nullptr);
    }
    std::cout << "maze, SICK at 5 Hz, seed 1, " << scans << " scans, stamped at the "
              << (stamp == ScanStamp::kFirst ? "first" : "last") << " beam: " << out.revisions
              << " keyframes revised, " << out.closer << " closer to the truth (sum of |relative heading error| "
              << out.reported_error_rad
              << " rad as reported, " << out.revised_error_rad << " rad revised); increments chained to "
              << out.chain_error_m << " m of the poses\n";
    return out;
  };
  const Outcome first = run(ScanStamp::kFirst, 537);
  EXPECT_GE(first.revisions, 5u);
  EXPECT_GE(3 * first.closer, 2 * first.revisions);
  EXPECT_LT(first.revised_error_rad, 0.85 * first.reported_error_rad);
  EXPECT_LT(first.chain_error_m, 1e-6);
  const Outcome last = run(ScanStamp::kLast, 300);
  EXPECT_EQ(last.revisions, 0u);
}

// When the segment match fails, the scan is segmented again without motion (the predicted
// rate may be what broke it); when that fails to match too, nothing says the prediction was
// wrong, and its segments stay (decision 115). A scan of the maze's 5 Hz run in the middle of
// a turn, its ranges replaced by a zigzag close to the sensor that nothing in the keyframe
// explains (no search: the scan is lost, and no later step segments it again).
TEST(SegmentOdometry, AScanNoMatchExplainsKeepsThePredictedDeskew) {
  sim::SensorModel slow = sim::SensorModel::sick180();
  slow.frequency_hz = 5.0;
  MazeRun maze(1, ScanStamp::kFirst, slow);
  OdometryParams params;
  params.recovery = false;
  SegmentOdometry odometry(params);
  std::size_t i = 0;
  for (; i < 400 && !(std::abs(odometry.velocity().omega) > 1.0); ++i) odometry.process(maze.simulation.next().scan);
  ASSERT_GT(std::abs(odometry.velocity().omega), 1.0) << "no turn within 400 scans";
  Scan zigzag = maze.simulation.next().scan;
  for (std::size_t b = 0; b < zigzag.ranges_m.size(); ++b) zigzag.ranges_m[b] = b % 2 == 0 ? 0.25 : 0.4;
  zigzag.valid.clear();
  const double predicted = odometry.velocity().omega;
  const OdometryStep step = odometry.process(zigzag);
  std::cout << "scan " << i << " of the turn, ranges replaced: match " << toString(step.match.status) << ", status "
            << toString(step.status) << ", deskewed with " << step.deskewed_with.omega << " rad/s (predicted "
            << predicted << ")\n";
  ASSERT_EQ(step.match.status, MatchStatus::kTooFewMatches);
  ASSERT_EQ(step.status, TrackStatus::kLost);
  EXPECT_EQ(step.deskewed_with.omega, predicted);
}

// The other side of decision 115: when the segmentation without motion does match, it is
// kept. In a turn of the maze's 50 Hz LMS100 run, the scan just processed is given again a
// millisecond later (the robot stopped) with its beam times stretched a hundredfold: deskewed
// with the turn's predicted rate over that 1.5 s sweep its walls bend by radians and match
// nothing; without motion they are the keyframe's walls.
TEST(SegmentOdometry, AScanThatMatchesOnlyWithoutMotionKeepsThatSegmentation) {
  MazeRun maze(1);
  SegmentOdometry odometry;
  Scan last;
  std::size_t i = 0;
  for (; i < 2000 && !(std::abs(odometry.velocity().omega) > 0.5); ++i) {
    last = maze.simulation.next().scan;
    odometry.process(last);
  }
  ASSERT_GT(std::abs(odometry.velocity().omega), 0.5) << "no turn within 2000 scans";
  Scan still = last;
  still.stamp_s += 1e-3;
  for (double& t : still.time_offsets_s) t *= 100.0;
  const double predicted = odometry.velocity().omega;
  const double sweep_s = still.time_offsets_s.back() - still.time_offsets_s.front();
  ASSERT_GT(std::abs(predicted) * sweep_s, 0.5) << "the predicted deskew would not break the match";
  const OdometryStep step = odometry.process(still);
  std::cout << "scan " << i << " of the turn (predicted " << predicted << " rad/s, a " << sweep_s
            << " s sweep): match " << toString(step.match.status) << ", status " << toString(step.status)
            << ", deskewed with " << step.deskewed_with.vx << " m/s, " << step.deskewed_with.omega << " rad/s\n";
  EXPECT_NE(step.match.status, MatchStatus::kTooFewMatches);
  EXPECT_NE(step.status, TrackStatus::kLost);
  EXPECT_EQ(step.deskewed_with.omega, 0.0);
  EXPECT_EQ(step.deskewed_with.vx, 0.0);
  EXPECT_LT(std::hypot(step.increment.x, step.increment.y), 0.02);
}

// The final heading error (rad).
double runHeadingError(const char* world_name, const sim::SensorModel& sensor, std::uint64_t seed, std::size_t scans,
                       const OdometryParams& params) {
  const auto [estimate, truth] = runFinalPoses(world_name, sensor, seed, scans, params);
  return std::abs(wrapAngle(estimate.yaw - truth.yaw));
}

// A 360-degree scanner at 5.5 Hz: the sweep lasts the whole period and, stamped at its first
// beam, spans the motion to the next scan; at a turn's onset the rate it was deskewed with
// is the turn's whole rate off. Estimated with the pose (the sweep model, decision 95), the
// maze's first 300 scans (three turns) end with a heading error four times smaller than with
// the rate from the past (measured, mean of seeds 1 and 2: 0.0038 rad against 0.0158 rad).
TEST(SegmentOdometry, AFullTurnSweepHasItsRateEstimatedWithItsPose) {
  const sim::SensorModel spinning = sim::SensorModel::rplidar360();
  OdometryParams fixed;
  fixed.estimate_sweep_rate = false;
  double with = 0.0, without = 0.0;
  for (const std::uint64_t seed : {1u, 2u}) {
    with += 0.5 * runHeadingError("maze", spinning, seed, 300, OdometryParams{});
    without += 0.5 * runHeadingError("maze", spinning, seed, 300, fixed);
  }
  std::cout << "maze, 360-degree scanner at 5.5 Hz, 300 scans, mean final heading error: sweep rate estimated "
            << with << " rad, from the past " << without << " rad\n";
  EXPECT_LT(with, 0.01);
  EXPECT_LT(with, 0.5 * without);
}

// Drivers stamp a scan at its first, middle or last beam. For each convention, simulated
// 50 Hz LMS100 runs through the maze (rolling shutter, stamps at that beam, no beam times in
// the scans as in a rawlog) are corrected with scanner_rotation_hz and the same convention;
// the correction must beat no correction, and the wrong convention must not beat the right
// one by more than 1 cm. The final error of one run is partly a random walk (a few
// centimetres either way), so each figure is the mean over three seeds.
double mazeFinalError(ScanStamp written, std::optional<ScanStamp> assumed, std::size_t scans) {
  double sum = 0.0;
  const std::uint64_t seeds[] = {3, 4, 5};
  for (const std::uint64_t seed : seeds) {
    MazeRun maze(seed, written);
    sim::Simulation& simulation = maze.simulation;
    OdometryParams params;
    params.scanner_rotation_hz = assumed ? 50.0 : 0.0;
    params.scan_stamp = assumed.value_or(ScanStamp::kFirst);
    SegmentOdometry odometry(params);
    Pose2D gt0, gt_last;
    for (std::size_t i = 0; i < std::min(scans, simulation.numScans()); ++i) {
      sim::SimulatedFrame f = simulation.next();
      f.scan.time_offsets_s.clear();  // as read from a rawlog
      odometry.process(f.scan);
      if (i == 0) gt0 = f.T_world_robot;
      gt_last = f.T_world_robot;
    }
    const Pose2D truth = relative(gt_last, gt0);
    sum += std::hypot(odometry.pose().x - truth.x, odometry.pose().y - truth.y);
  }
  return sum / std::size(seeds);
}

TEST(SegmentOdometry, RollingShutterCorrectionHelpsUnderEveryStampConvention) {
  for (const ScanStamp stamp : {ScanStamp::kFirst, ScanStamp::kMiddle, ScanStamp::kLast}) {
    const double none = mazeFinalError(stamp, std::nullopt, 2500);
    const double right = mazeFinalError(stamp, stamp, 2500);
    std::cout << "stamped at the " << toString(stamp) << " beam: mean final error " << none << " m uncorrected, "
              << right << " m corrected\n";
    EXPECT_LT(right, none) << toString(stamp);
  }
  // The wrong convention (middle-stamped scans corrected as first-stamped) is printed, not
  // asserted: at a constant velocity it deskews every scan about another beam, a rigid shift
  // of the same size for every scan that cancels in the relative motion; it can move the
  // final pose by about v * sweep / 2 (7 mm here), less than these three-seed means spread
  // between changes of the matcher (decision 90).
  const double wrong = mazeFinalError(ScanStamp::kMiddle, ScanStamp::kFirst, 2500);
  std::cout << "middle-stamped, corrected as first: mean final error " << wrong << " m\n";
}

// Honest uncertainty: the normalised estimation error squared of each match's covariance
// against the simulator's ground truth, e' P^-1 e with e the error of T_keyframe_curr.
// For a consistent estimator it follows a chi-square with 3 degrees of freedom: mean 3,
// 95 % of the steps below 7.81.
TEST(SegmentOdometry, CovarianceIsConsistentWithTheErrorsOnTheMaze) {
  MazeRun maze(2);
  sim::Simulation& simulation = maze.simulation;
  SegmentOdometry odometry;
  Pose2D key_truth, key_estimate;
  double sum = 0.0;
  std::size_t n = 0, below = 0;
  for (std::size_t i = 0; i < std::min<std::size_t>(3000, simulation.numScans()); ++i) {
    const sim::SimulatedFrame f = simulation.next();
    const OdometryStep step = odometry.process(f.scan);
    if (!step.first && (step.status == TrackStatus::kOk || step.status == TrackStatus::kRecovered)) {
      const Pose2D truth = relative(f.T_world_robot, key_truth);
      const Pose2D estimate = relative(step.T_odom_sensor, key_estimate);
      const Eigen::Vector3d e(estimate.x - truth.x, estimate.y - truth.y, wrapAngle(estimate.yaw - truth.yaw));
      const double nees = e.dot(step.increment_covariance.ldlt().solve(e));
      sum += nees;
      below += nees <= 7.81;
      ++n;
    }
    if (step.keyframe) {
      key_truth = f.T_world_robot;
      key_estimate = step.T_odom_sensor;
    }
  }
  ASSERT_GT(n, 1000u);
  const double mean = sum / static_cast<double>(n);
  const double share = static_cast<double>(below) / static_cast<double>(n);
  RecordProperty("mean_nees", std::to_string(mean));
  std::cout << "NEES over " << n << " steps: mean " << mean << " (chi-square(3): 3), share <= 7.81: " << share
            << " (0.95)\n";
  // Within the 95 % interval of one chi-square(3) draw, [0.216, 9.35], on average.
  EXPECT_GT(mean, 0.216);
  EXPECT_LT(mean, 9.35);
}

// The 181-beam SICK at 5 Hz through the maze, stamped at the first beam: a turn's onset or
// end changes the rotation rate within one scan interval, each sweep (0.1 s) is deskewed
// with a rate off by up to 1.7 rad/s, and the fits are off by tens of milliradians where the
// residuals show a milliradian. With the rolling-shutter correction's own error in the
// covariance (decision 117), the NEES of the motions from the keyframes is within the 95 %
// interval of a chi-square(3) draw on average (1.1 over seeds 1-3); without it, 60.
// The poses are the same either way.
TEST(SegmentOdometry, ADeskewedScansCovarianceIncludesTheRateChangeOverItsSweep) {
  sim::SensorModel slow = sim::SensorModel::sick180();
  slow.frequency_hz = 5.0;
  const auto meanNees = [&](bool deskew_covariance, std::uint64_t seed, Pose2D& last_pose) {
    MazeRun maze(seed, ScanStamp::kFirst, slow);
    OdometryParams params;
    params.deskew_covariance = deskew_covariance;
    SegmentOdometry odometry(params);
    Pose2D key_truth, key_estimate;
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < maze.simulation.numScans(); ++i) {
      const sim::SimulatedFrame f = maze.simulation.next();
      const OdometryStep step = odometry.process(f.scan);
      if (!step.first && step.status != TrackStatus::kLost) {
        const Pose2D truth = relative(f.T_world_robot, key_truth);
        const Pose2D estimate = relative(step.T_odom_sensor, key_estimate);
        const Eigen::Vector3d e(estimate.x - truth.x, estimate.y - truth.y, wrapAngle(estimate.yaw - truth.yaw));
        sum += e.dot(step.increment_covariance.ldlt().solve(e));
        ++n;
      }
      if (step.keyframe_revision) key_estimate = step.keyframe_revision->T_odom_sensor;
      if (step.keyframe) {
        key_truth = f.T_world_robot;
        key_estimate = step.T_odom_sensor;
      }
    }
    last_pose = odometry.pose();
    return n > 0 ? sum / static_cast<double>(n) : 0.0;
  };
  double with = 0.0, without = 0.0;
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    Pose2D pose_with, pose_without;
    with += meanNees(true, seed, pose_with) / 3.0;
    without += meanNees(false, seed, pose_without) / 3.0;
    EXPECT_EQ(pose_with.x, pose_without.x) << "seed " << seed;
    EXPECT_EQ(pose_with.yaw, pose_without.yaw) << "seed " << seed;
  }
  std::cout << "maze, SICK at 5 Hz, first-stamped, seeds 1-3: mean NEES " << with
            << " with the rolling-shutter term, " << without << " without\n";
  EXPECT_GT(with, 0.216);
  EXPECT_LT(with, 9.35);
  EXPECT_GT(without, 9.35);

  // A stamp 1 ms after the one before (a driver's jitter): the motion measured over that
  // interval is not a velocity of 200 m/s, and no step's covariance grows to metres.
  MazeRun maze(1, ScanStamp::kFirst, slow);
  SegmentOdometry odometry;
  double prev_stamp = 0.0, largest_m = 0.0;
  for (std::size_t i = 0; i < 60; ++i) {
    Scan scan = maze.simulation.next().scan;
    if (i == 30) scan.stamp_s = prev_stamp + 1e-3;
    prev_stamp = scan.stamp_s;
    const OdometryStep step = odometry.process(scan);
    if (step.status == TrackStatus::kDegenerate) continue;  // free along a corridor: 1 m by design
    largest_m = std::max(largest_m, std::sqrt(std::max(step.increment_covariance(0, 0), step.increment_covariance(1, 1))));
  }
  std::cout << "a stamp 1 ms after the last: largest translation sigma " << largest_m << " m\n";
  EXPECT_LT(largest_m, 0.1);
}

TEST(SegmentOdometry, FirstScanIsTheOriginAndTimesAreReported) {
  MazeRun maze(1);
  sim::Simulation& simulation = maze.simulation;
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
  for (double OdometryParams::*key : {&OdometryParams::prior_gate_sigmas, &OdometryParams::prior_accel_m_s2,
                                      &OdometryParams::odometry_error_ratio, &OdometryParams::prior_gate_floor_rad,
                                      &OdometryParams::prior_preference, &OdometryParams::search_preference}) {
    OdometryParams p;
    p.*key = -1.0;
    EXPECT_THROW(SegmentOdometry{p}, std::invalid_argument);
    p.*key = std::nan("");
    EXPECT_THROW(SegmentOdometry{p}, std::invalid_argument);
  }
  OdometryParams lax;
  lax.search_preference = 0.0;  // the bounds are inclusive
  EXPECT_NO_THROW(SegmentOdometry{lax});
  lax.search_preference = 10.5;
  EXPECT_THROW(SegmentOdometry{lax}, std::invalid_argument);
}

}  // namespace
}  // namespace lidarseg
