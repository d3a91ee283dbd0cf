#include "lidarseg/pipeline/OdometryRun.h"
#include "lidarseg/report/Baselines.h"
#include "lidarseg/core/NumberText.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lidarseg::pipeline {

OdometryRun::OdometryRun(const RunSettings& settings) : settings_(settings), gate_(settings.config.stamps) {
  const OdometryParams& p = settings_.config.odometry;
  p.validate();
  lidarseg_ = std::make_unique<LidarsegMethod>(p);
  // In the registry's order whatever the order asked, each once.
  for (const report::BaselineKind& kind : report::baselineKinds()) {
    if (std::find(settings_.baselines.begin(), settings_.baselines.end(), kind.name) != settings_.baselines.end()) {
      baselines_.push_back(makeBaseline(kind.name, settings_.config));
    }
  }
  for (const std::string& name : settings_.baselines) {
    if (!report::baselineKind(name)) (void)makeBaseline(name, settings_.config);  // throws, naming the known ones
  }
}

// The wheel-odometry increment when asked for and plausible; no motion after a time gap;
// otherwise nothing (constant velocity). Counted by the caller once the scan is used.
OdometryRun::PriorChoice OdometryRun::priorOf(const mrpt_adapter::LaserRecord& record, const StampStep& time) const {
  PriorChoice choice;
  if (settings_.use_odometry && record.odometry && last_odometry_) {
    const Pose2D inc = relative(*record.odometry, *last_odometry_);
    if (gate_.stamps().plausible(inc, time)) {
      choice.prior = inc;
      choice.from_odometry = true;
    } else {
      choice.jump = record.where + ": wheel odometry jumps by " + std::to_string(std::hypot(inc.x, inc.y)) + " m / " +
                    std::to_string(inc.yaw) + " rad; ignored as a prior";
    }
  }
  if (!choice.prior && time.gap) choice.prior = Pose2D{};
  return choice;
}

RunStep OdometryRun::process(const mrpt_adapter::LaserRecord& record) {
  RunStep out;
  out.time = gate_.time(record);
  const PriorChoice choice = priorOf(record, out.time);
  const ScanInput input{record, out.time, choice.prior};
  try {
    out.steps.push_back(lidarseg_->process(input));
  } catch (const std::invalid_argument& e) {
    out.error = gate_.skip(record, e.what());
    return out;  // a refused scan counts no prior
  }
  if (choice.from_odometry) ++odometry_priors_;
  if (!choice.jump.empty()) {
    ++odometry_jumps_;
    gate_.warn(choice.jump);
  }
  for (const auto& m : baselines_) out.steps.push_back(m->process(input));
  // A scan without odometry breaks the chain: the next reading's increment would span it.
  if (settings_.use_odometry) last_odometry_ = record.odometry;
  if (record.log_pose) log_poses_.push_back({out.time.output_stamp_s, *record.log_pose});
  if (record.odometry) wheel_odometry_.push_back({out.time.output_stamp_s, *record.odometry});
  if (!out.time.first) steps_.push_back(out.time.dt_s);
  gate_.accept(record, out.time);
  out.processed = true;
  return out;
}

double OdometryRun::medianStep() const { return steps_.empty() ? StampPolicy::kStartStepS : summarize(steps_).median; }

report::OdometryReport OdometryRun::finish(double max_lost_ratio) {
  report::OdometryReport r;
  // Asked for and absent, the wheel odometry was silently replaced by constant velocity.
  if (settings_.use_odometry && wheel_odometry_.empty()) {
    gate_.warn("--use-odometry: the log has no wheel odometry; every scan's prior was constant velocity");
    r.prior = "constant velocity (the log has no wheel odometry)";
  } else if (settings_.use_odometry && odometry_priors_ == 0) {
    gate_.warn("--use-odometry: no two consecutive scans have usable wheel odometry; every scan's prior was constant "
               "velocity");
    r.prior = "constant velocity (no usable wheel odometry between scans)";
  } else if (settings_.use_odometry) {
    r.prior = "wheel odometry";
  }
  const OdometryParams& p = settings_.config.odometry;
  if (p.deskew && p.scanner_rotation_hz > 0.0) {
    r.beam_times = "scanner at " + numberText(p.scanner_rotation_hz) + " Hz, stamped at the " + toString(p.scan_stamp) +
                   " beam (scans without their own beam times)";
  }
  static_cast<report::RecordCounts&>(r) = gate_.counts();
  r.odometry_jumps = odometry_jumps_;
  r.odometry_priors = odometry_priors_;
  lidarseg_->report().time_summary_us = summarize(lidarseg_->report().time_us);
  r.lidarseg = std::move(lidarseg_->report());
  if (static_cast<double>(r.lidarseg.lost) > max_lost_ratio * static_cast<double>(r.frames)) r.lidarseg.tracking = "lost";
  for (const auto& m : baselines_) {
    m->report().time_summary_us = summarize(m->report().time_us);
    r.baselines.push_back(std::move(m->report()));
  }
  const report::MethodReport* reference = r.baseline(report::kSpeedupBaseline);
  if (reference && r.lidarseg.time_summary_us.median > 0.0) {
    r.speedup_median = reference->time_summary_us.median / r.lidarseg.time_summary_us.median;
  }
  return r;
}

}  // namespace lidarseg::pipeline
