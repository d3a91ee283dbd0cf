#pragma once
/// @file BatchResults.h
/// lidarseg-batch's results: one run's figures (metrics.csv in OUT/run_<seed>/), every
/// finished run read back, and their aggregation into the paper's Table I (§IV.B); the
/// seeds and the experiment a results folder holds.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "lidarseg/core/Statistics.h"
#include "lidarseg/report/RunReport.h"

namespace lidarseg::report {

/// The per-run figures aggregated over runs, in metrics.csv's column order (after "seed"):
/// frames, then per method (lidarseg_, icp_) final error and ATE RMSE (m), mean, spread,
/// median and p99 time per scan (ms), Table I's edx, edy (m) and edθ (rad) with their
/// spreads; then the median speed-up and the path length (m).
const std::vector<std::string>& batchMetricNames();

/// One row per run read back from metrics.csv: the seed, then batchMetricNames() (NaN: not
/// measured).
using MetricRows = std::vector<std::vector<double>>;
/// Each metric summarised over the runs that measured it, by name.
using MetricStats = std::map<std::string, Summary>;

/// The column of a metric in a MetricRows row (column 0 is the seed).
std::size_t metricColumn(const std::string& name);

/// One run's figures in batchMetricNames() order; NaN for what was not measured (no ground
/// truth, no ICP).
std::vector<double> runMetrics(const OdometryReport& report);

/// The header line of metrics.csv and aggregate.csv: "seed", then batchMetricNames().
std::string metricsHeader();

/// A line of metrics.csv and aggregate.csv: the seed, then the figures (10 significant digits).
std::string metricsLine(std::uint64_t seed, const std::vector<double>& values);

/// The largest figure a metrics.csv may hold (m, ms, rad, a ratio), in magnitude: beyond it
/// a value is no run's (a final error of 1e308 m entered the mean).
constexpr double kMaxBatchMetric = 1e6;
/// The largest frame count a metrics.csv may hold.
constexpr double kMaxBatchFrames = 1e9;
/// The finished runs of a results folder.
struct FinishedRuns {
  std::vector<std::uint64_t> seeds;   ///< ascending, exact (not through a double)
  MetricRows rows;                    ///< one per seed; column 0 the seed as a double (plots)
  std::vector<std::string> warnings;  ///< run folders left out, each named with why
};
/// Every finished run's row (OUT/run_<seed>/metrics.csv, not run_<seed>.partial/), in seed
/// order. A folder run_* without metrics.csv, or not named run_SEED, is left out with a
/// warning. @throws std::runtime_error when OUT is no folder, holds no finished run, or a
/// metrics file is bad, naming FILE:LINE:COLUMN: a seed other than its folder's, a figure
/// not finite, beyond kMaxBatchMetric (kMaxBatchFrames) or negative (the signed means
/// edx, edy, edθ may be negative).
FinishedRuns readFinishedRuns(const std::string& out_dir);

/// Mean (and spread) of each metric over the runs; NaN values are left out.
MetricStats metricStats(const MetricRows& rows);

/// table1.md: the paper's Table I, one row per method that ran (times in ms, errors in mm,
/// mrad and m), then the median times per scan.
std::string table1Markdown(const std::string& title, const std::vector<std::uint64_t>& seeds,
                           const MetricStats& stats);

/// final_errors.png: each run's final position error against its seed, lidarseg's and,
/// `with_icp`, keyframed MRPT ICP's, as markers (gnuplot).
/// @throws std::runtime_error when gnuplot is missing or fails.
std::string finalErrorsPng(const MetricRows& rows, bool with_icp, const std::string& title);

/// aggregate.csv: every run's metrics.csv line under one header.
std::string aggregateCsv(const FinishedRuns& runs);

/// Parses seeds as "1-50", "3", "1,4,9-12" (sorted, without repeats; at most 100000).
/// @throws std::invalid_argument naming the bad part.
std::vector<std::uint64_t> parseSeeds(const std::string& text);

/// Records an experiment (`record`: what makes its runs one experiment, e.g. digests of its
/// inputs) in OUT/experiment.txt when OUT holds none; refuses a folder that holds another
/// one, whose runs would be averaged with these into one table.
/// @throws std::runtime_error naming the folder.
void claimExperiment(const std::string& out_dir, const std::string& record);

}  // namespace lidarseg::report
