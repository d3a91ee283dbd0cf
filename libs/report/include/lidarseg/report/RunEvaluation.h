#pragma once
/// @file RunEvaluation.h
/// A run's methods evaluated against what the user gave or the log holds: a ground truth
/// (Table I, final error, ATE), Freiburg relations, and the log's own poses as per-scan
/// relations (lidarseg-odometry --gt, --relations, --log-reference).

#include <optional>
#include <string>
#include <vector>

#include "lidarseg/eval/Relations.h"
#include "lidarseg/eval/StampedTrajectory.h"
#include "lidarseg/report/RunReport.h"

namespace lidarseg::report {

/// Ground truth, relations and the log's own poses, for the evaluation.
struct RunReferences {
  std::optional<eval::StampedTrajectory> gt;  ///< robot poses (TUM)
  std::optional<std::vector<eval::Relation>> relations;
  std::optional<std::vector<eval::Relation>> log_relations;
  /// Largest stamp difference for a pose to meet the ground truth's (s); evaluateRun()
  /// sets it to a quarter of the log's median scan period.
  double gt_tolerance_s = 0.025;
};

/// PREFIX.gt.tum beside a log PREFIX.rawlog, .clf or .log (optionally .gz), and beside the
/// simulator's CARMEN log PREFIX.carmen.log, as the simulator writes it; empty when there is
/// no such file. lidarseg-odometry and lidarseg-inspect look for their ground truth so.
std::string groundTruthBeside(const std::string& log_path);

/// Why the ground truth `truth` (read from `truth_path`) cannot measure scans stamped
/// `stamps_s`: fewer than two of them have a pose within `tolerance_s` (another log's truth,
/// relative stamps against absolute ones, a log of one scan). The text names the file, the
/// count and both time spans; empty when at least two scans pair. lidarseg-odometry and
/// lidarseg-inspect warn with it and leave the truth out.
std::string truthPairingProblem(const std::string& truth_path, const eval::StampedTrajectory& truth,
                                const std::vector<double>& stamps_s, double tolerance_s);

/// The ground truth (TUM) and relations files read before the run, so that a bad file fails
/// early; an empty path reads nothing.
/// @throws std::runtime_error naming the file and line.
RunReferences readRunReferences(const std::string& gt_path, const std::string& relations_path);

/// What of the run the evaluation needs besides its report.
struct RunTimeline {
  /// The log's own robot poses beside its scans (CARMEN laser lines), for `log_reference`.
  const eval::StampedTrajectory* log_poses = nullptr;
  /// The run's median scan period (s): a quarter of it is the ground truth's tolerance.
  double median_step_s = 0.0;
};

/// Every method of `report` against the references: errors against the ground truth,
/// the relations within `relations_tolerance_s`, and with `log_reference` the relations of
/// the log's own poses (a warning when the log has fewer than two).
void evaluateRun(const RunTimeline& run, RunReferences& refs, bool log_reference, double relations_tolerance_s,
                 OdometryReport& report);

}  // namespace lidarseg::report
