#include "lidarseg/pipeline/OdometryMethods.h"

#include <cmath>
#include <stdexcept>

#include <mrpt/poses/CPosePDFGaussian.h>

#include "lidarseg/report/Baselines.h"
#include "lidarseg/report/Timing.h"
#include "lidarseg/mrpt/LaserOdometry.h"
#include "lidarseg/mrpt/PoseConversion.h"

namespace lidarseg::pipeline {

using mrpt_adapter::toMrpt;
using mrpt_adapter::toPose2D;

// The pairwise options stay the defaults: the tools only track.
LidarsegMethod::LidarsegMethod(const OdometryParams& params)
    : OdometryMethod("lidarseg"), alignment_(mrpt_adapter::SegmentAlignment::TConfigParams{}, params) {}

MethodStep LidarsegMethod::process(const ScanInput& scan) {
  // The core reads the motion model's clock from the scan's stamp. While the stamp policy
  // keeps the log's stamp (a log that needed no repair), the record's scan goes as it is;
  // otherwise its ranges go through one buffer kept across scans, which stops allocating
  // once it has the sensor's size.
  const Scan& logged = scan.record.scan;
  const Scan* timed = &logged;
  if (logged.stamp_s != scan.time.model_stamp_s) {
    timed_ = logged;
    timed_.stamp_s = scan.time.model_stamp_s;
    timed = &timed_;
  }
  last_ = alignment_.track(*timed, scan.record.sensor_on_robot, scan.prior);
  return record(scan);
}

MethodStep LidarsegMethod::record(const ScanInput& scan) {
  const OdometryStep& c = last_.core;
  report::MethodReport& m = report_;
  m.trajectory.push_back({scan.time.output_stamp_s, toPose2D(last_.robot_pose.mean)});
  m.segmentation_us.push_back(c.wall_danielsson_us);
  m.cascade_us.push_back(c.cascade_us);
  m.matching_us.push_back(c.matching_us);
  m.time_us.push_back(c.wall_danielsson_us + c.cascade_us + c.matching_us);
  m.scan_status.push_back(toString(c.status));
  m.refinement_us.push_back(c.refinement_us);
  m.prior.push_back(c.prior);
  m.inlier_ratio.push_back(c.refine.inlier_ratio);
  m.refine_iterations.push_back(c.refine.iterations);
  m.match_status.push_back(c.first ? "first" : toString(c.match.status));
  m.scan_matches.push_back(c.match.matches.size());
  m.searched.push_back(c.search.has_value() ? 1 : 0);
  m.searches += c.search.has_value();
  m.wide_searches += c.wide_search;
  m.deskewed_again += c.deskewed_again;
  m.revised_keyframes += c.keyframe_revision.has_value();
  if (!c.first) {
    ++m.status_counts[toString(c.status)];
    if (c.match.status == MatchStatus::kTooFewMatches) ++m.match_failures[c.match.rejections.dominant()];
    if (c.status == TrackStatus::kLost) {
      ++m.lost;
      if (m.lost_scans.size() < 1000) m.lost_scans.push_back(scan.record.index);
    }
    if (std::sqrt(std::max(last_.increment.cov(0, 0), last_.increment.cov(1, 1))) > 0.1) ++m.weak_scans;
  }
  // The motion from the keyframe and its covariance, in the robot frame (T = S T_sensor S^-1).
  const Pose2D& S = scan.record.sensor_on_robot;
  const Pose2D robot_pose = m.trajectory.back().pose;
  if (c.keyframe_revision) key_robot_pose_ = compose(compose(S, c.keyframe_revision->T_odom_sensor), inverse(S));
  if (!c.first && (c.status == TrackStatus::kOk || c.status == TrackStatus::kRecovered ||
                   c.status == TrackStatus::kDegenerate)) {
    m.keyframe_motions.push_back({key_stamp_s_, scan.time.output_stamp_s, relative(robot_pose, key_robot_pose_),
                                  mrpt_adapter::conjugateCovariance(S, c.increment_covariance)});
  }
  if (c.first || c.keyframe) {
    key_stamp_s_ = scan.time.output_stamp_s;
    key_robot_pose_ = robot_pose;
  }
  m.final_sigma_x_m = std::sqrt(last_.robot_pose.cov(0, 0));
  m.final_sigma_y_m = std::sqrt(last_.robot_pose.cov(1, 1));
  m.final_sigma_yaw_rad = std::sqrt(last_.robot_pose.cov(2, 2));
  return {m.trajectory.back().stamp_s, m.trajectory.back().pose, m.time_us.back(),
          c.first ? std::string("first") : toString(c.status)};
}

IcpMethod::IcpMethod(std::string name, const mrpt::slam::CICP::TConfigParams& options, bool keyframed,
                     double keyframe_distance_m, double keyframe_angle_rad)
    : OdometryMethod(std::move(name)),
      keyframed_(keyframed),
      key_distance_(keyframe_distance_m),
      key_angle_(keyframe_angle_rad) {
  icp_.options = options;
}

Pose2D IcpMethod::predictedIncrement(const ScanInput& scan) const {
  if (scan.prior) return *scan.prior;
  if (last_dt_ <= 0.0) return {};
  const double k = scan.time.dt_s / last_dt_;  // constant velocity
  return {last_increment_.x * k, last_increment_.y * k, last_increment_.yaw * k};
}

MethodStep IcpMethod::process(const ScanInput& scan) {
  // A CARMEN line has no observation of its own: made here, outside ICP's time (a reader
  // of rawlogs would hand it over made).
  const auto observation = mrpt_adapter::observationOf(scan.record);
  const auto t0 = report::Clock::now();
  auto current = std::make_unique<mrpt::maps::CSimplePointsMap>();
  current->insertionOptions.minDistBetweenLaserPoints = 0.0f;
  current->loadFromRangeScan(*observation);
  bool renew = !reference_;
  std::string status = "first";
  if (reference_) {
    // From the reference: T_ref_curr = T_ref_last (+) predicted increment.
    Pose2D T_ref_curr = compose(relative(pose_, reference_pose_), predictedIncrement(scan));
    if (current->size() >= 5 && reference_->size() >= 5) {
      mrpt::slam::CICP::TReturnInfo info;
      const auto pdf =
          icp_.AlignPDF(reference_.get(), current.get(), mrpt::poses::CPosePDFGaussian(toMrpt(T_ref_curr)), info);
      T_ref_curr = toPose2D(pdf->getMeanVal());
      const bool converged = info.nIterations < icp_.options.maxIterations;
      status = converged ? "converged" : "not_converged";
      ++report_.status_counts[status];
      renew = !converged;
    } else {
      status = "skipped";
      ++report_.status_counts[status];
      renew = true;
    }
    const Pose2D new_pose = compose(reference_pose_, T_ref_curr);
    last_increment_ = relative(new_pose, pose_);
    last_dt_ = scan.time.dt_s;
    pose_ = new_pose;
    renew = renew || !keyframed_ || std::hypot(T_ref_curr.x, T_ref_curr.y) >= key_distance_ ||
            std::abs(T_ref_curr.yaw) >= key_angle_;
  }
  if (renew) {
    reference_ = std::move(current);
    reference_pose_ = pose_;
  }
  report_.time_us.push_back(report::microsecondsSince(t0));
  report_.trajectory.push_back({scan.time.output_stamp_s, pose_});
  return {scan.time.output_stamp_s, pose_, report_.time_us.back(), status};
}

std::unique_ptr<OdometryMethod> makeBaseline(const std::string& name, const mrpt_adapter::LidarsegConfig& config) {
  const OdometryParams& p = config.odometry;
  if (name == "icp") return std::make_unique<IcpMethod>(name, config.icp, true, p.keyframe_distance_m, p.keyframe_angle_rad);
  if (name == "icp-s2s") return std::make_unique<IcpMethod>(name, config.icp, false, 0.0, 0.0);
  std::string known;
  for (const report::BaselineKind& k : report::baselineKinds()) known += (known.empty() ? "'" : ", '") + k.name + "'";
  throw std::invalid_argument("unknown report::baseline '" + name + "' (known: " + known + ")");
}

}  // namespace lidarseg::pipeline
