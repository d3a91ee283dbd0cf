#include "lidarseg/report/RunEvaluation.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "lidarseg/core/NumberText.h"
#include "lidarseg/eval/TrajectoryMetrics.h"

namespace lidarseg::report {

namespace {

// A tolerance as a user reads it (3 significant digits: 0.005, not 0.004999995231628418).
std::string shortNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

std::string stemOf(const std::string& path) {
  for (const char* ext : {".rawlog.gz", ".rawlog", ".clf.gz", ".log.gz", ".clf", ".log"}) {
    const std::string e(ext);
    if (path.size() > e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0) {
      return path.substr(0, path.size() - e.size());
    }
  }
  return path;
}

void evaluate(MethodReport& m, const RunReferences& refs, double relations_tolerance_s) {
  if (refs.gt) m.errors = eval::evaluateTrajectory(m.trajectory, *refs.gt, refs.gt_tolerance_s);
  if (refs.gt && !m.keyframe_motions.empty()) {
    m.nees = eval::evaluateNees(m.keyframe_motions, *refs.gt, refs.gt_tolerance_s);
  }
  if (refs.relations)
    m.relations = eval::evaluateRelations(m.trajectory, *refs.relations, relations_tolerance_s);
  if (refs.log_relations)
    m.log_relations = eval::evaluateRelations(m.trajectory, *refs.log_relations, 1e-9);
}

}  // namespace

std::string groundTruthBeside(const std::string& log_path) {
  const std::string stem = stemOf(log_path);
  std::vector<std::string> candidates = {stem + ".gt.tum"};
  // lidarseg-simulate --carmen writes PREFIX.carmen.log beside PREFIX.gt.tum.
  const std::string carmen = ".carmen";
  if (stem.size() > carmen.size() && stem.compare(stem.size() - carmen.size(), carmen.size(), carmen) == 0) {
    candidates.push_back(stem.substr(0, stem.size() - carmen.size()) + ".gt.tum");
  }
  for (const std::string& c : candidates) {
    if (std::filesystem::exists(c)) return c;
  }
  return {};
}

std::string truthPairingProblem(const std::string& truth_path, const eval::StampedTrajectory& truth,
                                const std::vector<double>& stamps_s, double tolerance_s) {
  std::size_t paired = 0;
  for (double t : stamps_s) paired += eval::nearestIndex(truth, t, tolerance_s).has_value();
  if (paired >= 2) return {};
  std::string text = "ground truth '" + truth_path + "': " + std::to_string(paired) + " of the " +
                     std::to_string(stamps_s.size()) + " scans have a pose within " + shortNumber(tolerance_s) +
                     " s; no trajectory errors";
  if (!truth.empty() && !stamps_s.empty()) {
    const auto [lo, hi] = std::minmax_element(stamps_s.begin(), stamps_s.end());
    const auto stamp = [](double t) {  // absolute stamps: millisecond digits, no exponent
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.3f", t);
      return std::string(buf);
    };
    text += " (truth from " + stamp(truth.front().stamp_s) + " to " + stamp(truth.back().stamp_s) + " s, scans from " +
            stamp(*lo) + " to " + stamp(*hi) + " s)";
  }
  return text;
}

RunReferences readRunReferences(const std::string& gt_path, const std::string& relations_path) {
  RunReferences refs;
  if (!gt_path.empty()) refs.gt = eval::readTum(gt_path);
  if (!relations_path.empty()) refs.relations = eval::readRelations(relations_path);
  return refs;
}

void evaluateRun(const RunTimeline& run, RunReferences& refs, bool log_reference, double relations_tolerance_s,
                 OdometryReport& report) {
  refs.gt_tolerance_s = std::max(1e-6, 0.25 * run.median_step_s);
  if (log_reference) {
    if (run.log_poses == nullptr || run.log_poses->size() < 2) {
      const std::string warning = "--log-reference: the log has no poses beside its scans";
      report.warnings.push_back(warning);
      report.warning_kinds.add(warning);
    } else {
      refs.log_relations = eval::relationsFrom(*run.log_poses, 0.0, 0.0, 1);
    }
  }
  if (refs.gt) {
    // A ground truth that pairs with fewer than two scans gives no trajectory error: say so
    // with both time spans (another log's truth, relative against absolute stamps, or a log
    // of one scan) rather than fail the run or print errors of nothing.
    std::vector<double> stamps;
    for (const auto& p : report.lidarseg.trajectory) stamps.push_back(p.stamp_s);
    const std::string warning = truthPairingProblem(report.gt_path, *refs.gt, stamps, refs.gt_tolerance_s);
    if (!warning.empty()) {
      report.warnings.push_back(warning);
      report.warning_kinds.add(warning);
      refs.gt.reset();
    }
  }
  evaluate(report.lidarseg, refs, relations_tolerance_s);
  if (report.lidarseg.relations && report.lidarseg.relations->evaluated == 0 && !refs.relations->empty() &&
      !report.lidarseg.trajectory.empty()) {
    // Say so, with both time spans: the usual cause is a log with relative stamps against
    // relations with absolute ones (or the relations of another log).
    double lo = refs.relations->front().t1_s, hi = lo;
    for (const auto& rel : *refs.relations) {
      lo = std::min({lo, rel.t1_s, rel.t2_s});
      hi = std::max({hi, rel.t1_s, rel.t2_s});
    }
    const std::string warning =
        "--relations: none of the " + std::to_string(refs.relations->size()) +
        " relations pairs with this log's scans within --relations-tolerance " + numberText(relations_tolerance_s) +
        " s (relations from " + numberText(lo) + " to " + numberText(hi) + " s, scans from " +
        numberText(report.lidarseg.trajectory.front().stamp_s) + " to " +
        numberText(report.lidarseg.trajectory.back().stamp_s) + " s); no relation statistics";
    report.warnings.push_back(warning);
    report.warning_kinds.add(warning);
  }
  for (MethodReport& baseline : report.baselines) evaluate(baseline, refs, relations_tolerance_s);
}

}  // namespace lidarseg::report
