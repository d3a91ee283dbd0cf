#include "lidarseg/apps/OdometryApp.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/slam/CICP.h>

#include "FeatureCsv.h"
#include "Json.h"
#include "OutputFiles.h"
#include "Plots.h"
#include "Timing.h"
#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/mrpt/FeatureConfig.h"
#include "lidarseg/mrpt/FeatureObservation.h"
#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/LaserOdometry.h"
#include "lidarseg/mrpt/OdometryConfig.h"
#include "lidarseg/mrpt/PoseConversion.h"

namespace lidarseg::apps {

namespace fs = std::filesystem;

namespace {

using mrpt_adapter::toMrpt;
using mrpt_adapter::toPose2D;

std::string stemOf(const std::string& path) {
  for (const char* ext : {".rawlog.gz", ".rawlog", ".clf.gz", ".log.gz", ".clf", ".log"}) {
    const std::string e(ext);
    if (path.size() > e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0) {
      return path.substr(0, path.size() - e.size());
    }
  }
  return path;
}

// MRPT ICP as a laser odometry: each scan's points aligned against a reference scan's (the
// keyframe's, renewed with lidarseg's policy, or simply the previous scan's), from the same
// kind of prior as lidarseg.
class IcpOdometry {
 public:
  IcpOdometry(mrpt::slam::CICP& icp, bool keyframed, double keyframe_distance_m, double keyframe_angle_rad)
      : icp_(icp), keyframed_(keyframed), key_distance_(keyframe_distance_m), key_angle_(keyframe_angle_rad) {}

  // increment_prior: the wheel-odometry increment, or nothing for constant velocity;
  // restart: the prior restarts from rest (a time gap).
  void process(const mrpt::obs::CObservation2DRangeScan& obs, const std::optional<Pose2D>& increment_prior,
               double dt, bool restart, double stamp, MethodReport& report) {
    const auto t0 = Clock::now();
    auto current = std::make_unique<mrpt::maps::CSimplePointsMap>();
    current->insertionOptions.minDistBetweenLaserPoints = 0.0f;
    current->loadFromRangeScan(obs);
    bool renew = !reference_;
    if (reference_) {
      Pose2D increment;
      if (increment_prior) {
        increment = *increment_prior;
      } else if (!restart && last_dt_ > 0.0) {
        const double k = dt / last_dt_;
        increment = {last_increment_.x * k, last_increment_.y * k, last_increment_.yaw * k};
      }
      // From the reference: T_ref_curr = T_ref_last (+) predicted increment.
      Pose2D T_ref_curr = compose(relative(pose_, reference_pose_), increment);
      if (current->size() >= 5 && reference_->size() >= 5) {
        mrpt::slam::CICP::TReturnInfo info;
        const auto pdf = icp_.AlignPDF(reference_.get(), current.get(),
                                       mrpt::poses::CPosePDFGaussian(toMrpt(T_ref_curr)), info);
        T_ref_curr = toPose2D(pdf->getMeanVal());
        const bool converged = info.nIterations < icp_.options.maxIterations;
        ++report.status_counts[converged ? "converged" : "not_converged"];
        renew = renew || !converged;
      } else {
        ++report.status_counts["skipped"];
        renew = true;
      }
      const Pose2D new_pose = compose(reference_pose_, T_ref_curr);
      last_increment_ = relative(new_pose, pose_);
      last_dt_ = dt;
      pose_ = new_pose;
      renew = renew || !keyframed_ || std::hypot(T_ref_curr.x, T_ref_curr.y) >= key_distance_ ||
              std::abs(T_ref_curr.yaw) >= key_angle_;
    }
    if (renew) {
      reference_ = std::move(current);
      reference_pose_ = pose_;
    }
    report.time_us.push_back(microsecondsSince(t0));
    report.trajectory.push_back({stamp, pose_});
  }

 private:
  mrpt::slam::CICP& icp_;
  bool keyframed_;
  double key_distance_, key_angle_;
  std::unique_ptr<mrpt::maps::CSimplePointsMap> reference_;
  Pose2D reference_pose_, pose_, last_increment_;
  double last_dt_ = 0.0;
};

// Progress on stderr: a counter with the rate, redrawn at most 5 times a second.
class Progress {
 public:
  explicit Progress(bool enabled) : enabled_(enabled && isatty(STDERR_FILENO) == 1) {}
  void update(std::size_t scans, bool force = false) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (!force && now - last_ < std::chrono::milliseconds(200)) return;
    last_ = now;
    const double s = std::chrono::duration<double>(now - start_).count();
    std::cerr << "\r[lidarseg-odometry] " << scans << " scans, " << std::fixed << std::setprecision(1) << s
              << " s (" << std::setprecision(0) << (s > 0 ? static_cast<double>(scans) / s : 0.0) << " scans/s)   " << std::flush;
  }
  void done(std::size_t scans) {
    if (!enabled_) return;
    update(scans, true);
    std::cerr << "\n";
  }

 private:
  bool enabled_;
  Clock::time_point start_ = Clock::now();
  Clock::time_point last_{};
};

void finishMethod(MethodReport& m) { m.time_summary_us = summarize(m.time_us); }

void evaluate(MethodReport& m, const eval::StampedTrajectory* gt, double gt_tolerance,
              const std::vector<eval::Relation>* relations, double rel_tolerance,
              const std::vector<eval::Relation>* log_relations) {
  if (gt != nullptr) m.errors = eval::evaluateTrajectory(m.trajectory, *gt, gt_tolerance);
  if (relations != nullptr) m.relations = eval::evaluateRelations(m.trajectory, *relations, rel_tolerance);
  if (log_relations != nullptr) m.log_relations = eval::evaluateRelations(m.trajectory, *log_relations, 1e-9);
}

std::string tumOf(const eval::StampedTrajectory& t, const std::string& header) {
  std::ostringstream os;
  eval::writeTum(os, t, header);
  return os.str();
}

void writeSummary(JsonWriter& j, const char* key, const Summary& s, double scale) {
  j.beginObject(key);
  j.value("mean", s.mean * scale).value("std", s.stddev * scale).value("median", s.median * scale);
  j.value("p99", s.p99 * scale).value("max", s.max * scale).value("count", s.count);
  j.endObject();
}

void writeRelations(JsonWriter& j, const char* key, const eval::RelationErrors& r) {
  j.beginObject(key);
  j.value("relations", r.relations).value("evaluated", r.evaluated);
  writeSummary(j, "translation_m", r.translation_m, 1.0);
  writeSummary(j, "rotation_deg", r.rotation_rad, 180.0 / M_PI);
  j.endObject();
}

}  // namespace

OdometryApp::OdometryApp(OdometryOptions options) : options_(std::move(options)) {}

OdometryReport OdometryApp::run() {
  const OdometryOptions& o = options_;
  OdometryReport report;
  report.input = o.input;

  // Configuration: lidarseg's sections and MRPT's ICP section.
  OdometryParams params;
  FeatureDetectorParams feature_params;
  mrpt::slam::CICP icp;
  if (!o.config_path.empty()) {
    params = mrpt_adapter::loadOdometryParamsFile(o.config_path);
    feature_params = mrpt_adapter::loadFeatureDetectorParamsFile(o.config_path);
    mrpt::config::CConfigFile cfg(o.config_path);
    if (cfg.sectionExists("icp")) icp.options.loadFromConfigFile(cfg, "icp");
  }
  if (o.scanner_rotation_hz >= 0.0) params.scanner_rotation_hz = o.scanner_rotation_hz;
  if (!o.scan_stamp.empty()) params.scan_stamp = scanStampFromString(o.scan_stamp);
  params.validate();

  // Reference data, read before the run so that a bad file fails early.
  std::string gt_path = o.gt_path;
  if (gt_path.empty() && o.auto_gt) {
    const std::string candidate = stemOf(o.input) + ".gt.tum";
    if (fs::exists(candidate)) gt_path = candidate;
  }
  std::optional<eval::StampedTrajectory> gt;
  if (!gt_path.empty()) gt = eval::readTum(gt_path);
  report.gt_path = gt_path;
  std::optional<std::vector<eval::Relation>> relations;
  if (!o.relations_path.empty()) relations = eval::readRelations(o.relations_path);
  report.relations_path = o.relations_path;

  mrpt_adapter::LaserLogReader reader(o.input, o.sensor);
  report.format = reader.format() == mrpt_adapter::LogFormat::kRawlog ? "rawlog" : "carmen";
  mrpt_adapter::LaserOdometry odometry(params);
  // Doors and corners, when an output wants them.
  const bool want_features = !o.features_out.empty() || !o.write_rawlog.empty();
  const FeatureDetector detector(feature_params);
  std::vector<Feature> features;
  std::ostringstream features_csv;
  writeFeatureCsvHeader(features_csv);

  report.lidarseg.name = "lidarseg";
  MethodReport icp_report, icp_s2s_report;
  icp_report.name = "icp";
  icp_s2s_report.name = "icp-s2s";
  IcpOdometry icp_keyframed(icp, true, params.keyframe_distance_m, params.keyframe_angle_rad);
  IcpOdometry icp_scan_to_scan(icp, false, 0.0, 0.0);
  eval::StampedTrajectory log_poses;

  // Rawlog output, written as it goes under a temporary name.
  OutputSet outputs;
  std::unique_ptr<mrpt::io::CFileGZOutputStream> rawlog_out;
  if (!o.write_rawlog.empty()) {
    rawlog_out = std::make_unique<mrpt::io::CFileGZOutputStream>();
    outputs.addWritten(o.write_rawlog);
    if (!rawlog_out->open(o.write_rawlog + ".tmp", 0)) {
      throw std::runtime_error("cannot write '" + o.write_rawlog + ".tmp'");
    }
  }

  // State of the run.
  Progress progress(o.progress);
  bool have_previous = false;
  double last_stamp = 0.0, last_log_stamp = 0.0, last_model_stamp = 0.0, last_dt = 0.1;
  std::optional<Pose2D> last_odometry;
  Pose2D last_lidarseg_pose;
  std::vector<double> dts;

  while (true) {
    if (o.max_scans != 0 && report.frames >= o.max_scans) break;
    std::optional<mrpt_adapter::LaserRecord> record;
    try {
      record = reader.next();
    } catch (const std::runtime_error& e) {
      if (!o.allow_truncated || report.frames == 0) throw;
      report.log_error = e.what();  // the scans before it stand
      break;
    }
    if (!record) break;
    const auto& obs = *record->observation;

    // Time. The motion model runs on its own clock: the log's steps, with the last good
    // step standing in for a non-increasing one; a long gap restarts the prior from rest.
    // The outputs keep the log's stamps, nudged by 1 ms where one does not increase.
    double model_stamp = record->stamp_s;
    double stamp = record->stamp_s;
    bool restart_prior = false;
    bool synthetic_time = false;
    if (have_previous) {
      const double dt_log = record->stamp_s - last_log_stamp;
      double step_dt = dt_log;
      if (!(dt_log > 0.0)) {
        ++report.non_increasing_stamps;
        synthetic_time = true;
        step_dt = last_dt;
      } else if (dt_log > o.max_time_gap_s) {
        ++report.time_gaps;
        restart_prior = true;
        if (report.warnings.size() < 100) {
          report.warnings.push_back(record->where + ": time gap of " + std::to_string(dt_log) +
                                    " s; the motion prior restarts from rest");
        }
      } else {
        last_dt = dt_log;
      }
      model_stamp = last_model_stamp + step_dt;
      if (!(stamp > last_stamp)) stamp = last_stamp + 1e-3;
    }
    last_log_stamp = record->stamp_s;
    const double dt = have_previous ? model_stamp - last_model_stamp : 0.0;

    // Wheel-odometry prior, when asked for and plausible.
    std::optional<mrpt::poses::CPose2D> odo_increment;
    if (o.use_odometry && record->odometry) {
      if (last_odometry) {
        const Pose2D inc = relative(*record->odometry, *last_odometry);
        // Without a usable time step, a step of up to 0.5 s is allowed.
        const double span = synthetic_time ? 0.5 : std::max(dt, 0.05);
        const double limit_t = o.max_speed_mps * span + 0.1;
        const double limit_r = o.max_turn_rate_radps * span + 0.1;
        if (std::hypot(inc.x, inc.y) > limit_t || std::abs(inc.yaw) > limit_r) {
          ++report.odometry_jumps;
          if (report.warnings.size() < 100) {
            report.warnings.push_back(record->where + ": wheel odometry jumps by " +
                                      std::to_string(std::hypot(inc.x, inc.y)) + " m / " +
                                      std::to_string(inc.yaw) + " rad; ignored as a prior");
          }
        } else {
          odo_increment = toMrpt(inc);
        }
      }
      last_odometry = record->odometry;
    }
    std::optional<mrpt::poses::CPose2D> lidarseg_prior = odo_increment;
    if (!lidarseg_prior && restart_prior) lidarseg_prior = mrpt::poses::CPose2D();

    // lidarseg.
    mrpt_adapter::LaserOdometryStep step;
    try {
      mrpt::obs::CObservation2DRangeScan timed = obs;  // the stamp used for the motion model
      timed.timestamp = mrpt::Clock::fromDouble(model_stamp);
      step = odometry.process(timed, lidarseg_prior);
    } catch (const std::invalid_argument& e) {
      ++report.skipped_count;
      if (report.skipped.size() < 100) report.skipped.push_back(record->where + " (scan " + std::to_string(record->index) + "): " + e.what());
      continue;
    }
    const Pose2D pose = toPose2D(step.robot_pose.mean);
    report.lidarseg.trajectory.push_back({stamp, pose});
    report.lidarseg.segmentation_us.push_back(step.core.wall_danielsson_us);
    report.lidarseg.cascade_us.push_back(step.core.cascade_us);
    report.lidarseg.matching_us.push_back(step.core.matching_us);
    report.lidarseg.time_us.push_back(step.core.wall_danielsson_us + step.core.cascade_us +
                                      step.core.matching_us);
    report.lidarseg.scan_status.push_back(toString(step.core.status));
    report.lidarseg.refinement_us.push_back(step.core.refinement_us);
    report.lidarseg.prior.push_back(step.core.prior);
    report.lidarseg.inlier_ratio.push_back(step.core.refine.inlier_ratio);
    report.lidarseg.refine_iterations.push_back(step.core.refine.iterations);
    report.lidarseg.match_status.push_back(step.core.first ? "first" : toString(step.core.match.status));
    report.lidarseg.scan_matches.push_back(step.core.match.matches.size());
    if (!step.core.first) {
      ++report.lidarseg.status_counts[toString(step.core.status)];
      if (step.core.match.status == MatchStatus::kTooFewMatches) {
        ++report.lidarseg.match_failures[step.core.match.rejections.dominant()];
      }
      if (step.core.status == TrackStatus::kLost) {
        ++report.lidarseg.lost;
        if (report.lidarseg.lost_scans.size() < 1000) report.lidarseg.lost_scans.push_back(record->index);
      }
      if (std::sqrt(std::max(step.increment.cov(0, 0), step.increment.cov(1, 1))) > 0.1) {
        ++report.lidarseg.weak_scans;
      }
    }
    report.lidarseg.final_sigma_x_m = std::sqrt(step.robot_pose.cov(0, 0));
    report.lidarseg.final_sigma_y_m = std::sqrt(step.robot_pose.cov(1, 1));
    report.lidarseg.final_sigma_yaw_rad = std::sqrt(step.robot_pose.cov(2, 2));
    if (record->log_pose) log_poses.push_back({stamp, *record->log_pose});
    if (want_features) {
      detector.detect(odometry.core().lastSegmentation(), features);
      const auto& sp = obs.sensorPose;
      if (!o.features_out.empty()) {
        writeFeatureCsvRows(features_csv, stamp, record->index, {sp.x(), sp.y(), sp.yaw()}, features);
      }
    }

    // MRPT ICP, keyframed like lidarseg and scan to scan, with the same kind of prior.
    {
      std::optional<Pose2D> icp_prior;
      if (odo_increment) icp_prior = toPose2D(*odo_increment);
      if (o.baseline_icp) icp_keyframed.process(obs, icp_prior, dt, restart_prior, stamp, icp_report);
      if (o.baseline_icp_s2s) icp_scan_to_scan.process(obs, icp_prior, dt, restart_prior, stamp, icp_s2s_report);
    }

    // Rawlog output: lidarseg's motion as the robot's odometry action, then the scan and
    // the observations that came with it.
    if (rawlog_out) {
      auto archive = mrpt::serialization::archiveFrom(*rawlog_out);
      mrpt::obs::CActionCollection actions;
      mrpt::obs::CActionRobotMovement2D move;
      const Pose2D inc = step.core.first ? Pose2D{} : relative(pose, last_lidarseg_pose);
      move.rawOdometryIncrementReading = toMrpt(inc);
      move.estimationMethod = mrpt::obs::CActionRobotMovement2D::emScan2DMatching;
      move.poseChange = mrpt::poses::CPosePDFGaussian::Create(toMrpt(inc), step.increment.cov);
      move.timestamp = obs.timestamp;
      actions.insert(move);
      archive << actions;
      mrpt::obs::CSensoryFrame frame;
      // The log's own odometry observations are replaced by lidarseg's action.
      for (const auto& other : record->companions) {
        if (!std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(other)) frame.insert(other);
      }
      frame.insert(record->observation);
      auto landmarks = mrpt_adapter::makeBearingRangeObservation(features, obs.sensorPose, obs.maxRange, obs.aperture);
      landmarks->timestamp = obs.timestamp;
      frame.insert(landmarks);
      archive << frame;
    }
    last_lidarseg_pose = pose;
    if (have_previous) dts.push_back(dt);
    last_stamp = stamp;
    last_model_stamp = model_stamp;
    have_previous = true;
    ++report.frames;
    progress.update(report.frames);
  }
  progress.done(report.frames);
  report.sensor = reader.sensor();
  for (const auto& s : reader.issues()) {
    if (report.skipped.size() < 100) report.skipped.push_back(s);
  }
  report.skipped_count += reader.skipped();
  for (const auto& s : reader.unknownTypes()) report.warnings.push_back(s);
  if (report.frames == 0) {
    throw std::runtime_error("'" + o.input + "' holds no usable laser scan" +
                             (o.sensor.empty() ? std::string() : " with sensor '" + o.sensor + "'"));
  }
  if (rawlog_out) rawlog_out->close();

  // Evaluation.
  finishMethod(report.lidarseg);
  if (static_cast<double>(report.lidarseg.lost) > o.max_lost_ratio * static_cast<double>(report.frames)) {
    report.lidarseg.tracking = "lost";
  }
  const double median_dt = dts.empty() ? 0.1 : summarize(dts).median;
  const double gt_tolerance = std::max(1e-6, 0.25 * median_dt);
  std::optional<std::vector<eval::Relation>> log_relations;
  if (o.log_reference) {
    if (log_poses.size() < 2) {
      report.warnings.push_back("--log-reference: the log has no poses beside its scans");
    } else {
      log_relations = eval::relationsFrom(log_poses, 0.0, 0.0, 1);
    }
  }
  evaluate(report.lidarseg, gt ? &*gt : nullptr, gt_tolerance, relations ? &*relations : nullptr,
           o.relations_tolerance_s, log_relations ? &*log_relations : nullptr);
  const auto finishIcp = [&](MethodReport& m, std::optional<MethodReport>& slot) {
    finishMethod(m);
    evaluate(m, gt ? &*gt : nullptr, gt_tolerance, relations ? &*relations : nullptr, o.relations_tolerance_s,
             log_relations ? &*log_relations : nullptr);
    slot = std::move(m);
  };
  if (o.baseline_icp) {
    finishIcp(icp_report, report.icp);
    if (report.lidarseg.time_summary_us.median > 0.0) {
      report.speedup_median = report.icp->time_summary_us.median / report.lidarseg.time_summary_us.median;
    }
  }
  if (o.baseline_icp_s2s) finishIcp(icp_s2s_report, report.icp_s2s);

  // Outputs, all put in place together.
  if (!o.out_dir.empty()) {
    fs::create_directories(o.out_dir);
    const auto path = [&](const char* name) { return (fs::path(o.out_dir) / name).string(); };
    outputs.add(path("lidarseg.tum"), tumOf(report.lidarseg.trajectory, "lidarseg robot poses, odometry frame"));
    if (report.icp) outputs.add(path("icp.tum"), tumOf(report.icp->trajectory, "MRPT ICP (keyframed) robot poses, odometry frame"));
    if (report.icp_s2s) {
      outputs.add(path("icp-s2s.tum"), tumOf(report.icp_s2s->trajectory, "MRPT ICP (scan to scan) robot poses, odometry frame"));
    }
    std::ostringstream csv;
    csv << "index,stamp_s,segmentation_us,cascade_us,matching_us,total_us,status,matches,refinement_us,"
           "inlier_ratio,refine_iterations,match_status,prior_x_m,prior_y_m,prior_yaw_rad"
        << (report.icp ? ",icp_total_us" : "") << (report.icp_s2s ? ",icp_s2s_total_us" : "") << "\n";
    csv << std::setprecision(9);
    for (std::size_t k = 0; k < report.lidarseg.time_us.size(); ++k) {
      csv << k << ',' << std::fixed << report.lidarseg.trajectory[k].stamp_s << std::defaultfloat << ','
          << report.lidarseg.segmentation_us[k] << ',' << report.lidarseg.cascade_us[k] << ','
          << report.lidarseg.matching_us[k] << ',' << report.lidarseg.time_us[k];
      csv << ',' << report.lidarseg.scan_status[k] << ',' << report.lidarseg.scan_matches[k] << ','
          << report.lidarseg.refinement_us[k] << ',' << report.lidarseg.inlier_ratio[k] << ','
          << report.lidarseg.refine_iterations[k] << ',' << report.lidarseg.match_status[k] << ','
          << report.lidarseg.prior[k].x << ',' << report.lidarseg.prior[k].y << ',' << report.lidarseg.prior[k].yaw;
      if (report.icp) csv << ',' << report.icp->time_us[k];
      if (report.icp_s2s) csv << ',' << report.icp_s2s->time_us[k];
      csv << '\n';
    }
    outputs.add(path("timing.csv"), csv.str());
    outputs.add(path("summary.json"), summaryJson(report));
    outputs.add(path("results.md"), markdownTable(report));
    if (o.plots) {
      std::vector<PlotSeries> series;
      const auto add = [&](const std::string& name, const eval::StampedTrajectory& t, int b, int g, int r,
                           const Pose2D& anchor) {
        PlotSeries s{name, b, g, r, {}, {}, false};
        for (const auto& p : t) {
          const Pose2D q = compose(anchor, p.pose);
          s.x.push_back(q.x);
          s.y.push_back(q.y);
        }
        series.push_back(std::move(s));
      };
      // Every trajectory starts where the reference starts (ground truth or log poses).
      const eval::StampedTrajectory* reference = gt ? &*gt : (log_poses.empty() ? nullptr : &log_poses);
      Pose2D anchor;
      if (reference != nullptr) {
        const auto k = eval::nearestIndex(*reference, report.lidarseg.trajectory.front().stamp_s, gt_tolerance);
        if (k) anchor = (*reference)[*k].pose;
        add(gt ? "ground truth" : "log poses", *reference, 0, 0, 0, {});
      }
      add("lidarseg", report.lidarseg.trajectory, 200, 80, 0, anchor);
      if (report.icp) add("MRPT ICP keyframed", report.icp->trajectory, 0, 0, 220, anchor);
      if (report.icp_s2s) add("MRPT ICP s2s", report.icp_s2s->trajectory, 160, 0, 160, anchor);
      outputs.add(path("trajectories.png"), plotTrajectoriesPng(series, "Trajectories: " + fs::path(o.input).filename().string()));
      std::vector<PlotSeries> hist;
      hist.push_back({"lidarseg", 200, 80, 0, report.lidarseg.time_us, {}, false});
      if (report.icp) hist.push_back({"MRPT ICP keyframed", 0, 0, 220, report.icp->time_us, {}, false});
      outputs.add(path("timing.png"), plotHistogramsPng(hist, "Time per scan", "microseconds"));
    }
    report.outputs = {path("lidarseg.tum"), path("timing.csv"), path("summary.json"), path("results.md")};
    if (report.icp) report.outputs.push_back(path("icp.tum"));
    if (report.icp_s2s) report.outputs.push_back(path("icp-s2s.tum"));
  }
  if (!o.features_out.empty()) outputs.add(o.features_out, features_csv.str());
  outputs.commit();
  if (!o.write_rawlog.empty()) report.outputs.push_back(o.write_rawlog);
  return report;
}

std::string OdometryApp::markdownTable(const OdometryReport& r) {
  std::ostringstream os;
  os << std::fixed;
  std::vector<const MethodReport*> methods = {&r.lidarseg};
  if (r.icp) methods.push_back(&*r.icp);
  if (r.icp_s2s) methods.push_back(&*r.icp_s2s);
  os << "Input: `" << r.input << "` (" << r.format << ", sensor " << r.sensor << "), " << r.frames
     << " scans";
  if (!r.gt_path.empty()) os << ", ground truth `" << r.gt_path << "`";
  os << "\n\n";
  const bool gt = r.lidarseg.errors.has_value();
  os << "| method | t (ms) | σt (ms) | median (ms) | p99 (ms) | max (ms)";
  if (gt) os << " | edx (mm) | σedx (mm) | edy (mm) | σedy (mm) | edθ (mrad) | σedθ (mrad) | final error (m) | ATE RMSE (m)";
  os << " |\n|---|---:|---:|---:|---:|---:";
  if (gt) os << "|---:|---:|---:|---:|---:|---:|---:|---:";
  os << "|\n";
  for (const auto* m : methods) {
    const Summary& t = m->time_summary_us;
    os << "| " << m->name << " | " << std::setprecision(4) << t.mean / 1e3 << " | " << t.stddev / 1e3 << " | "
       << t.median / 1e3 << " | " << t.p99 / 1e3 << " | " << t.max / 1e3;
    if (gt && m->errors) {
      const auto& e = *m->errors;
      os << std::setprecision(2) << " | " << e.motion.dx_m.mean * 1e3 << " | " << e.motion.dx_m.stddev * 1e3
         << " | " << e.motion.dy_m.mean * 1e3 << " | " << e.motion.dy_m.stddev * 1e3 << " | "
         << e.motion.dtheta_rad.mean * 1e3 << " | " << e.motion.dtheta_rad.stddev * 1e3 << " | "
         << std::setprecision(3) << e.final_position_error_m << " | " << e.ate_rmse_m;
    }
    os << " |\n";
  }
  os << "\nlidarseg matches:";
  for (const auto& [k, v] : r.lidarseg.status_counts) os << " " << k << " " << v << ";";
  os << " scans with a translation 1-sigma above 0.1 m: " << r.lidarseg.weak_scans
     << ". Final pose 1-sigma from the propagated covariance: " << std::setprecision(3)
     << r.lidarseg.final_sigma_x_m << " m, " << r.lidarseg.final_sigma_y_m << " m, "
     << r.lidarseg.final_sigma_yaw_rad * 180 / M_PI << " deg.\n";
  if (!r.lidarseg.match_failures.empty()) {
    os << "\nSegment matches that failed, by their main reason:";
    for (const auto& [k, v] : r.lidarseg.match_failures) os << " " << k << " " << v << ";";
    os << "\n";
  }
  if (r.lidarseg.tracking == "lost") {
    os << "\n**lidarseg lost track**: " << r.lidarseg.lost << " of " << r.frames
       << " scans lost (the prediction was kept); no speed-up is claimed for this run.\n";
  } else if (r.icp) {
    os << "\nSpeed-up (median ICP time / median lidarseg time, same run): " << std::setprecision(1)
       << r.speedup_median << "x\n";
  }
  const auto relTable = [&](const char* title, auto get) {
    if (!get(r.lidarseg)) return;
    os << "\n" << title << "\n\n| method | evaluated | trans. mean (m) | trans. median (m) | trans. std (m) | rot. mean (deg) | rot. median (deg) | rot. std (deg) |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto* m : methods) {
      const auto& e = *get(*m);
      os << "| " << m->name << " | " << e.evaluated << "/" << e.relations << std::setprecision(4) << " | "
         << e.translation_m.mean << " | " << e.translation_m.median << " | " << e.translation_m.stddev << " | "
         << e.rotation_rad.mean * 180 / M_PI << " | " << e.rotation_rad.median * 180 / M_PI << " | "
         << e.rotation_rad.stddev * 180 / M_PI << " |\n";
    }
  };
  relTable("Relations (Kümmerle et al. 2009):", [](const MethodReport& m) { return m.relations ? &*m.relations : nullptr; });
  relTable("Per-scan relative motion against the log's poses:",
           [](const MethodReport& m) { return m.log_relations ? &*m.log_relations : nullptr; });
  return os.str();
}

std::string OdometryApp::summaryJson(const OdometryReport& r) {
  JsonWriter j;
  j.beginObject();
  j.value("input", r.input).value("format", r.format).value("sensor", r.sensor).value("frames", r.frames);
  j.value("skipped", r.skipped_count);
  j.beginArray("skipped_examples");
  for (const auto& s : r.skipped) j.value(nullptr, s);
  j.endArray();
  j.value("non_increasing_stamps", r.non_increasing_stamps).value("time_gaps", r.time_gaps);
  j.value("odometry_jumps", r.odometry_jumps);
  if (!r.log_error.empty()) j.value("log_error", r.log_error);
  j.beginArray("warnings");
  for (const auto& s : r.warnings) j.value(nullptr, s);
  j.endArray();
  if (!r.gt_path.empty()) j.value("ground_truth", r.gt_path);
  if (!r.relations_path.empty()) j.value("relations", r.relations_path);
  j.beginObject("methods");
  std::vector<const MethodReport*> methods = {&r.lidarseg};
  if (r.icp) methods.push_back(&*r.icp);
  if (r.icp_s2s) methods.push_back(&*r.icp_s2s);
  for (const auto* m : methods) {
    j.beginObject(m->name.c_str());
    writeSummary(j, "time_ms", m->time_summary_us, 1e-3);
    j.value("trajectory", m->name + ".tum");
    j.beginObject("status");
    for (const auto& [k, v] : m->status_counts) j.value(k.c_str(), v);
    j.endObject();
    if (m->name == "lidarseg") {
      writeSummary(j, "segmentation_ms", summarize(m->segmentation_us), 1e-3);
      writeSummary(j, "cascade_ms", summarize(m->cascade_us), 1e-3);
      writeSummary(j, "matching_ms", summarize(m->matching_us), 1e-3);
      j.beginObject("final_sigma");
      j.value("x_m", m->final_sigma_x_m).value("y_m", m->final_sigma_y_m).value("yaw_rad", m->final_sigma_yaw_rad);
      j.endObject();
      j.value("weak_scans", m->weak_scans);
      j.value("tracking", m->tracking).value("lost", m->lost);
      j.beginArray("lost_scans");
      for (const auto k : m->lost_scans) j.value(nullptr, k);
      j.endArray();
      j.beginObject("match_failures");
      for (const auto& [k, v] : m->match_failures) j.value(k.c_str(), v);
      j.endObject();
    }
    if (m->errors) {
      const auto& e = *m->errors;
      j.beginObject("errors");
      j.value("associated", e.associated).value("path_length_m", e.path_length_m);
      j.value("final_position_error_m", e.final_position_error_m).value("final_yaw_error_rad", e.final_yaw_error_rad);
      j.value("ate_rmse_m", e.ate_rmse_m).value("ate_mean_m", e.ate_mean_m).value("ate_max_m", e.ate_max_m);
      j.beginObject("table1");
      j.value("t_ms", m->time_summary_us.mean * 1e-3).value("sigma_t_ms", m->time_summary_us.stddev * 1e-3);
      j.value("edx_m", e.motion.dx_m.mean).value("sigma_edx_m", e.motion.dx_m.stddev);
      j.value("edy_m", e.motion.dy_m.mean).value("sigma_edy_m", e.motion.dy_m.stddev);
      j.value("edtheta_rad", e.motion.dtheta_rad.mean).value("sigma_edtheta_rad", e.motion.dtheta_rad.stddev);
      j.endObject();
      j.endObject();
    }
    if (m->relations) writeRelations(j, "relations", *m->relations);
    if (m->log_relations) writeRelations(j, "log_relations", *m->log_relations);
    j.endObject();
  }
  j.endObject();
  if (r.icp) j.value("speedup_median", r.speedup_median);
  j.endObject();
  return j.str();
}

void OdometryApp::print(const OdometryReport& r, std::ostream& os) {
  os << markdownTable(r);
  os << "\nskipped: " << r.skipped_count << ", non-increasing stamps: " << r.non_increasing_stamps
     << ", time gaps: " << r.time_gaps << ", odometry jumps: " << r.odometry_jumps << "\n";
  os << "lidarseg status:";
  for (const auto& [k, v] : r.lidarseg.status_counts) os << " " << k << "=" << v;
  os << "\n";
  for (const auto& s : r.skipped) os << "skipped: " << s << "\n";
  for (const auto& s : r.warnings) os << "warning: " << s << "\n";
  if (!r.log_error.empty()) {
    os << "warning: the log ends early: " << r.log_error << "; the results cover the " << r.frames
       << " scans before it\n";
  }
  for (const auto& s : r.outputs) os << "wrote " << s << "\n";
}

}  // namespace lidarseg::apps
