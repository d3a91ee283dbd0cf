#include "lidarseg/apps/SimulateApp.h"
#include "lidarseg/core/Angles.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <mrpt/core/Clock.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include "lidarseg/mrpt/ScanConverter.h"
#include "lidarseg/mrpt/SimulationConfig.h"
#include "lidarseg/sim/Simulation.h"
#include "lidarseg/sim/Trajectory.h"
#include "lidarseg/sim/WorldFile.h"

namespace lidarseg::apps {

namespace fs = std::filesystem;

namespace {


// A text output written under a temporary name and renamed when the run succeeds.
class PendingFile {
 public:
  explicit PendingFile(std::string path) : path_(std::move(path)), out_(path_ + ".tmp") {
    if (!out_) throw std::runtime_error("cannot write '" + path_ + ".tmp'");
    out_ << std::fixed;
  }
  std::ofstream& out() { return out_; }
  void commit() {
    out_.close();
    if (!out_) throw std::runtime_error("error while writing '" + path_ + ".tmp'");
    fs::rename(path_ + ".tmp", path_);
  }
  ~PendingFile() {
    if (out_.is_open()) {
      out_.close();
      std::error_code ec;
      fs::remove(path_ + ".tmp", ec);
    }
  }

 private:
  std::string path_;
  std::ofstream out_;
};

// TUM trajectory line: time x y z qx qy qz qw (rotation about z only).
void writeTum(std::ostream& os, double t, const Pose2D& p, double z) {
  os << std::setprecision(9) << t << ' ' << p.x << ' ' << p.y << ' ' << z << ' ' << 0.0 << ' '
     << 0.0 << ' ' << std::sin(0.5 * p.yaw) << ' ' << std::cos(0.5 * p.yaw) << '\n';
}

}  // namespace

SimulateApp::SimulateApp(SimulateOptions options) : options_(std::move(options)) {}

SimulateReport SimulateApp::run() {
  try {
    return runOrThrow();
  } catch (...) {
    // Leave nothing half-written behind.
    std::error_code ec;
    fs::remove(options_.out_prefix + ".rawlog.tmp", ec);
    fs::remove_all(options_.out_prefix + "_Images.tmp", ec);
    throw;
  }
}

SimulateReport SimulateApp::runOrThrow() {
  if (options_.out_prefix.empty()) throw std::invalid_argument("no output prefix given (--out)");
  const sim::World world = sim::loadWorldFile(options_.world_path);
  const sim::Trajectory trajectory = sim::loadTrajectoryFile(options_.trajectory_path);
  sim::SimulationParams params;
  params.sensor = sim::sensorProfile(options_.sensor);
  if (!options_.config_path.empty()) {
    mrpt_adapter::loadSimulationParamsFile(params, options_.config_path);
  }
  params.seed = options_.seed;
  params.rolling_shutter = params.rolling_shutter && options_.rolling_shutter;
  if (!options_.scan_stamp.empty()) params.scan_stamp = scanStampFromString(options_.scan_stamp);
  if (options_.camera_every_scans >= 0) {
    params.camera_every_scans = static_cast<std::size_t>(options_.camera_every_scans);
  }
  sim::Simulation simulation(world, trajectory, params);

  const std::string prefix = options_.out_prefix;
  const fs::path parent = fs::path(prefix).parent_path();
  if (!parent.empty()) fs::create_directories(parent);
  const std::string rawlog_path = prefix + ".rawlog";
  const std::string images_dir = prefix + "_Images";
  const std::string images_tmp = images_dir + ".tmp";
  std::error_code ec;
  fs::remove_all(images_tmp, ec);
  if (params.camera_every_scans > 0) fs::create_directories(images_tmp);

  PendingFile gt(prefix + ".gt.tum"), odom(prefix + ".odom.tum"), features(prefix + ".features.csv"),
      rois(prefix + ".rois.csv");
  std::unique_ptr<PendingFile> carmen;
  if (options_.write_carmen) carmen = std::make_unique<PendingFile>(prefix + ".carmen.log");
  gt.out() << "# timestamp x y z qx qy qz qw (true robot pose, world frame)\n";
  odom.out() << "# timestamp x y z qx qy qz qw (wheel odometry, drifting)\n";
  features.out() << "scan,t,type,x,y,theta,width,id,resolvable,seen_as\n";
  rois.out() << "image,scan,t,file,door,kind,u_min,v_min,u_max,v_max\n";
  if (carmen) {
    carmen->out() << "# lidarseg-simulate: " << options_.world_path << ", seed " << options_.seed
                  << "\n# ROBOTLASER1 and ODOM lines; poses are wheel odometry\n";
  }

  SimulateReport report;
  report.rawlog_path = rawlog_path;
  report.length_m = trajectory.length();
  report.duration_s = trajectory.duration();
  {
    mrpt::io::CFileGZOutputStream file(rawlog_path + ".tmp");
    if (!file.fileOpenCorrectly()) throw std::runtime_error("cannot write '" + rawlog_path + ".tmp'");
    auto archive = mrpt::serialization::archiveFrom(file);
    const mrpt::poses::CPose3D lidar_pose(0, 0, params.lidar_z_m, 0, 0, 0);
    const auto& cam = params.camera;
    // MRPT camera pose: +z forward, +x right, +y down, in the robot frame.
    const mrpt::poses::CPose3D camera_pose(cam.x_m, cam.y_m, cam.z_m, cam.yaw_rad - 0.5 * kPi, 0.0, -0.5 * kPi);
    const sim::SensorModel& sensor = params.sensor;
    const double fov = std::abs(sensor.layout->angles().back() - sensor.layout->angles().front());

    for (std::size_t i = 0; i < simulation.numScans(); ++i) {
      const sim::SimulatedFrame f = simulation.next();
      const double t = f.stamp_s;
      // Odometry first: an MRPT consumer then has the motion before the scan it explains.
      auto odo = mrpt::obs::CObservationOdometry::Create();
      odo->sensorLabel = "ODOMETRY";
      odo->timestamp = mrpt::Clock::fromDouble(t);
      odo->odometry = mrpt::poses::CPose2D(f.odometry.x, f.odometry.y, f.odometry.yaw);
      archive << *odo;
      const auto scan_obs = mrpt_adapter::makeRangeScanObservation(f.scan, "LIDAR", lidar_pose, sensor.range_sigma_m);
      archive << *scan_obs;
      writeTum(gt.out(), t, f.T_world_robot, 0.0);
      writeTum(odom.out(), t, f.odometry, 0.0);
      for (const sim::Feature& ft : f.features) {
        features.out() << std::setprecision(9) << i << ',' << t << ',' << lidarseg::toString(ft.type)
                       << ',' << std::setprecision(4) << ft.position.x() << ',' << ft.position.y()
                       << ',' << ft.theta_rad << ',' << ft.width_m << ',' << ft.id << ','
                       << (ft.resolvable ? 1 : 0) << ',' << lidarseg::toString(ft.seen_as) << '\n';
        (lidarseg::isDoor(ft.type) ? report.door_sightings : report.corner_sightings)++;
      }
      if (f.has_image) {
        char name[32];
        std::snprintf(name, sizeof(name), "img_%06zu.png", report.images);
        mrpt::img::CImage img;
        auto rgb = f.image.rgb;
        img.loadFromMemoryBuffer(static_cast<unsigned>(f.image.width), static_cast<unsigned>(f.image.height), true,
                                 rgb.data(), true);
        if (!img.saveToFile(images_tmp + "/" + name)) {
          throw std::runtime_error("cannot write image '" + images_tmp + "/" + name + "'");
        }
        img.setExternalStorage(name);
        auto obs = mrpt::obs::CObservationImage::Create();
        obs->sensorLabel = "CAMERA";
        obs->timestamp = mrpt::Clock::fromDouble(t);
        obs->cameraPose = camera_pose;
        obs->cameraParams.ncols = static_cast<uint32_t>(cam.width);
        obs->cameraParams.nrows = static_cast<uint32_t>(cam.height);
        obs->cameraParams.setIntrinsicParamsFromValues(cam.fx, cam.fy, cam.cx, cam.cy);
        obs->image = std::move(img);
        archive << *obs;
        for (const sim::DoorBox& b : f.door_boxes) {
          rois.out() << report.images << ',' << i << ',' << std::setprecision(9) << t << ',' << name
                     << ',' << b.door << ',' << sim::toString(world.doors()[b.door].kind) << ','
                     << b.u_min << ',' << b.v_min << ',' << b.u_max << ',' << b.v_max << '\n';
        }
        ++report.images;
      }
      if (carmen) {
        auto& c = carmen->out();
        const double step = fov / static_cast<double>(f.scan.size() - 1);
        c << std::setprecision(6) << "ROBOTLASER1 0 " << -0.5 * fov << ' ' << fov << ' ' << step << ' '
          << sensor.max_range_m << " 0.01 0 " << f.scan.size();
        c << std::setprecision(4);
        for (double r : f.scan.ranges_m) c << ' ' << r;
        c << " 0 " << f.odometry.x << ' ' << f.odometry.y << ' ' << f.odometry.yaw << ' '
          << f.odometry.x << ' ' << f.odometry.y << ' ' << f.odometry.yaw << " 0 0 0 0 0 "
          << std::setprecision(6) << t << " lidarseg-sim " << t << '\n';
        c << "ODOM " << std::setprecision(4) << f.odometry.x << ' ' << f.odometry.y << ' '
          << f.odometry.yaw << " 0 0 0 " << std::setprecision(6) << t << " lidarseg-sim " << t << '\n';
      }
      ++report.scans;
    }
  }
  // Everything written: publish the outputs.
  fs::rename(rawlog_path + ".tmp", rawlog_path);
  gt.commit();
  odom.commit();
  features.commit();
  rois.commit();
  if (carmen) carmen->commit();
  if (params.camera_every_scans > 0) {
    fs::remove_all(images_dir, ec);
    fs::rename(images_tmp, images_dir);
  }
  return report;
}

}  // namespace lidarseg::apps
