#pragma once
/// @file
/// lidarseg::report: the run report's text outputs, shared by every tool that
/// runs an OdometryRun (summary.json through nlohmann-json, timing.csv, results.md, TUM).

#include <iosfwd>
#include <string>
#include <vector>

#include "lidarseg/report/RunReport.h"

namespace lidarseg::report {

class OutputSet;
struct RunReferences;

/// A trajectory as a TUM file with a comment header.
std::string tumText(const eval::StampedTrajectory& trajectory, const std::string& header);
/// Per scan: stamps, stage times, statuses, the prior; one column per baseline's time.
std::string timingCsv(const OdometryReport& report);
/// summary.json: counts, per method time summaries, statuses, errors; non-finite numbers
/// are written as null.
std::string summaryJson(const OdometryReport& report);
/// summary.json as the manifest of its output set: the same, and `files`, the names of the
/// set's files in its folder (docs/reliability.md, "Publishing a set").
std::string summaryJson(const OdometryReport& report, const std::vector<std::string>& files);
/// results.md: the paper's Table I columns plus final error and ATE, then the counts.
std::string markdownTable(const OdometryReport& report);

/// The names of every file lidarseg-odometry may write in its output folder (any run): its
/// set's own files and the manifest; what the tool's command line is checked against.
std::vector<std::string> runOutputNames();
/// The names of the files one run may write in its output folder: lidarseg.tum, timing.csv,
/// results.md and summary.json; NAME.tum for each baseline it runs (`baselines`, names of
/// baselineKinds(): icp.tum, icp-s2s.tum); the two
/// PNG plots when it draws; wheel-odometry.tum and log-poses.tum always (whether the log has
/// them is only known once read). What the run's command line is checked against: an input
/// named like a file this run does not write (`--gt out/icp.tum` without `--baseline icp`)
/// is not a collision, and a publish never removes an input.
std::vector<std::string> runOutputNames(const std::vector<std::string>& baselines, bool plots);

/// Adds a run's text outputs to `outputs`, in OUT_DIR (created): lidarseg.tum, icp.tum and
/// icp-s2s.tum for the baselines that ran, wheel-odometry.tum and log-poses.tum (the log's
/// own, from the first scan's pose) when the log has them, timing.csv, summary.json (the
/// set's manifest, written at commit: `report` must outlive the commit) and results.md. Returns the paths in the order a run lists them (the report's first, then
/// the trajectories of the baselines and of the log).
std::vector<std::string> addRunOutputs(OutputSet& outputs, const std::string& out_dir, const OdometryReport& report,
                                       const eval::StampedTrajectory& log_poses,
                                       const eval::StampedTrajectory& wheel_odometry);

/// Adds a run's charts to `outputs`, in OUT_DIR: trajectories.png (the reference, the
/// ground truth or else the log's poses, then the wheel odometry and every method, each
/// from the reference's pose at lidarseg's first scan; titled with `input_name`) and
/// timing.png (lidarseg's and keyframed ICP's time per scan).
/// @throws std::runtime_error when gnuplot is missing or fails (decision 55).
void addRunPlots(OutputSet& outputs, const std::string& out_dir, const OdometryReport& report,
                 const RunReferences& refs, const eval::StampedTrajectory& log_poses,
                 const eval::StampedTrajectory& wheel_odometry, const std::string& input_name);

/// A readable summary for stdout: the Markdown table, the stamp and odometry counts, the
/// lidarseg statuses and the files written; no warnings.
void printRunSummary(const OdometryReport& report, std::ostream& os);

/// The run's warnings for stderr, each line starting "TOOL: warning: ": one line per kind
/// with its count and first occurrence ("449 x, the first: FILE:1130: time gap of 1.6 s;
/// ..."), the skipped scans and an early end of the log.
void printRunWarnings(const OdometryReport& report, const std::string& tool, std::ostream& err);

}  // namespace lidarseg::report
