#pragma once
/// @file BatchApp.h
/// The logic of `lidarseg-batch`: the paper's experiment (§IV.B) — many simulated runs of
/// one trajectory with different noise seeds, each matched by lidarseg and MRPT ICP —
/// as independent, resumable jobs, and the aggregation of their results.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "lidarseg/report/BatchResults.h"

namespace lidarseg::apps {

/// What one run is made of (a job).
struct BatchJob {
  std::string world_path;         ///< config/worlds/*.world
  std::string trajectory_path;    ///< config/worlds/*.traj
  std::string sensor = "lms100";  ///< sensor profile (lidarseg-simulate's --sensor)
  /// Optional INI/YAML with a [simulation] section (lidarseg-simulate's).
  std::string sim_config_path;
  /// Optional INI/YAML with [segmentation] [matcher] [odometry] [icp] (lidarseg-odometry's).
  std::string odometry_config_path;
  std::uint64_t seed = 1;  ///< noise seed of the simulated run
  /// Results folder: the run goes to OUT/run_<seed>/ (written as run_<seed>.partial/ and
  /// renamed when complete, so a killed job leaves no result that looks finished).
  std::string out_dir;
  bool baseline_icp = true;  ///< also run MRPT ICP (keyframed like lidarseg)
  /// Keep the simulated rawlog and images (large); default: only the results.
  bool keep_data = false;
  /// A job of `lidarseg-batch run`: the runner's lock on `out_dir`, inherited as this
  /// descriptor (`--folder-lock-fd`, set by the runner). -1 (a job started by hand): the job
  /// shares the folder's lock with other such jobs, and is refused while a runner or an
  /// aggregation holds it.
  int folder_lock_fd = -1;
};

/// Aggregated figures over the runs found in a results folder.
struct BatchSummary {
  std::size_t runs = 0;              ///< finished runs found
  std::vector<std::uint64_t> seeds;  ///< their seeds, ascending
  std::vector<std::string> failed;   ///< "seed N: message" of runs that failed
  std::vector<std::string> warnings; ///< run folders left out (no metrics.csv), each named
  /// OUT/table1.md: paper Table I (times in ms, errors in mm, mrad and m).
  std::string table_markdown;
};

/// What `lidarseg-batch run` gives: the runs that failed and the aggregation of the finished.
struct BatchOutcome {
  std::vector<std::string> failed;  ///< "seed N: why" of the runs that failed
  BatchSummary summary;             ///< over every finished run of the folder
};

/// Runs and aggregates the batch; every member is static (the state is the results folder).
class BatchApp {
 public:
  /// The folder of one seed's finished run.
  static std::string runDir(const std::string& out_dir, std::uint64_t seed);
  /// Whether that run has finished (its folder holds metrics.csv).
  static bool finished(const std::string& out_dir, std::uint64_t seed);

  /// Runs one job in this process: simulate, run both methods, write OUT/run_<seed>/
  /// (summary.json, metrics.csv, trajectories, timing). Skips a finished run. First takes
  /// part in the folder's lock (see BatchJob::folder_lock_fd: shared with other `one` jobs,
  /// never beside a runner or an aggregation that is not its own) and checks that the folder
  /// holds this experiment's runs, then holds its seed's lock.
  /// @throws std::runtime_error on failure, when another writer holds the folder, or when
  /// the folder holds another experiment (nothing is left that looks finished).
  static void runOne(const BatchJob& job);

  /// Runs the jobs for `seeds` that have not finished, `jobs` at a time, each in its own
  /// process (`self_exe one ...`), so that a failing or crashing run is reported while the
  /// others finish. Returns the seeds that failed with their messages. `progress`: a line
  /// on stderr per finished run with the time so far and the time left, shown only when
  /// stderr is a terminal.
  static std::vector<std::string> runMany(const BatchJob& base, const std::vector<std::uint64_t>& seeds,
                                          std::size_t jobs, const std::string& self_exe, bool progress);

  /// runMany(), then aggregate() with `title`, the folder's lock held across both: no other
  /// writer (another `lidarseg-batch run`, `aggregate` or `one`) can add or change a run
  /// between the runs and their table; the runner's own jobs inherit its lock. `between`, when given, is called at that moment, the
  /// lock still held (a test's view of it).
  /// @throws std::runtime_error as runMany() and aggregate() do.
  static BatchOutcome runAndAggregate(const BatchJob& base, const std::vector<std::uint64_t>& seeds, std::size_t jobs,
                                      const std::string& self_exe, bool progress, const std::string& title,
                                      const std::function<void()>& between = {});

  /// Reads every OUT/run_*/metrics.csv, writes OUT/table1.md, OUT/aggregate.csv and
  /// OUT/final_errors.png, and returns the summary.
  /// @throws std::runtime_error when no finished run is found or a metrics file is bad.
  static BatchSummary aggregate(const std::string& out_dir, const std::string& title);
};

/// Parses "1-50", "3", "1,4,9-12" (lidarseg::pipeline's).
using report::parseSeeds;

}  // namespace lidarseg::apps
