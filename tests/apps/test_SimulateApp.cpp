// lidarseg-simulate run as a class: outputs, determinism per seed, ground truth, errors.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include <unistd.h>

#include <gtest/gtest.h>

#include "TempFiles.h"
#include "FolderEvents.h"

#include "lidarseg/apps/SimulateApp.h"
#include "lidarseg/report/OutputFiles.h"
#include "lidarseg/logs/CarmenLogReader.h"
#include "lidarseg/mrpt/RawlogScanReader.h"
#include "lidarseg/mrpt/ScanConverter.h"

namespace lidarseg::apps {
namespace {
namespace fs = std::filesystem;
const std::string kWorlds = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/";
const std::string kTmp = std::string(LIDARSEG_TEST_TMP_DIR) + "/sim";

// This test's own folder (see testing::testFolder).
std::string testDir() { return lidarseg::testing::testFolder(kTmp); }

using lidarseg::testing::slurp;

// A 12 m run along the hospital's bottom corridor, past four doors.
SimulateOptions shortRun(const std::string& name, std::uint64_t seed) {
  fs::create_directories(kTmp);
  const std::string traj = testDir() + "/short.traj";
  std::ofstream(traj) << "speed 1.5\nturn_radius 0.5\nwaypoint 0 0\nwaypoint 12 0\n";
  SimulateOptions o;
  o.world_path = kWorlds + "hospital.world";
  o.trajectory_path = traj;
  o.seed = seed;
  o.out_prefix = testDir() + "/" + name;
  o.camera_every_scans = 50;
  o.write_carmen = true;
  return o;
}

TEST(SimulateApp, WritesEveryOutputAndTheSameBytesForTheSameSeed) {
  const SimulateReport a = SimulateApp(shortRun("a", 7)).run();
  const SimulateReport b = SimulateApp(shortRun("b", 7)).run();
  const SimulateReport c = SimulateApp(shortRun("c", 8)).run();
  EXPECT_EQ(a.scans, 401u);  // 8 s at 50 Hz, both ends included
  EXPECT_EQ(a.images, 9u);
  for (const char* ext : {".rawlog", ".gt.tum", ".odom.tum", ".features.csv", ".rois.csv", ".carmen.log",
                          "_Images/img_000004.png"}) {
    const std::string pa = testDir() + "/a" + ext, pb = testDir() + "/b" + ext;
    ASSERT_TRUE(fs::exists(pa)) << pa;
    EXPECT_EQ(slurp(pa), slurp(pb)) << ext << " differs for the same seed";
  }
  EXPECT_NE(slurp(testDir() + "/a.rawlog"), slurp(testDir() + "/c.rawlog"));
  EXPECT_EQ(slurp(testDir() + "/a.gt.tum"), slurp(testDir() + "/c.gt.tum"));  // the truth has no noise
  EXPECT_FALSE(fs::exists(testDir() + "/a.rawlog.tmp"));
  EXPECT_GT(a.door_sightings, 0u);
}

using lidarseg::testing::FolderEvents;

std::ptrdiff_t positionOf(const std::vector<std::string>& events, const std::string& event) {
  return std::find(events.begin(), events.end(), event) - events.begin();
}

// A reader opens the rawlog: when a second run replaces a first, the old rawlog goes before
// its images folder, and the new one appears after the new images folder, last (issue 16).
TEST(SimulateApp, ARerunPublishesItsRawlogLastAfterItsImagesFolder) {
  SimulateApp(shortRun("rerun", 7)).run();
  FolderEvents events(testDir());
  ASSERT_TRUE(events.watching());
  const SimulateReport r = SimulateApp(shortRun("rerun", 8)).run();
  const std::vector<std::string> order = events.read();
  ASSERT_FALSE(order.empty());
  EXPECT_EQ(order.back(), "+rerun.rawlog");
  const auto at = [&](const std::string& e) { return positionOf(order, e); };
  const auto n = static_cast<std::ptrdiff_t>(order.size());
  ASSERT_LT(at("-rerun.rawlog"), n);
  ASSERT_LT(at("-rerun_Images"), n);
  ASSERT_LT(at("+rerun_Images"), n);
  EXPECT_LT(at("-rerun.rawlog"), at("-rerun_Images")) << "an old rawlog stood beside no images";
  EXPECT_LT(at("+rerun_Images"), at("+rerun.rawlog"));
  EXPECT_EQ(std::count(order.begin(), order.end(), "+rerun.rawlog"), 1);
  // The folder now holds the second run's images.
  std::size_t images = 0;
  for (const auto& e : fs::directory_iterator(testDir() + "/rerun_Images")) images += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(images, r.images);
  EXPECT_FALSE(fs::exists(testDir() + "/rerun_Images.tmp"));
}

TEST(SimulateApp, GeneratedBuildingWritesItsWorldAndTrajectoryThatReproduceTheRun) {
  fs::create_directories(kTmp);
  SimulateOptions o;
  o.building_seed = 4;  // a tuning seed
  o.out_prefix = kTmp + "/building";
  o.camera_every_scans = 0;
  const SimulateReport r = SimulateApp(o).run();
  EXPECT_GT(r.scans, 1000u);
  EXPECT_GT(r.door_sightings, 100u);
  const std::string doors = slurp(kTmp + "/building.doors.csv");
  EXPECT_EQ(doors.rfind("id,kind,width,double,recess,thickness", 0), 0u);
  // The same run from the files it wrote: the same truth, the same scans.
  SimulateOptions again;
  again.world_path = kTmp + "/building.world";
  again.trajectory_path = kTmp + "/building.traj";
  again.out_prefix = kTmp + "/building_again";
  again.camera_every_scans = 0;
  SimulateApp(again).run();
  EXPECT_TRUE(slurp(kTmp + "/building.features.csv") == slurp(kTmp + "/building_again.features.csv"));
  EXPECT_TRUE(slurp(kTmp + "/building.rawlog") == slurp(kTmp + "/building_again.rawlog"));
  // One or the other, not both.
  o.world_path = kWorlds + "hospital.world";
  EXPECT_THROW(SimulateApp(o).run(), std::invalid_argument);
  SimulateOptions none;
  none.out_prefix = kTmp + "/none";
  EXPECT_THROW(SimulateApp(none).run(), std::invalid_argument);
}

TEST(SimulateApp, GroundTruthMatchesTheTrajectoryAndTheRawlog) {
  SimulateApp(shortRun("gt", 3)).run();
  std::ifstream gt(testDir() + "/gt.gt.tum");
  std::string line;
  std::getline(gt, line);  // header
  std::vector<std::array<double, 8>> rows;
  while (std::getline(gt, line)) {
    std::istringstream is(line);
    std::array<double, 8> r{};
    for (double& v : r) is >> v;
    rows.push_back(r);
  }
  ASSERT_EQ(rows.size(), 401u);
  EXPECT_NEAR(rows.front()[1], 0.0, 1e-9);
  EXPECT_NEAR(rows.back()[1], 12.0, 1e-6);
  EXPECT_NEAR(rows[200][1], 6.0, 1e-6);  // 1.5 m/s * 4 s
  EXPECT_NEAR(rows[1][0] - rows[0][0], 0.02, 1e-6);  // 50 Hz (epoch seconds: ~2e-7 s resolution)
  // The rawlog's scans carry the same timestamps and a valid LMS100 geometry.
  mrpt_adapter::RawlogScanReader reader(testDir() + "/gt.rawlog");
  std::size_t n = 0;
  while (auto s = reader.next()) {
    EXPECT_NEAR(mrpt::Clock::toDouble(s->observation->timestamp), rows[n][0], 1e-5);
    EXPECT_EQ(s->observation->getScanSize(), 541u);
    EXPECT_NEAR(s->observation->aperture, 1.5 * M_PI, 1e-5);
    ++n;
  }
  EXPECT_EQ(n, 401u);
  EXPECT_EQ(reader.sensorLabel(), "LIDAR");
  // CARMEN: one ROBOTLASER1 and one ODOM line per scan.
  std::ifstream carmen(testDir() + "/gt.carmen.log");
  std::size_t lasers = 0, odoms = 0;
  while (std::getline(carmen, line)) {
    lasers += line.rfind("ROBOTLASER1 ", 0) == 0;
    odoms += line.rfind("ODOM ", 0) == 0;
  }
  EXPECT_EQ(lasers, 401u);
  EXPECT_EQ(odoms, 401u);
}

// Issue 16: a configured beam count and field of view reach the CARMEN file as they reach
// the rawlog (its ROBOTLASER1 lines carried the sensor profile's 270 degrees for 181 beams
// over 180, so every reader of the CARMEN file saw another sensor).
TEST(SimulateApp, TheCarmenFileCarriesTheConfiguredBeamLayout) {
  const std::string ini = testDir() + "/half.ini";
  std::ofstream(ini) << "[simulation]\nnum_beams = 181\nfield_of_view_rad = 3.141592653589793\n";
  SimulateOptions o = shortRun("half", 2);
  o.config_path = ini;
  o.camera_every_scans = 0;
  SimulateApp(o).run();
  mrpt_adapter::RawlogScanReader rawlog(o.out_prefix + ".rawlog");
  const auto first = rawlog.next();
  ASSERT_TRUE(first);
  ASSERT_EQ(first->observation->getScanSize(), 181u);
  EXPECT_NEAR(first->observation->aperture, M_PI, 1e-6);
  logs::CarmenLogReader carmen(o.out_prefix + ".carmen.log");
  std::size_t lines = 0;
  while (const auto laser = carmen.next()) {
    ASSERT_EQ(laser->ranges_m.size(), 181u);
    EXPECT_NEAR(laser->angular_resolution_rad * 180.0, M_PI, 1e-4) << "line " << laser->line;
    EXPECT_NEAR(laser->start_angle_rad, -0.5 * M_PI, 1e-5) << "line " << laser->line;
    ++lines;
  }
  EXPECT_GT(lines, 50u);
}

TEST(SimulateApp, BadInputNamesTheFileAndLeavesNoOutput) {
  const std::string bad = testDir() + "/bad.world";
  fs::create_directories(kTmp);
  std::ofstream(bad) << "wall 0 0 10 0\nwall 0 0 0\n";
  SimulateOptions o = shortRun("bad", 1);
  o.world_path = bad;
  try {
    SimulateApp(o).run();
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), bad + ":2: 'wall' expects 4 numbers, got 3");
  }
  EXPECT_FALSE(fs::exists(testDir() + "/bad.rawlog"));
  o = shortRun("bad", 1);
  o.sensor = "lms200";
  EXPECT_THROW(SimulateApp(o).run(), std::invalid_argument);
  EXPECT_FALSE(fs::exists(testDir() + "/bad.rawlog.tmp"));
}

// A path through a wall was simulated as if the robot passed through it (issue 16): refused
// before anything is written, naming the trajectory, the world, the leg and the wall.
TEST(SimulateApp, APathThroughAWallIsRefusedNamingTheLegAndTheWall) {
  SimulateOptions o = shortRun("through", 1);
  // From the bottom corridor up through the wall at y = 1.2 (hospital.world).
  std::ofstream(o.trajectory_path) << "speed 1\nturn_radius 0.5\nwaypoint 5 0\nwaypoint 15 0\nwaypoint 15 8\n";
  try {
    SimulateApp(o).run();
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("'" + o.trajectory_path + "': the path goes through a wall of '" + o.world_path + "' at (15, 1.2)", 0), 0u)
        << what;
    EXPECT_NE(what.find("on the leg from waypoint 2 (15, 0) to waypoint 3 (15, 8)"), std::string::npos) << what;
  }
  EXPECT_FALSE(fs::exists(o.out_prefix + ".rawlog"));
  EXPECT_FALSE(fs::exists(o.out_prefix + ".gt.tum"));
}

// --building writes PREFIX.world, PREFIX.traj and PREFIX.doors.csv: a configuration file of
// one of those names was overwritten by the run (issue 16). Refused before anything is read.
TEST(SimulateApp, ABuildingFileOverAnInputIsAUsageErrorAndLeavesTheInput) {
  for (const char* ext : {".traj", ".world", ".doors.csv"}) {
    SimulateOptions o;
    o.building_seed = 4;
    o.out_prefix = testDir() + "/own";
    o.config_path = o.out_prefix + ext;
    std::ofstream(o.config_path) << "# a simulation configuration\n";
    try {
      SimulateApp(o).run();
      FAIL() << "no error for " << ext;
    } catch (const report::UsageError& e) {
      EXPECT_EQ(std::string(e.what()), "--out '" + o.config_path + "' is the input '" + o.config_path +
                                           "': an output never overwrites its input");
    }
    EXPECT_EQ(slurp(o.config_path), "# a simulation configuration\n");
    EXPECT_FALSE(fs::exists(o.out_prefix + ".rawlog"));
  }
}

}  // namespace
}  // namespace lidarseg::apps
