#include "lidarseg/apps/SimulateApp.h"

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "lidarseg/apps/CommandLine.h"
#include "lidarseg/core/NumberText.h"
#include "lidarseg/mrpt/SimulationConfig.h"
#include "lidarseg/report/OutputFiles.h"
#include "lidarseg/report/Progress.h"
#include "lidarseg/pipeline/SimulationFiles.h"
#include "lidarseg/sim/BuildingGenerator.h"
#include "lidarseg/sim/Simulation.h"
#include "lidarseg/sim/Trajectory.h"
#include "lidarseg/sim/WorldFile.h"

namespace lidarseg::apps {

using report::NamedOutput;
using report::OutputSet;

namespace fs = std::filesystem;

namespace {

// The sensor profile, then the configuration file, then the command line's overrides.
sim::SimulationParams simulationParams(const SimulateOptions& o) {
  sim::SimulationParams params;
  params.sensor = sim::sensorProfile(o.sensor);
  if (!o.config_path.empty()) mrpt_adapter::loadSimulationParamsFile(params, o.config_path);
  params.seed = o.seed;
  params.rolling_shutter = params.rolling_shutter && o.rolling_shutter;
  if (!o.scan_stamp.empty()) params.scan_stamp = scanStampFromString(o.scan_stamp);
  if (o.camera_every_scans >= 0)
    params.camera_every_scans = static_cast<std::size_t>(o.camera_every_scans);
  return params;
}

}  // namespace

SimulateApp::SimulateApp(SimulateOptions options) : options_(std::move(options)) {}

namespace {

// The command line's choices, checked before anything is read or written (usage errors).
void checkOptions(const SimulateOptions& o) {
  if (o.out_prefix.empty()) throw UsageError("no output prefix given (--out)");
  if (o.building_seed && (!o.world_path.empty() || !o.trajectory_path.empty())) {
    throw UsageError("--building replaces --world and --trajectory: give one or the other");
  }
  if (!o.building_seed && (o.world_path.empty() || o.trajectory_path.empty())) {
    throw UsageError("give --world and --trajectory, or --building SEED");
  }
  checkedOption("--sensor-model", [&] { (void)sim::sensorProfile(o.sensor); });
  if (!o.scan_stamp.empty()) checkedOption("--scan-stamp", [&] { (void)scanStampFromString(o.scan_stamp); });
}

}  // namespace

SimulateReport SimulateApp::run() {
  checkOptions(options_);
  // Before any work: an output that is an input is refused, a second writer at once; the
  // lock is held until the temporaries of a failed run are removed.
  OutputSet claimed;
  std::vector<NamedOutput> files;
  for (const char* ext : {".rawlog", ".gt.tum", ".odom.tum", ".features.csv", ".rois.csv", ".carmen.log"}) {
    files.push_back({options_.out_prefix + ext, "--out"});
  }
  // A generated building is written out too (writeBuildingFiles()): never over an input.
  if (options_.building_seed) {
    for (const char* ext : {".world", ".traj", ".doors.csv"}) files.push_back({options_.out_prefix + ext, "--out"});
  }
  claimed.claimOutputs(files, {}, {options_.world_path, options_.trajectory_path, options_.config_path});
  try {
    SimulateReport report = runOrThrow();
    claimed.commit();
    return report;
  } catch (...) {
    // Leave nothing half-written behind.
    std::error_code ec;
    fs::remove_all(options_.out_prefix + "_Images.tmp", ec);
    report::releaseTemporary(options_.out_prefix + "_Images.tmp");
    throw;
  }
}

namespace {

// The world and trajectory: a generated building's, or read from -w/-t.
struct Scene {
  std::optional<sim::Building> building;
  sim::World world;
  sim::Trajectory trajectory;
};

// A robot driven through a wall (a waypoint on the wrong side, a closed door on the way)
// would give scans no robot can take: refused, naming the leg, the place and the wall.
void refusePathThroughWalls(const SimulateOptions& o, const sim::World& world, const sim::Trajectory& trajectory) {
  const auto crossing = sim::firstWallCrossing(world, trajectory);
  const auto point = [](const Eigen::Vector2d& p) { return "(" + numberText(p.x()) + ", " + numberText(p.y()) + ")"; };
  if (!crossing) {
    // Crossing no outline, a path that starts inside clutter stays inside it.
    const Eigen::Vector2d start = trajectory.waypoints().front();
    const auto holding = sim::clutterHolding(world, start);
    if (!holding) return;
    const sim::Wall& side = world.walls()[*holding];
    const std::string path = o.building_seed ? "building " + std::to_string(*o.building_seed) : "'" + o.trajectory_path + "'";
    const std::string in = o.building_seed ? std::string() : " of '" + o.world_path + "'";
    throw std::runtime_error(path + ": the path runs inside clutter" + in + " from its start " + point(start) +
                             " (the piece with the side from " + point(side.a) + " to " + point(side.b) + ")");
  }
  const sim::Wall& wall = world.walls()[crossing->wall];
  const std::size_t leg = trajectory.legAtDistance(crossing->s_m);
  const auto& wp = trajectory.waypoints();
  const char* what = wall.kind == sim::SurfaceKind::kDoor ? "a door leaf" : wall.kind == sim::SurfaceKind::kClutter ? "clutter" : "a wall";
  const std::string path = o.building_seed ? "building " + std::to_string(*o.building_seed) : "'" + o.trajectory_path + "'";
  const std::string in = o.building_seed ? std::string() : " of '" + o.world_path + "'";
  throw std::runtime_error(path + ": the path goes through " + what + in + " at " + point(crossing->point) + ", " +
                           numberText(std::round(crossing->s_m * 1e3) / 1e3) + " m from its start, on the leg from waypoint " +
                           std::to_string(leg + 1) + " " + point(wp[leg]) + " to waypoint " + std::to_string(leg + 2) + " " +
                           point(wp[leg + 1]) + " (it runs from " + point(wall.a) + " to " + point(wall.b) + ")");
}

Scene loadScene(const SimulateOptions& o) {
  std::optional<sim::Building> building;
  if (o.building_seed) {
    if (!o.world_path.empty() || !o.trajectory_path.empty()) {
      throw std::invalid_argument("--building replaces --world and --trajectory: give one or the other");
    }
    building = sim::generateBuilding(*o.building_seed);
  } else if (o.world_path.empty() || o.trajectory_path.empty()) {
    throw std::invalid_argument("give --world and --trajectory, or --building SEED");
  }
  sim::World world = building ? building->world() : sim::loadWorldFile(o.world_path);
  sim::Trajectory trajectory = building ? building->trajectory() : sim::loadTrajectoryFile(o.trajectory_path);
  refusePathThroughWalls(o, world, trajectory);
  return Scene{std::move(building), std::move(world), std::move(trajectory)};
}

// The generated building as files: the same run again with -w/-t, and its doors (none
// without a building). Committed with the run's other outputs.
std::vector<std::unique_ptr<report::PendingFile>> writeBuildingFiles(const std::string& prefix,
                                                                       const std::optional<sim::Building>& building) {
  std::vector<std::unique_ptr<report::PendingFile>> files;
  if (!building) return files;
  for (const char* ext : {".world", ".traj", ".doors.csv"}) {
    files.push_back(std::make_unique<report::PendingFile>(prefix + ext));
  }
  sim::writeWorldFile(files[0]->out(), *building);
  sim::writeTrajectoryFile(files[1]->out(), *building);
  sim::writeDoorTable(files[2]->out(), *building);
  return files;
}

// Every scan of the simulation into the files, with progress on stderr.
void simulateScans(sim::Simulation& simulation, pipeline::SimulationFiles& files, bool show_progress) {
  report::Progress progress("lidarseg-simulate", show_progress, simulation.numScans());
  for (std::size_t i = 0; i < simulation.numScans(); ++i) {
    files.write(i, simulation.next());
    progress.update(i + 1);
  }
  progress.done(simulation.numScans());
}

// What the run wrote, with the trajectory's length and duration.
SimulateReport reportOf(const std::string& prefix, const sim::Trajectory& trajectory,
                        const pipeline::SimulationCounts& counts) {
  SimulateReport report;
  report.rawlog_path = prefix + ".rawlog";
  report.length_m = trajectory.length();
  report.duration_s = trajectory.duration();
  report.scans = counts.scans;
  report.images = counts.images;
  report.door_sightings = counts.door_sightings;
  report.corner_sightings = counts.corner_sightings;
  return report;
}

}  // namespace

SimulateReport SimulateApp::runOrThrow() {
  const Scene scene = loadScene(options_);
  const sim::SimulationParams params = simulationParams(options_);
  sim::Simulation simulation(scene.world, scene.trajectory, params);
  pipeline::prepareSimulationFolders(options_.out_prefix, params.camera_every_scans > 0);
  auto building_files = writeBuildingFiles(options_.out_prefix, scene.building);
  pipeline::SimulationFiles files(options_.out_prefix, params, scene.world, options_.world_path, options_.write_carmen);
  simulateScans(simulation, files, options_.progress);
  std::vector<report::PendingFile*> companions;
  for (auto& f : building_files) companions.push_back(f.get());
  files.commit(companions);  // the rawlog last
  return reportOf(options_.out_prefix, scene.trajectory, files.counts());
}

std::string simulationPrefix(const std::string& out, const std::string& world_path) {
  std::error_code ec;
  const bool folder = (!out.empty() && out.back() == '/') || fs::is_directory(out, ec);
  if (!folder) return out;
  return (fs::path(out) / fs::path(world_path).stem()).string();
}

}  // namespace lidarseg::apps
