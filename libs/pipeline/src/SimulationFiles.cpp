#include "lidarseg/pipeline/SimulationFiles.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <stdexcept>
#include <utility>

#include <mrpt/core/Clock.h>
#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationOdometry.h>

#include "lidarseg/core/Angles.h"
#include "lidarseg/mrpt/ScanConverter.h"

namespace lidarseg::pipeline {

namespace fs = std::filesystem;

namespace {

// TUM trajectory line: time x y z qx qy qz qw (rotation about z only).
void writeTum(std::ostream& os, double t, const Pose2D& p, double z) {
  os << std::setprecision(9) << t << ' ' << p.x << ' ' << p.y << ' ' << z << ' ' << 0.0 << ' '
     << 0.0 << ' ' << std::sin(0.5 * p.yaw) << ' ' << std::cos(0.5 * p.yaw) << '\n';
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
// The beams' geometry is the simulated scan's own (the rawlog's): a configured beam count or
// field of view overrides the sensor profile's.
void writeCarmenLines(std::ostream& c, const sim::SimulatedFrame& f) {
  const std::size_t n = f.scan.size();
  const double fov = std::abs(f.scan.layout->angle(n - 1) - f.scan.layout->angle(0));
  const double step = fov / static_cast<double>(n - 1);
  const double t = f.stamp_s;
  c << std::setprecision(6) << "ROBOTLASER1 0 " << -0.5 * fov << ' ' << fov << ' ' << step << ' '
    << f.scan.max_range_m << " 0.01 0 " << n;
  c << std::setprecision(4);
  for (double r : f.scan.ranges_m) c << ' ' << r;
  c << " 0 " << f.odometry.x << ' ' << f.odometry.y << ' ' << f.odometry.yaw << ' ' << f.odometry.x
    << ' ' << f.odometry.y << ' ' << f.odometry.yaw << " 0 0 0 0 0 " << std::setprecision(6) << t
    << " lidarseg-sim " << t << '\n';
  c << "ODOM " << std::setprecision(4) << f.odometry.x << ' ' << f.odometry.y << ' '
    << f.odometry.yaw << " 0 0 0 " << std::setprecision(6) << t << " lidarseg-sim " << t << '\n';
}

}  // namespace

namespace {

// An image a run writes in PREFIX_Images/: img_NNNNNN.png, a plain file.
bool isSimulatedImage(const fs::directory_entry& entry) {
  std::error_code ec;
  const std::string name = entry.path().filename().string();
  if (!entry.is_regular_file(ec) || entry.is_symlink(ec)) return false;
  if (name.size() <= 8 || name.compare(0, 4, "img_") != 0 || name.compare(name.size() - 4, 4, ".png") != 0) return false;
  return name.find_first_not_of("0123456789", 4) == name.size() - 4;
}

// An earlier run's PREFIX_Images/ is replaced; one holding anything else (the user's files,
// an input) is refused, never removed.
void checkImagesFolder(const std::string& images) {
  const std::string foreign = report::foreignEntry(images, isSimulatedImage);
  if (!foreign.empty()) {
    throw std::runtime_error("'" + images + "' would be replaced by this run's camera images, but it holds '" + foreign +
                             "', which is no image lidarseg-simulate writes: move it, or choose another --out");
  }
}

}  // namespace

void prepareSimulationFolders(const std::string& prefix, bool camera) {
  if (camera) checkImagesFolder(prefix + "_Images");
  const fs::path parent = fs::path(prefix).parent_path();
  if (!parent.empty()) fs::create_directories(parent);
  std::error_code ec;
  fs::remove_all(prefix + "_Images.tmp", ec);
  if (camera) {
    report::registerTemporaryFolder(prefix + "_Images.tmp");
    fs::create_directories(prefix + "_Images.tmp");
  }
}

SimulationFiles::SimulationFiles(const std::string& prefix, const sim::SimulationParams& params,
                                 const sim::World& world, const std::string& world_path,
                                 bool write_carmen)
    : prefix_(prefix),
      params_(params),
      world_(world),
      lidar_pose_(0, 0, params.lidar_z_m, 0, 0, 0),
      gt_(prefix_ + ".gt.tum"),
      odom_(prefix_ + ".odom.tum"),
      features_(prefix_ + ".features.csv"),
      rois_(prefix_ + ".rois.csv"),
      carmen_(write_carmen ? std::make_unique<report::PendingFile>(prefix_ + ".carmen.log") : nullptr),
      rawlog_tmp_(report::uniqueTemporary(prefix_ + ".rawlog")),
      rawlog_(rawlog_tmp_, prefix_ + ".rawlog", 1) {
  gt_.out() << "# timestamp x y z qx qy qz qw (true robot pose, world frame)\n";
  odom_.out() << "# timestamp x y z qx qy qz qw (wheel odometry, drifting)\n";
  features_.out() << "scan,t,type,x,y,theta,width,id,resolvable,seen_as\n";
  rois_.out() << "image,scan,t,file,door,kind,u_min,v_min,u_max,v_max\n";
  if (carmen_) {
    carmen_->out() << "# lidarseg-simulate: " << world_path << ", seed " << params.seed
                   << "\n# ROBOTLASER1 and ODOM lines; poses are wheel odometry\n";
  }
}

void SimulationFiles::write(std::size_t i, const sim::SimulatedFrame& f) {
  writeRawlogScan(f);
  writeTum(gt_.out(), f.stamp_s, f.T_world_robot, 0.0);
  writeTum(odom_.out(), f.stamp_s, f.odometry, 0.0);
  for (const sim::Feature& ft : f.features) {
    writeFeatureRow(features_.out(), i, f.stamp_s, ft);
    (lidarseg::isDoor(ft.type) ? counts_.door_sightings : counts_.corner_sightings)++;
  }
  if (f.has_image) writeImage(i, f, counts_.images++);
  if (carmen_) writeCarmenLines(carmen_->out(), f);
  ++counts_.scans;
}

// Odometry first: an MRPT consumer then has the motion before the scan it explains.
void SimulationFiles::writeRawlogScan(const sim::SimulatedFrame& f) {
  auto odo = mrpt::obs::CObservationOdometry::Create();
  odo->sensorLabel = "ODOMETRY";
  odo->timestamp = mrpt::Clock::fromDouble(f.stamp_s);
  odo->odometry = mrpt::poses::CPose2D(f.odometry.x, f.odometry.y, f.odometry.yaw);
  archive_ << *odo;
  archive_ << *mrpt_adapter::makeRangeScanObservation(f.scan, "LIDAR", lidar_pose_,
                                                      params_.sensor.range_sigma_m);
}

// Image number `image` (of scan `i`): its PNG, its observation in the rawlog, its door boxes.
void SimulationFiles::writeImage(std::size_t i, const sim::SimulatedFrame& f, std::size_t image) {
  char name[32];
  std::snprintf(name, sizeof(name), "img_%06zu.png", image);
  archive_ << *imageObservation(f, params_.camera, prefix_ + "_Images.tmp", name);
  for (const sim::DoorBox& b : f.door_boxes) {
    rois_.out() << image << ',' << i << ',' << std::setprecision(9) << f.stamp_s << ',' << name
                << ',' << b.door << ',' << sim::toString(world_.doors()[b.door].kind) << ','
                << b.u_min << ',' << b.v_min << ',' << b.u_max << ',' << b.v_max << '\n';
  }
}

// The rawlog is what a reader opens: the one it replaces is removed first, and it is renamed
// into place last, once its images folder and the text files beside it are the new run's.
void SimulationFiles::commit(const std::vector<report::PendingFile*>& companions) {
  rawlog_.close();
  // Every file written whole before any is put in place: a full disk publishes none.
  for (report::PendingFile* f : {&gt_, &odom_, &features_, &rois_}) f->finish();
  if (carmen_) carmen_->finish();
  for (report::PendingFile* f : companions) f->finish();
  const std::string rawlog = prefix_ + ".rawlog";
  std::error_code ec;
  fs::remove(rawlog, ec);
  if (ec) throw std::runtime_error("cannot remove the previous '" + rawlog + "': " + ec.message());
  if (params_.camera_every_scans > 0) publishImages();
  gt_.commit();
  odom_.commit();
  features_.commit();
  rois_.commit();
  if (carmen_) carmen_->commit();
  for (report::PendingFile* f : companions) f->commit();
  fs::rename(rawlog_tmp_, rawlog);
  report::releaseTemporary(rawlog_tmp_);
  committed_ = true;
}

// PREFIX_Images.tmp/ becomes PREFIX_Images/, replacing an earlier run's folder.
void SimulationFiles::publishImages() {
  const std::string images = prefix_ + "_Images";
  checkImagesFolder(images);  // again: the folder may have changed while the run simulated
  std::error_code ec;
  if (fs::is_directory(images, ec)) {
    for (const auto& entry : fs::directory_iterator(images, ec)) fs::remove(entry.path(), ec);
    if (!fs::remove(images, ec) || ec) {
      throw std::runtime_error("cannot remove the previous '" + images + "': " +
                               (ec ? ec.message() : std::string("not empty")));
    }
  }
  fs::rename(images + ".tmp", images);
  report::releaseTemporary(images + ".tmp");
}

// A run that did not commit leaves no rawlog temporary behind.
SimulationFiles::~SimulationFiles() {
  if (committed_) return;
  std::error_code ec;  // the stream's file is closed, unchecked, with it
  fs::remove(rawlog_tmp_, ec);
  report::releaseTemporary(rawlog_tmp_);
}

}  // namespace lidarseg::pipeline
