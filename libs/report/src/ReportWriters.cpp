#include "lidarseg/report/ReportWriters.h"
#include "lidarseg/report/Baselines.h"
#include "lidarseg/core/Angles.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "lidarseg/report/JsonText.h"
#include "lidarseg/report/OutputFiles.h"
#include "lidarseg/report/Plots.h"
#include "lidarseg/report/RecordGate.h"
#include "lidarseg/report/RunEvaluation.h"

namespace lidarseg::report {

namespace {

Json number(double v) { return finiteOrNull(v); }

Json summaryOf(const Summary& s, double scale) {
  if (s.count == 0) {  // nothing evaluated: no statistic, not a perfect 0
    return Json{{"mean", nullptr}, {"std", nullptr}, {"median", nullptr}, {"p99", nullptr}, {"max", nullptr}, {"count", 0}};
  }
  return Json{{"mean", number(s.mean * scale)},     {"std", number(s.stddev * scale)},
              {"median", number(s.median * scale)}, {"p99", number(s.p99 * scale)},
              {"max", number(s.max * scale)},       {"count", s.count}};
}

Json relationsOf(const eval::RelationErrors& r) {
  return Json{{"relations", r.relations},
              {"evaluated", r.evaluated},
              {"translation_m", summaryOf(r.translation_m, 1.0)},
              {"rotation_deg", summaryOf(r.rotation_rad, kRadToDeg)}};
}

Json errorsOf(const MethodReport& m) {
  const auto& e = *m.errors;
  return Json{{"associated", e.associated},
              {"path_length_m", number(e.path_length_m)},
              {"final_position_error_m", number(e.final_position_error_m)},
              {"final_yaw_error_rad", number(e.final_yaw_error_rad)},
              {"ate_rmse_m", number(e.ate_rmse_m)},
              {"ate_mean_m", number(e.ate_mean_m)},
              {"ate_max_m", number(e.ate_max_m)},
              {"table1",
               {{"t_ms", number(m.time_summary_us.mean * 1e-3)},
                {"sigma_t_ms", number(m.time_summary_us.stddev * 1e-3)},
                {"edx_m", number(e.motion.dx_m.mean)},
                {"sigma_edx_m", number(e.motion.dx_m.stddev)},
                {"edy_m", number(e.motion.dy_m.mean)},
                {"sigma_edy_m", number(e.motion.dy_m.stddev)},
                {"edtheta_rad", number(e.motion.dtheta_rad.mean)},
                {"sigma_edtheta_rad", number(e.motion.dtheta_rad.stddev)}}}};
}

Json methodOf(const MethodReport& m) {
  Json j{{"time_ms", summaryOf(m.time_summary_us, 1e-3)}, {"trajectory", m.name + ".tum"}};
  j["status"] = Json::object();
  for (const auto& [k, v] : m.status_counts) j["status"][k] = v;
  if (m.name == "lidarseg") {
    j["segmentation_ms"] = summaryOf(summarize(m.segmentation_us), 1e-3);
    j["cascade_ms"] = summaryOf(summarize(m.cascade_us), 1e-3);
    j["matching_ms"] = summaryOf(summarize(m.matching_us), 1e-3);
    j["final_sigma"] = {{"x_m", number(m.final_sigma_x_m)},
                        {"y_m", number(m.final_sigma_y_m)},
                        {"yaw_rad", number(m.final_sigma_yaw_rad)}};
    j["weak_scans"] = m.weak_scans;
    j["tracking"] = m.tracking;
    j["lost"] = m.lost;
    j["lost_scans"] = m.lost_scans;
    j["searches"] = m.searches;
    j["wide_searches"] = m.wide_searches;
    j["deskewed_again"] = m.deskewed_again;
    j["revised_keyframes"] = m.revised_keyframes;
    j["match_failures"] = Json::object();
    for (const auto& [k, v] : m.match_failures) j["match_failures"][k] = v;
  }
  if (m.errors) j["errors"] = errorsOf(m);
  if (m.nees) {
    // Nothing evaluated: no statistic (null), not a perfect 0.
    const bool any = m.nees->evaluated > 0;
    const auto figure = [&](double v) { return any ? number(v) : Json(nullptr); };
    j["nees"] = {{"evaluated", m.nees->evaluated},
                 {"singular", m.nees->singular},
                 {"mean", figure(m.nees->mean)},
                 {"median", figure(m.nees->median)},
                 {"share_within_95", figure(m.nees->share_within_95)}};
  }
  if (m.relations) j["relations"] = relationsOf(*m.relations);
  if (m.log_relations) j["log_relations"] = relationsOf(*m.log_relations);
  return j;
}

std::vector<const MethodReport*> methodsOf(const OdometryReport& r) {
  std::vector<const MethodReport*> methods = {&r.lidarseg};
  for (const MethodReport& b : r.baselines) methods.push_back(&b);
  return methods;
}

// A baseline's column of timing.csv: "icp-s2s" gives "icp_s2s_total_us".
std::string timeColumn(const std::string& name) {
  std::string c = name;
  std::replace(c.begin(), c.end(), '-', '_');
  return c + "_total_us";
}

// A baseline's kind (its file's header, the pictures' label and colour); every baseline a
// run makes has one.
const BaselineKind& kindOf(const MethodReport& baseline) {
  const BaselineKind* k = baselineKind(baseline.name);
  if (k == nullptr) throw std::logic_error("a baseline of no known kind: '" + baseline.name + "'");
  return *k;
}

}  // namespace

std::string tumText(const eval::StampedTrajectory& t, const std::string& header) {
  std::ostringstream os;
  eval::writeTum(os, t, header);
  return os.str();
}

std::string timingCsv(const OdometryReport& report) {
  const MethodReport& l = report.lidarseg;
  std::ostringstream csv;
  csv << "index,stamp_s,segmentation_us,cascade_us,matching_us,total_us,status,matches,refinement_us,"
         "inlier_ratio,refine_iterations,match_status,prior_x_m,prior_y_m,prior_yaw_rad,searched";
  for (const MethodReport& b : report.baselines) csv << ',' << timeColumn(b.name);
  csv << "\n";
  csv << std::setprecision(9);
  for (std::size_t k = 0; k < l.time_us.size(); ++k) {
    csv << k << ',' << std::fixed << l.trajectory[k].stamp_s << std::defaultfloat << ',' << l.segmentation_us[k]
        << ',' << l.cascade_us[k] << ',' << l.matching_us[k] << ',' << l.time_us[k] << ',' << l.scan_status[k] << ','
        << l.scan_matches[k] << ',' << l.refinement_us[k] << ',' << l.inlier_ratio[k] << ','
        << l.refine_iterations[k] << ',' << l.match_status[k] << ',' << l.prior[k].x << ',' << l.prior[k].y << ','
        << l.prior[k].yaw << ',' << static_cast<int>(l.searched[k]);
    for (const MethodReport& b : report.baselines) csv << ',' << b.time_us[k];
    csv << '\n';
  }
  return csv.str();
}

namespace {

Json summaryObject(const OdometryReport& r) {
  Json j{{"input", r.input},
         {"format", r.format},
         {"sensor", r.sensor},
         {"frames", r.frames},
         {"skipped", r.skipped_count},
         {"skipped_examples", r.skipped},
         {"non_increasing_stamps", r.non_increasing_stamps},
         {"time_gaps", r.time_gaps},
         {"clock_jumps", r.clock_jumps},
         {"odometry_jumps", r.odometry_jumps},
         {"prior", r.prior},
         {"beam_times", r.beam_times},
         {"odometry_priors", r.odometry_priors}};
  if (!r.log_error.empty()) j["log_error"] = r.log_error;
  j["warnings"] = r.warnings;
  j["warning_kinds"] = warningKindsJson(r.warning_kinds);
  if (!r.gt_path.empty()) j["ground_truth"] = r.gt_path;
  if (!r.relations_path.empty()) j["relations"] = r.relations_path;
  j["methods"] = Json::object();
  for (const auto* m : methodsOf(r)) j["methods"][m->name] = methodOf(*m);
  if (r.baseline(kSpeedupBaseline)) j["speedup_median"] = number(r.speedup_median);
  return j;
}

}  // namespace

std::string summaryJson(const OdometryReport& r) { return jsonText(summaryObject(r)); }

std::string summaryJson(const OdometryReport& r, const std::vector<std::string>& files) {
  Json j = summaryObject(r);
  j[OutputSet::kManifestFiles] = files;
  return jsonText(j);
}

namespace {

void tableOne(const OdometryReport& r, std::ostream& os) {
  const bool gt = r.lidarseg.errors.has_value();
  os << "| method | t (ms) | σt (ms) | median (ms) | p99 (ms) | max (ms)";
  if (gt) os << " | edx (mm) | σedx (mm) | edy (mm) | σedy (mm) | edθ (mrad) | σedθ (mrad) | final error (m) | ATE RMSE (m)";
  os << " |\n|---|---:|---:|---:|---:|---:";
  if (gt) os << "|---:|---:|---:|---:|---:|---:|---:|---:";
  os << "|\n";
  for (const auto* m : methodsOf(r)) {
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
}

void lidarsegCounts(const OdometryReport& r, std::ostream& os) {
  os << "\nlidarseg matches:";
  for (const auto& [k, v] : r.lidarseg.status_counts) os << " " << k << " " << v << ";";
  os << " scans with a translation 1-sigma above 0.1 m: " << r.lidarseg.weak_scans
     << ". Final pose 1-sigma from the propagated covariance: " << std::setprecision(3)
     << r.lidarseg.final_sigma_x_m << " m, " << r.lidarseg.final_sigma_y_m << " m, "
     << r.lidarseg.final_sigma_yaw_rad * kRadToDeg << " deg.\n";
  if (r.lidarseg.nees && r.lidarseg.nees->evaluated > 0) {
    const eval::NeesSummary& n = *r.lidarseg.nees;
    os << "\nCovariance against the ground truth: NEES of the motion from the keyframe over " << n.evaluated
       << " scans, mean " << std::setprecision(2) << n.mean << ", median " << n.median << " (chi-square(3): 3 and "
       << "2.37), " << std::setprecision(1) << 100.0 * n.share_within_95 << " % at or below 7.81 (95 %).\n";
  }
  if (!r.lidarseg.match_failures.empty()) {
    os << "\nSegment matches that failed, by their main reason:";
    for (const auto& [k, v] : r.lidarseg.match_failures) os << " " << k << " " << v << ";";
    os << "\n";
  }
  if (r.lidarseg.tracking == "lost") {
    os << "\n**lidarseg lost track**: " << r.lidarseg.lost << " of " << r.frames
       << " scans lost (the prediction was kept); no speed-up is claimed for this run.\n";
  } else if (r.baseline(kSpeedupBaseline)) {
    os << "\nSpeed-up (median ICP time / median lidarseg time, same run): " << std::setprecision(1)
       << r.speedup_median << "x\n";
  }
}

template <typename Get>
void relationTable(const OdometryReport& r, const char* title, Get get, std::ostream& os) {
  if (!get(r.lidarseg)) return;
  os << "\n" << title
     << "\n\n| method | evaluated | trans. mean (m) | trans. median (m) | trans. std (m) | rot. mean (deg) | rot. "
        "median (deg) | rot. std (deg) |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto* m : methodsOf(r)) {
    const auto& e = *get(*m);
    if (e.evaluated == 0) {  // nothing evaluated: no statistic, not a perfect 0
      os << "| " << m->name << " | 0/" << e.relations << " | — | — | — | — | — | — |\n";
      continue;
    }
    os << "| " << m->name << " | " << e.evaluated << "/" << e.relations << std::setprecision(4) << " | "
       << e.translation_m.mean << " | " << e.translation_m.median << " | " << e.translation_m.stddev << " | "
       << e.rotation_rad.mean * kRadToDeg << " | " << e.rotation_rad.median * kRadToDeg << " | "
       << e.rotation_rad.stddev * kRadToDeg << " |\n";
  }
}

}  // namespace

std::string markdownTable(const OdometryReport& r) {
  std::ostringstream os;
  os << std::fixed;
  os << "Input: `" << r.input << "` (" << r.format << ", sensor " << r.sensor << "), " << r.frames << " scans";
  if (!r.gt_path.empty()) os << ", ground truth `" << r.gt_path << "`";
  os << "; prior: " << r.prior;
  if (r.odometry_priors > 0) os << " (" << r.odometry_priors << " scans)";
  os << "\n\n";
  tableOne(r, os);
  lidarsegCounts(r, os);
  relationTable(r, "Relations (Kümmerle et al. 2009):",
                [](const MethodReport& m) { return m.relations ? &*m.relations : nullptr; }, os);
  relationTable(r, "Per-scan relative motion against the log's poses:",
                [](const MethodReport& m) { return m.log_relations ? &*m.log_relations : nullptr; }, os);
  return os.str();
}

namespace {

// A trajectory moved so that it starts at the identity (the log's wheel odometry and poses
// are compared from the first scan's pose).
eval::StampedTrajectory fromFirst(eval::StampedTrajectory t) {
  if (t.empty()) return t;
  const Pose2D first = t.front().pose;
  for (auto& p : t) p.pose = relative(p.pose, first);
  return t;
}

}  // namespace

std::vector<std::string> runOutputNames() {
  std::vector<std::string> names = {"lidarseg.tum", "wheel-odometry.tum", "log-poses.tum", "timing.csv",
                                    "results.md",   "trajectories.png",   "timing.png",    "summary.json"};
  for (const BaselineKind& k : baselineKinds()) names.push_back(k.name + ".tum");
  return names;
}

std::vector<std::string> runOutputNames(const std::vector<std::string>& baselines, bool plots) {
  std::vector<std::string> names = {"lidarseg.tum", "wheel-odometry.tum", "log-poses.tum", "timing.csv", "results.md",
                                    "summary.json"};
  for (const std::string& b : baselines) names.push_back(b + ".tum");
  if (plots) names.insert(names.end(), {"trajectories.png", "timing.png"});
  return names;
}

std::vector<std::string> addRunOutputs(OutputSet& outputs, const std::string& out_dir, const OdometryReport& report,
                                       const eval::StampedTrajectory& log_poses,
                                       const eval::StampedTrajectory& wheel_odometry) {
  namespace fs = std::filesystem;
  fs::create_directories(out_dir);
  const auto path = [&](const char* name) { return (fs::path(out_dir) / name).string(); };
  outputs.add(path("lidarseg.tum"), tumText(report.lidarseg.trajectory, "lidarseg robot poses, odometry frame"));
  for (const MethodReport& b : report.baselines) {
    outputs.add(path((b.name + ".tum").c_str()),
                tumText(b.trajectory, kindOf(b).description + " robot poses, odometry frame"));
  }
  // The log's own wheel odometry and poses, for tools such as evo to compare with.
  if (!wheel_odometry.empty()) {
    outputs.add(path("wheel-odometry.tum"),
                tumText(fromFirst(wheel_odometry), "the log's wheel odometry, from the first scan's pose"));
  }
  if (!log_poses.empty()) {
    outputs.add(path("log-poses.tum"),
                tumText(fromFirst(log_poses), "the log's own poses (CARMEN: corrected), from the first scan's pose"));
  }
  outputs.add(path("timing.csv"), timingCsv(report));
  // Written at commit, listing every file of the set (the plots and a --features-out or
  // --write-rawlog in this folder included). Of an older set's files, only those with the
  // names below are removed when this set does not write them: a file the user named (a
  // rawlog written by --write-rawlog may be this run's input) is left in place.
  outputs.addManifest(path("summary.json"),
                      [&report](const std::vector<std::string>& files) { return summaryJson(report, files); },
                      runOutputNames());
  outputs.add(path("results.md"), markdownTable(report));
  std::vector<std::string> written = {path("lidarseg.tum"), path("timing.csv"), path("summary.json"), path("results.md")};
  for (const MethodReport& b : report.baselines) written.push_back(path((b.name + ".tum").c_str()));
  if (!wheel_odometry.empty()) written.push_back(path("wheel-odometry.tum"));
  if (!log_poses.empty()) written.push_back(path("log-poses.tum"));
  return written;
}

namespace {
// The run's trajectories as chart series: the reference as it is, then the wheel odometry
// and every method from the reference's pose at lidarseg's first scan.
std::vector<PlotSeries> trajectorySeries(const OdometryReport& report, const RunReferences& refs,
                                         const eval::StampedTrajectory& log_poses,
                                         const eval::StampedTrajectory& wheel_odometry) {
  std::vector<PlotSeries> series;
  const auto add = [&](const std::string& name, const eval::StampedTrajectory& t, Rgb colour, const Pose2D& anchor) {
    if (t.empty()) return;
    PlotSeries s = makeSeries(name, colour);
    const Pose2D first_inverse = inverse(t.front().pose);
    for (const auto& p : t) {
      const Pose2D q = compose(anchor, compose(first_inverse, p.pose));
      s.x.push_back(q.x);
      s.y.push_back(q.y);
    }
    series.push_back(std::move(s));
  };
  const eval::StampedTrajectory* reference = refs.gt ? &*refs.gt : (log_poses.empty() ? nullptr : &log_poses);
  Pose2D anchor;
  if (reference != nullptr) {
    const auto k = eval::nearestIndex(*reference, report.lidarseg.trajectory.front().stamp_s, refs.gt_tolerance_s);
    if (k) anchor = (*reference)[*k].pose;
    PlotSeries s = makeSeries(refs.gt ? "ground truth" : "log poses", kTruthColour);
    for (const auto& p : *reference) s.x.push_back(p.pose.x), s.y.push_back(p.pose.y);
    series.push_back(std::move(s));
  }
  add("wheel odometry", wheel_odometry, kWheelColour, anchor);
  add("lidarseg", report.lidarseg.trajectory, kLidarsegColour, anchor);
  for (const MethodReport& b : report.baselines) add(kindOf(b).label, b.trajectory, kindOf(b).colour, anchor);
  return series;
}
}  // namespace

void addRunPlots(OutputSet& outputs, const std::string& out_dir, const OdometryReport& report,
                 const RunReferences& refs, const eval::StampedTrajectory& log_poses,
                 const eval::StampedTrajectory& wheel_odometry, const std::string& input_name) {
  const auto path = [&](const char* name) { return (std::filesystem::path(out_dir) / name).string(); };
  std::vector<PlotSeries> hist;
  hist.push_back(makeSeries("lidarseg", kLidarsegColour));
  hist.back().x = report.lidarseg.time_us;
  // lidarseg's time beside the speed-up's baseline (the scan-to-scan one would crowd it).
  if (const MethodReport* b = report.baseline(kSpeedupBaseline)) {
    hist.push_back(makeSeries(kindOf(*b).label, kindOf(*b).colour));
    hist.back().x = b->time_us;
  }
  outputs.add(path("trajectories.png"), plotTrajectoriesPng(trajectorySeries(report, refs, log_poses, wheel_odometry),
                                                            "Trajectories: " + input_name));
  outputs.add(path("timing.png"), plotHistogramsPng(hist, "Time per scan", "microseconds"));
}

void printRunSummary(const OdometryReport& r, std::ostream& os) {
  os << markdownTable(r);
  os << "\n" << recordCountsLine(r.skipped_count, r) << ", odometry jumps: " << r.odometry_jumps << "\n";
  os << "lidarseg status:";
  for (const auto& [k, v] : r.lidarseg.status_counts) os << " " << k << "=" << v;
  os << "\n";
  for (const auto& s : r.outputs) os << "wrote " << s << "\n";
}

void printRunWarnings(const OdometryReport& r, const std::string& tool_name, std::ostream& err) {
  const std::string tool = tool_name + ": warning: ";
  printWarningKinds(r.warning_kinds, tool_name, err);
  if (r.skipped_count > 0) {
    err << tool << r.skipped_count << " scans or lines skipped, the first: "
        << (r.skipped.empty() ? std::string("?") : r.skipped.front()) << " (all in summary.json)\n";
  }
  if (!r.log_error.empty()) {
    err << tool << "the log ends early: " << r.log_error << "; the results cover the " << r.frames
        << " scans before it\n";
  }
}

}  // namespace lidarseg::report
