// Tracks every scan of MRPT's Telecom Faculty log with lidarseg's SegmentAlignment::track,
// without the wheel odometry (constant-velocity prior), and fails unless no scan is lost,
// every pose is finite and the tracked path is as long as the wheel odometry's within 10 %.
#include <cmath>
#include <iostream>

#include <mrpt/poses/CPose2D.h>

#include <lidarseg/mrpt/RawlogScanReader.h>
#include <lidarseg/mrpt/SegmentAlignment.h>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: " << argv[0] << " TELECOM.rawlog\n";
    return 2;
  }
  lidarseg::mrpt_adapter::SegmentAlignment align;  // align.trackingOptions: the tools' [odometry]
  lidarseg::mrpt_adapter::RawlogScanReader reader(argv[1]);
  std::size_t scans = 0, lost = 0;
  double tracked_m = 0.0, odometry_m = 0.0;
  mrpt::poses::CPose2D last_pose, last_odometry;
  while (auto scan = reader.next()) {
    const auto step = align.track(*scan->observation);  // the robot's pose in the odometry frame
    const mrpt::poses::CPose2D pose = step.robot_pose.mean;
    if (!std::isfinite(pose.x()) || !std::isfinite(pose.y()) || !std::isfinite(pose.phi())) {
      std::cerr << "scan " << scans << ": a non-finite pose\n";
      return 1;
    }
    lost += step.core.status == lidarseg::TrackStatus::kLost;
    if (scans > 0) tracked_m += pose.distanceTo(last_pose);
    if (scans > 0 && scan->odometry) odometry_m += scan->odometry->distanceTo(last_odometry);
    last_pose = pose;
    if (scan->odometry) last_odometry = *scan->odometry;
    ++scans;
  }
  std::cout << "tracked " << scans << " scans, " << lost << " lost; path " << tracked_m
            << " m (wheel odometry " << odometry_m << " m); last pose " << last_pose << "\n";
  const bool ok = scans > 100 && lost == 0 && odometry_m > 10.0 &&
                  std::abs(tracked_m - odometry_m) <= 0.1 * odometry_m;
  return ok ? 0 : 1;
}
