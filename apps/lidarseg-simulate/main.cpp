// lidarseg-simulate: a robot with a lidar, wheel odometry and a camera driving through a
// simulated building; writes an MRPT rawlog and its ground truth.
#include <iostream>

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include "lidarseg/apps/CommandLine.h"
#include "lidarseg/apps/SimulateApp.h"

int main(int argc, char** argv) {
  try {
    TCLAP::CmdLine cmd("Simulate a lidar + camera run with ground truth (MRPT rawlog output)", ' ', "0.1.0");
    TCLAP::ValueArg<std::string> world("w", "world", "world file (config/worlds/*.world)", false, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> traj("t", "trajectory", "trajectory file (config/worlds/*.traj)", false, "", "FILE", cmd);
    TCLAP::ValueArg<std::uint64_t> building("", "building",
                                            "a generated building of this seed and its loop, instead of -w/-t "
                                            "(also writes PREFIX.world, PREFIX.traj, PREFIX.doors.csv)",
                                            false, 0, "SEED", cmd);
    TCLAP::ValueArg<std::string> sensor("", "sensor-model", "simulated sensor: lms100, utm30lx, sick180, rplidar360", false, "lms100",
                                        "NAME", cmd);
    TCLAP::ValueArg<std::string> config("c", "config", "INI/YAML with a [simulation] section", false, "", "FILE", cmd);
    TCLAP::ValueArg<std::uint64_t> seed("", "seed", "noise seed (same seed, same bytes)", false, 1, "N", cmd);
    TCLAP::ValueArg<std::string> out("o", "out",
                                     "output folder (a name ending in / or an existing folder: writes DIR/WORLD.rawlog, "
                                     "...), or a file prefix (writes PREFIX.rawlog, ...)",
                                     true, "", "DIR", cmd);
    TCLAP::SwitchArg quiet("q", "quiet", "no progress on stderr", cmd);
    TCLAP::ValueArg<std::string> scan_stamp("", "scan-stamp", "stamp each scan at its first, middle or last beam",
                                            false, "", "first|middle|last", cmd);
    TCLAP::SwitchArg no_rs("", "no-rolling-shutter", "measure every beam of a scan from one pose", cmd);
    TCLAP::ValueArg<long> camera("", "camera-every", "an image every N scans (0: no camera)", false, -1, "N", cmd);
    TCLAP::SwitchArg carmen("", "carmen", "also write PREFIX.carmen.log (ROBOTLASER1/ODOM)", cmd);
    if (const auto status = lidarseg::apps::parseCommandLine(cmd, argc, argv, "lidarseg-simulate",
                                                             {{"-s", "--sensor-model"}, {"--sensor", "--sensor-model"}})) return *status;

    if (camera.isSet() && camera.getValue() < 0) {
      std::cerr << "lidarseg-simulate: usage error: --camera-every: " << camera.getValue()
                << " is negative (0: no camera, N: an image every N scans)\n";
      return lidarseg::apps::kUsageError;
    }
    lidarseg::apps::SimulateOptions o;
    o.world_path = world.getValue();
    o.trajectory_path = traj.getValue();
    if (building.isSet()) o.building_seed = building.getValue();
    o.sensor = sensor.getValue();
    o.config_path = config.getValue();
    o.seed = seed.getValue();
    o.out_prefix = lidarseg::apps::simulationPrefix(
        out.getValue(), building.isSet() ? "building" + std::to_string(building.getValue()) : world.getValue());
    o.progress = !quiet.getValue();
    o.rolling_shutter = !no_rs.getValue();
    o.scan_stamp = scan_stamp.getValue();
    o.camera_every_scans = camera.getValue();
    o.write_carmen = carmen.getValue();
    const auto r = lidarseg::apps::SimulateApp(o).run();
    std::cout << "lidarseg-simulate: " << r.rawlog_path << ": " << r.scans << " scans, " << r.images
              << " images, " << r.length_m << " m in " << r.duration_s << " s; "
              << r.door_sightings << " door and " << r.corner_sightings << " corner sightings\n";
    return lidarseg::apps::exitAfterStdout("lidarseg-simulate", 0);
  } catch (const std::exception& e) {
    return lidarseg::apps::errorExit("lidarseg-simulate", e);
  }
}
