#include "lidarseg/pipeline/OdometryRun.h"

#include <stdexcept>

namespace lidarseg::pipeline {

OdometryRun::OdometryRun(const RunSettings& settings) : settings_(settings), stamps_(settings.config.stamps) {
  const OdometryParams& p = settings_.config.odometry;
  p.validate();
  lidarseg_ = std::make_unique<LidarsegMethod>(p);
  methods_.push_back(lidarseg_.get());
  if (settings_.icp_keyframed) {
    icp_ = std::make_unique<IcpMethod>("icp", settings_.config.icp, true, p.keyframe_distance_m, p.keyframe_angle_rad);
    methods_.push_back(icp_.get());
  }
  if (settings_.icp_scan_to_scan) {
    icp_s2s_ = std::make_unique<IcpMethod>("icp-s2s", settings_.config.icp, false, 0.0, 0.0);
    methods_.push_back(icp_s2s_.get());
  }
}

void OdometryRun::warn(const std::string& message) {
  if (counts_.warnings.size() < 100) counts_.warnings.push_back(message);
}

// The wheel-odometry increment when asked for and plausible; no motion after a time gap;
// otherwise nothing (constant velocity).
std::optional<Pose2D> OdometryRun::priorOf(const mrpt_adapter::LaserRecord& record, const StampStep& time) {
  std::optional<Pose2D> prior;
  if (settings_.use_odometry && record.odometry && last_odometry_) {
    const Pose2D inc = relative(*record.odometry, *last_odometry_);
    if (stamps_.plausible(inc, time)) {
      prior = inc;
    } else {
      ++counts_.odometry_jumps;
      warn(record.where + ": wheel odometry jumps by " + std::to_string(std::hypot(inc.x, inc.y)) + " m / " +
           std::to_string(inc.yaw) + " rad; ignored as a prior");
    }
  }
  if (!prior && time.gap) prior = Pose2D{};
  return prior;
}

RunStep OdometryRun::process(const mrpt_adapter::LaserRecord& record) {
  RunStep out;
  out.time = stamps_.next(record.stamp_s);
  const ScanInput input{record, out.time, priorOf(record, out.time)};
  try {
    lidarseg_->process(input);
  } catch (const std::invalid_argument& e) {
    ++counts_.skipped_count;
    out.error = record.where + " (scan " + std::to_string(record.index) + "): " + e.what();
    if (counts_.skipped.size() < 100) counts_.skipped.push_back(out.error);
    return out;
  }
  for (OdometryMethod* m : methods_) {
    if (m != lidarseg_.get()) m->process(input);
  }
  if (out.time.non_increasing) ++counts_.non_increasing_stamps;
  if (out.time.clock_jump) {
    ++counts_.clock_jumps;
    warn(record.where + ": the clock jumps back by " + std::to_string(-out.time.log_step_s) +
         " s; the motion prior restarts from rest");
  } else if (out.time.gap) {
    ++counts_.time_gaps;
    warn(record.where + ": time gap of " + std::to_string(out.time.log_step_s) +
         " s; the motion prior restarts from rest");
  }
  if (settings_.use_odometry && record.odometry) last_odometry_ = record.odometry;
  if (record.log_pose) log_poses_.push_back({out.time.output_stamp_s, *record.log_pose});
  if (record.odometry) wheel_odometry_.push_back({out.time.output_stamp_s, *record.odometry});
  if (!out.time.first) steps_.push_back(out.time.dt_s);
  stamps_.accept(out.time);
  ++counts_.frames;
  out.processed = true;
  return out;
}

double OdometryRun::medianStep() const { return steps_.empty() ? 0.1 : summarize(steps_).median; }

OdometryReport OdometryRun::finish(double max_lost_ratio) {
  OdometryReport r = counts_;
  for (OdometryMethod* m : methods_) m->report().time_summary_us = summarize(m->report().time_us);
  r.lidarseg = std::move(lidarseg_->report());
  if (static_cast<double>(r.lidarseg.lost) > max_lost_ratio * static_cast<double>(r.frames)) r.lidarseg.tracking = "lost";
  if (icp_) r.icp = std::move(icp_->report());
  if (icp_s2s_) r.icp_s2s = std::move(icp_s2s_->report());
  if (r.icp && r.lidarseg.time_summary_us.median > 0.0) {
    r.speedup_median = r.icp->time_summary_us.median / r.lidarseg.time_summary_us.median;
  }
  return r;
}

}  // namespace lidarseg::pipeline
