#include "lidarseg/apps/SimulateApp.h"
#include "lidarseg/pipeline/Progress.h"
#include "lidarseg/core/Angles.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include <mrpt/core/Clock.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include "lidarseg/pipeline/OutputFiles.h"
#include "lidarseg/mrpt/ScanConverter.h"
#include "lidarseg/mrpt/SimulationConfig.h"
#include "lidarseg/sim/BuildingGenerator.h"
#include "lidarseg/sim/Simulation.h"
#include "lidarseg/sim/Trajectory.h"
#include "lidarseg/sim/WorldFile.h"

namespace lidarseg::apps {

using pipeline::NamedOutput;
using pipeline::OutputSet;

namespace fs = std::filesystem;

namespace {

// A text output written under a unique temporary name (removed by the SIGINT/SIGTERM
// handler, decision 47) and renamed when the run succeeds.
class PendingFile {
 public:
  explicit PendingFile(std::string path)
      : path_(std::move(path)), tmp_(pipeline::uniqueTemporary(path_)), out_(tmp_) {
    if (!out_) {
      pipeline::releaseTemporary(tmp_);
      throw std::runtime_error("cannot write '" + tmp_ + "'");
    }
    out_ << std::fixed;
  }
  std::ofstream& out() { return out_; }
  void commit() {
    out_.close();
    if (!out_) throw std::runtime_error("error while writing '" + tmp_ + "' (disk full?)");
    fs::rename(tmp_, path_);
    pipeline::releaseTemporary(tmp_);
  }
  ~PendingFile() {
    if (out_.is_open()) {
      out_.close();
      std::error_code ec;
      fs::remove(tmp_, ec);
      pipeline::releaseTemporary(tmp_);
    }
  }
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

 private:
  std::string path_, tmp_;
  std::ofstream out_;
};

// TUM trajectory line: time x y z qx qy qz qw (rotation about z only).
void writeTum(std::ostream& os, double t, const Pose2D& p, double z) {
  os << std::setprecision(9) << t << ' ' << p.x << ' ' << p.y << ' ' << z << ' ' << 0.0 << ' '
     << 0.0 << ' ' << std::sin(0.5 * p.yaw) << ' ' << std::cos(0.5 * p.yaw) << '\n';
}

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

// Creates the output's folder, and an empty PREFIX_Images.tmp/ when the run has a camera,
// registered for the SIGINT/SIGTERM cleanup like the files' temporaries. Its name is fixed
// (the folder lock keeps a second run away): a killed run's is removed by the next.
void prepareFolders(const std::string& prefix, bool camera) {
  const fs::path parent = fs::path(prefix).parent_path();
  if (!parent.empty()) fs::create_directories(parent);
  std::error_code ec;
  fs::remove_all(prefix + "_Images.tmp", ec);
  if (camera) {
    pipeline::registerTemporaryFolder(prefix + "_Images.tmp");
    fs::create_directories(prefix + "_Images.tmp");
  }
}

// The frame's image saved as DIR/NAME (PNG), in an observation that refers to that file.
mrpt::obs::CObservationImage::Ptr imageObservation(const sim::SimulatedFrame& f,
                                                   const sim::PinholeCamera& cam,
                                                   const std::string& dir,
                                                   const std::string& name) {
  mrpt::img::CImage img;
  auto rgb = f.image.rgb;
  img.loadFromMemoryBuffer(static_cast<unsigned>(f.image.width),
                           static_cast<unsigned>(f.image.height), true, rgb.data(), true);
  if (!img.saveToFile(dir + "/" + name))
    throw std::runtime_error("cannot write image '" + dir + "/" + name + "'");
  img.setExternalStorage(name);
  auto obs = mrpt::obs::CObservationImage::Create();
  obs->sensorLabel = "CAMERA";
  obs->timestamp = mrpt::Clock::fromDouble(f.stamp_s);
  // MRPT camera pose: +z forward, +x right, +y down, in the robot frame.
  obs->cameraPose =
      mrpt::poses::CPose3D(cam.x_m, cam.y_m, cam.z_m, cam.yaw_rad - 0.5 * kPi, 0.0, -0.5 * kPi);
  obs->cameraParams.ncols = static_cast<uint32_t>(cam.width);
  obs->cameraParams.nrows = static_cast<uint32_t>(cam.height);
  obs->cameraParams.setIntrinsicParamsFromValues(cam.fx, cam.fy, cam.cx, cam.cy);
  obs->image = std::move(img);
  return obs;
}

// A PREFIX.features.csv row: one door or corner the lidar sees in scan `i` at time `t`.
void writeFeatureRow(std::ostream& os, std::size_t i, double t, const sim::Feature& ft) {
  os << std::setprecision(9) << i << ',' << t << ',' << lidarseg::toString(ft.type) << ','
     << std::setprecision(4) << ft.position.x() << ',' << ft.position.y() << ',' << ft.theta_rad
     << ',' << ft.width_m << ',' << ft.id << ',' << (ft.resolvable ? 1 : 0) << ','
     << lidarseg::toString(ft.seen_as) << '\n';
}

// The ROBOTLASER1 and ODOM lines of one scan (CARMEN); both poses are the wheel odometry.
void writeCarmenLines(std::ostream& c, const sim::SimulatedFrame& f,
                      const sim::SensorModel& sensor) {
  const double fov = std::abs(sensor.layout->angles().back() - sensor.layout->angles().front());
  const double step = fov / static_cast<double>(f.scan.size() - 1);
  const double t = f.stamp_s;
  c << std::setprecision(6) << "ROBOTLASER1 0 " << -0.5 * fov << ' ' << fov << ' ' << step << ' '
    << sensor.max_range_m << " 0.01 0 " << f.scan.size();
  c << std::setprecision(4);
  for (double r : f.scan.ranges_m) c << ' ' << r;
  c << " 0 " << f.odometry.x << ' ' << f.odometry.y << ' ' << f.odometry.yaw << ' ' << f.odometry.x
    << ' ' << f.odometry.y << ' ' << f.odometry.yaw << " 0 0 0 0 0 " << std::setprecision(6) << t
    << " lidarseg-sim " << t << '\n';
  c << "ODOM " << std::setprecision(4) << f.odometry.x << ' ' << f.odometry.y << ' '
    << f.odometry.yaw << " 0 0 0 " << std::setprecision(6) << t << " lidarseg-sim " << t << '\n';
}

// Every output of a run, written scan by scan under temporary names; commit() publishes them.
class RunOutputs {
 public:
  RunOutputs(const SimulateOptions& o, const sim::SimulationParams& params,
             const sim::World& world);
  void write(std::size_t i, const sim::SimulatedFrame& f, SimulateReport& report);
  void commit();
  // A run that did not commit leaves no rawlog temporary behind.
  ~RunOutputs() {
    if (committed_) return;
    rawlog_.close();
    std::error_code ec;
    fs::remove(rawlog_tmp_, ec);
    pipeline::releaseTemporary(rawlog_tmp_);
  }
  RunOutputs(const RunOutputs&) = delete;
  RunOutputs& operator=(const RunOutputs&) = delete;

 private:
  bool committed_ = false;
  void writeRawlogScan(const sim::SimulatedFrame& f);
  void writeImage(std::size_t i, const sim::SimulatedFrame& f, std::size_t image);

  std::string prefix_;
  const sim::SimulationParams& params_;
  const sim::World& world_;
  const mrpt::poses::CPose3D lidar_pose_;
  PendingFile gt_, odom_, features_, rois_;
  std::unique_ptr<PendingFile> carmen_;
  std::string rawlog_tmp_;  // registered for the SIGINT/SIGTERM cleanup
  mrpt::io::CFileGZOutputStream rawlog_;
  mrpt::serialization::CArchiveStreamBase<mrpt::io::CFileGZOutputStream> archive_{rawlog_};
};

// Opens every output (PREFIX.rawlog last) and writes the text files' headers.
RunOutputs::RunOutputs(const SimulateOptions& o, const sim::SimulationParams& params,
                       const sim::World& world)
    : prefix_(o.out_prefix),
      params_(params),
      world_(world),
      lidar_pose_(0, 0, params.lidar_z_m, 0, 0, 0),
      gt_(prefix_ + ".gt.tum"),
      odom_(prefix_ + ".odom.tum"),
      features_(prefix_ + ".features.csv"),
      rois_(prefix_ + ".rois.csv"),
      carmen_(o.write_carmen ? std::make_unique<PendingFile>(prefix_ + ".carmen.log") : nullptr),
      rawlog_tmp_(pipeline::uniqueTemporary(prefix_ + ".rawlog")),
      rawlog_(rawlog_tmp_) {
  if (!rawlog_.fileOpenCorrectly()) throw std::runtime_error("cannot write '" + rawlog_tmp_ + "'");
  gt_.out() << "# timestamp x y z qx qy qz qw (true robot pose, world frame)\n";
  odom_.out() << "# timestamp x y z qx qy qz qw (wheel odometry, drifting)\n";
  features_.out() << "scan,t,type,x,y,theta,width,id,resolvable,seen_as\n";
  rois_.out() << "image,scan,t,file,door,kind,u_min,v_min,u_max,v_max\n";
  if (carmen_) {
    carmen_->out() << "# lidarseg-simulate: " << o.world_path << ", seed " << o.seed
                   << "\n# ROBOTLASER1 and ODOM lines; poses are wheel odometry\n";
  }
}

// Scan `i` with its truth, odometry, sightings and image, in every output; counted in `report`.
void RunOutputs::write(std::size_t i, const sim::SimulatedFrame& f, SimulateReport& report) {
  writeRawlogScan(f);
  writeTum(gt_.out(), f.stamp_s, f.T_world_robot, 0.0);
  writeTum(odom_.out(), f.stamp_s, f.odometry, 0.0);
  for (const sim::Feature& ft : f.features) {
    writeFeatureRow(features_.out(), i, f.stamp_s, ft);
    (lidarseg::isDoor(ft.type) ? report.door_sightings : report.corner_sightings)++;
  }
  if (f.has_image) writeImage(i, f, report.images++);
  if (carmen_) writeCarmenLines(carmen_->out(), f, params_.sensor);
  ++report.scans;
}

// Odometry first: an MRPT consumer then has the motion before the scan it explains.
void RunOutputs::writeRawlogScan(const sim::SimulatedFrame& f) {
  auto odo = mrpt::obs::CObservationOdometry::Create();
  odo->sensorLabel = "ODOMETRY";
  odo->timestamp = mrpt::Clock::fromDouble(f.stamp_s);
  odo->odometry = mrpt::poses::CPose2D(f.odometry.x, f.odometry.y, f.odometry.yaw);
  archive_ << *odo;
  archive_ << *mrpt_adapter::makeRangeScanObservation(f.scan, "LIDAR", lidar_pose_,
                                                      params_.sensor.range_sigma_m);
}

// Image number `image` (of scan `i`): its PNG, its observation in the rawlog, its door boxes.
void RunOutputs::writeImage(std::size_t i, const sim::SimulatedFrame& f, std::size_t image) {
  char name[32];
  std::snprintf(name, sizeof(name), "img_%06zu.png", image);
  archive_ << *imageObservation(f, params_.camera, prefix_ + "_Images.tmp", name);
  for (const sim::DoorBox& b : f.door_boxes) {
    rois_.out() << image << ',' << i << ',' << std::setprecision(9) << f.stamp_s << ',' << name
                << ',' << b.door << ',' << sim::toString(world_.doors()[b.door].kind) << ','
                << b.u_min << ',' << b.v_min << ',' << b.u_max << ',' << b.v_max << '\n';
  }
}

// Closes the rawlog and renames every output to its final name (the images folder last).
void RunOutputs::commit() {
  rawlog_.close();
  fs::rename(rawlog_tmp_, prefix_ + ".rawlog");
  pipeline::releaseTemporary(rawlog_tmp_);
  committed_ = true;
  gt_.commit();
  odom_.commit();
  features_.commit();
  rois_.commit();
  if (carmen_) carmen_->commit();
  if (params_.camera_every_scans > 0) {
    std::error_code ec;
    fs::remove_all(prefix_ + "_Images", ec);
    fs::rename(prefix_ + "_Images.tmp", prefix_ + "_Images");
    pipeline::releaseTemporary(prefix_ + "_Images.tmp");
  }
}

}  // namespace

SimulateApp::SimulateApp(SimulateOptions options) : options_(std::move(options)) {}

SimulateReport SimulateApp::run() {
  if (options_.out_prefix.empty()) throw std::invalid_argument("no output prefix given (--out)");
  // Before any work: an output that is an input is refused, a second writer at once; the
  // lock is held until the temporaries of a failed run are removed.
  OutputSet claimed;
  std::vector<NamedOutput> files;
  for (const char* ext : {".rawlog", ".gt.tum", ".odom.tum", ".features.csv", ".rois.csv", ".carmen.log"}) {
    files.push_back({options_.out_prefix + ext, "--out"});
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
    pipeline::releaseTemporary(options_.out_prefix + "_Images.tmp");
    throw;
  }
}

SimulateReport SimulateApp::runOrThrow() {
  if (options_.out_prefix.empty()) throw std::invalid_argument("no output prefix given (--out)");
  std::optional<sim::Building> building;
  if (options_.building_seed) {
    if (!options_.world_path.empty() || !options_.trajectory_path.empty()) {
      throw std::invalid_argument("--building replaces --world and --trajectory: give one or the other");
    }
    building = sim::generateBuilding(*options_.building_seed);
  } else if (options_.world_path.empty() || options_.trajectory_path.empty()) {
    throw std::invalid_argument("give --world and --trajectory, or --building SEED");
  }
  const sim::World world = building ? building->world() : sim::loadWorldFile(options_.world_path);
  const sim::Trajectory trajectory =
      building ? building->trajectory() : sim::loadTrajectoryFile(options_.trajectory_path);
  const sim::SimulationParams params = simulationParams(options_);
  sim::Simulation simulation(world, trajectory, params);
  prepareFolders(options_.out_prefix, params.camera_every_scans > 0);
  // The generated building as files: the same run again with -w/-t, and its doors.
  std::vector<std::unique_ptr<PendingFile>> building_files;
  if (building) {
    for (const char* ext : {".world", ".traj", ".doors.csv"}) {
      building_files.push_back(std::make_unique<PendingFile>(options_.out_prefix + ext));
    }
    sim::writeWorldFile(building_files[0]->out(), *building);
    sim::writeTrajectoryFile(building_files[1]->out(), *building);
    sim::writeDoorTable(building_files[2]->out(), *building);
  }
  RunOutputs outputs(options_, params, world);
  SimulateReport report;
  report.rawlog_path = options_.out_prefix + ".rawlog";
  report.length_m = trajectory.length();
  report.duration_s = trajectory.duration();
  pipeline::Progress progress("lidarseg-simulate", options_.progress, simulation.numScans());
  for (std::size_t i = 0; i < simulation.numScans(); ++i) {
    outputs.write(i, simulation.next(), report);
    progress.update(i + 1);
  }
  progress.done(simulation.numScans());
  outputs.commit();
  for (auto& f : building_files) f->commit();
  return report;
}

std::string simulationPrefix(const std::string& out, const std::string& world_path) {
  std::error_code ec;
  const bool folder = (!out.empty() && out.back() == '/') || fs::is_directory(out, ec);
  if (!folder) return out;
  return (fs::path(out) / fs::path(world_path).stem()).string();
}

}  // namespace lidarseg::apps
