#pragma once
/// @file SimulateApp.h
/// The logic of `lidarseg-simulate`: a simulated run written as an MRPT rawlog with its
/// ground truth.

#include <cstdint>
#include <optional>
#include <string>

namespace lidarseg::apps {

/// Command-line options of `lidarseg-simulate`.
struct SimulateOptions {
  std::string world_path;         ///< config/worlds/*.world
  std::string trajectory_path;    ///< config/worlds/*.traj
  /// Instead of a world and a trajectory file: the generated building of this seed
  /// (sim::generateBuilding with its default parameters) and its loop; the run also writes
  /// PREFIX.world, PREFIX.traj (the same run again with -w/-t) and PREFIX.doors.csv.
  std::optional<std::uint64_t> building_seed;
  std::string sensor = "lms100";  ///< sensor profile: lms100, utm30lx, sick180, rplidar360
  /// Optional INI/YAML with a [simulation] section (config/simulate.ini).
  std::string config_path;
  std::uint64_t seed = 1;  ///< noise seed: the same seed gives the same bytes
  /// Output prefix: writes PREFIX.rawlog, PREFIX_Images/, PREFIX.gt.tum, PREFIX.odom.tum,
  /// PREFIX.features.csv, PREFIX.rois.csv (and PREFIX.carmen.log).
  std::string out_prefix;
  /// Each beam measured at its own instant; false: every beam of a scan from one pose.
  bool rolling_shutter = true;
  /// Which beam's instant the scans are stamped with; empty: the configuration's.
  std::string scan_stamp;
  /// -1: keep the configuration's value; 0: no camera; N: an image every N scans.
  long camera_every_scans = -1;
  bool write_carmen = false;  ///< also write PREFIX.carmen.log
  /// Progress with rate and ETA on stderr (shown only when stderr is a terminal; -q: off).
  bool progress = true;
};

/// What a run produced.
struct SimulateReport {
  std::size_t scans = 0;             ///< scans written
  std::size_t images = 0;            ///< camera images written (PREFIX_Images/)
  double length_m = 0.0;             ///< trajectory length (m)
  double duration_s = 0.0;           ///< trajectory duration (s)
  std::size_t door_sightings = 0;    ///< rows of PREFIX.features.csv that are doors
  std::size_t corner_sightings = 0;  ///< rows of PREFIX.features.csv that are corners
  std::string rawlog_path;           ///< PREFIX.rawlog
};

/// Simulates the run and writes every output atomically (temporary names renamed at the
/// end: an error leaves no partial file).
class SimulateApp {
 public:
  explicit SimulateApp(SimulateOptions options);
  /// @throws std::runtime_error / std::invalid_argument naming the file and line or key.
  SimulateReport run();

 private:
  // Loads the inputs, simulates scan by scan and publishes the outputs; run() cleans up.
  SimulateReport runOrThrow();
  SimulateOptions options_;
};

/// The file prefix of a simulated run written to `out` (docs/cli.md): a folder when `out`
/// ends in '/' or is an existing folder (then DIR/WORLD, WORLD the world file's stem),
/// else `out` itself, the older prefix form.
std::string simulationPrefix(const std::string& out, const std::string& world_path);

}  // namespace lidarseg::apps
