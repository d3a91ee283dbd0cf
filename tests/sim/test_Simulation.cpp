#include <cmath>

#include <gtest/gtest.h>

#include "lidarseg/sim/Simulation.h"
#include "lidarseg/sim/WorldFile.h"

namespace lidarseg::sim {
namespace {
const std::string kWorlds = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/";

TEST(Simulation, FramesTimesOdometryAndImages) {
  const World world = loadWorldFile(kWorlds + "maze.world");
  const Trajectory traj = loadTrajectoryFile(kWorlds + "maze.traj");
  SimulationParams p;
  p.camera_every_scans = 100;
  Simulation sim(world, traj, p);
  EXPECT_EQ(sim.numScans(), static_cast<std::size_t>(std::floor(traj.duration() * 50.0)) + 1);
  double drift_at_50m = 0.0;
  for (std::size_t i = 0; i < 2600; ++i) {
    const SimulatedFrame f = sim.next();
    EXPECT_NEAR(f.stamp_s - p.start_time_s, 0.02 * static_cast<double>(i), 1e-6);
    EXPECT_EQ(f.has_image, i % 100 == 0);
    if (i == 0) {
      EXPECT_NEAR(f.odometry.x, f.T_world_robot.x, 1e-12);
      EXPECT_NEAR(f.odometry.yaw, f.T_world_robot.yaw, 1e-12);
    }
    if (i == 2500) drift_at_50m = std::hypot(f.odometry.x - f.T_world_robot.x, f.odometry.y - f.T_world_robot.y);
  }
  // 2 %/m translation and 0.005 rad/m heading noise over 50 m: clearly off, not absurd.
  EXPECT_GT(drift_at_50m, 0.02);
  EXPECT_LT(drift_at_50m, 10.0);
}

TEST(Simulation, ACrawlingTrajectoryIsRefusedNotPlannedForever) {
  const World world = loadWorldFile(kWorlds + "maze.world");
  const Trajectory crawl({{24, 0}, {34, 0}}, 1e-6, 0.6);  // 10 m at 1 um/s: 5e8 scans at 50 Hz
  SimulationParams p;
  try {
    Simulation sim(world, crawl, p);
    FAIL() << "planned " << sim.numScans() << " scans";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("more than the"), std::string::npos) << e.what();
  }
}

TEST(Simulation, BeamCountAndFieldOfViewCanBeOverridden) {
  const World world = loadWorldFile(kWorlds + "maze.world");
  const Trajectory traj = loadTrajectoryFile(kWorlds + "maze.traj");
  SimulationParams p;
  p.num_beams = 181;
  p.field_of_view_rad = 3.14159265358979323846;
  p.camera_every_scans = 0;
  Simulation sim(world, traj, p);
  const SimulatedFrame f = sim.next();
  EXPECT_EQ(f.scan.size(), 181u);
  EXPECT_NEAR(f.scan.layout->angle(0), -3.14159265358979323846 / 2, 1e-12);
  EXPECT_FALSE(f.has_image);
  p.num_beams = 1;
  EXPECT_THROW(Simulation(world, traj, p), std::invalid_argument);
}

}  // namespace
}  // namespace lidarseg::sim
