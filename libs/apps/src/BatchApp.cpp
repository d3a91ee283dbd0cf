#include "lidarseg/apps/BatchApp.h"
#include "lidarseg/report/Progress.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include <sys/wait.h>
#include <unistd.h>

#include "lidarseg/report/BatchResults.h"
#include "lidarseg/report/OutputFiles.h"
#include "lidarseg/pipeline/ParallelJobs.h"
#include "lidarseg/apps/OdometryApp.h"
#include "lidarseg/apps/SimulateApp.h"
#include "lidarseg/mrpt/SimulationConfig.h"
#include "lidarseg/sim/Simulation.h"
#include "lidarseg/eval/Csv.h"
#include "lidarseg/apps/CommandLine.h"

namespace lidarseg::apps {

using report::writeFileAtomically;
using report::OutputSet;

namespace fs = std::filesystem;

std::string BatchApp::runDir(const std::string& out_dir, std::uint64_t seed) {
  return (fs::path(out_dir) / ("run_" + std::to_string(seed))).string();
}

bool BatchApp::finished(const std::string& out_dir, std::uint64_t seed) {
  return fs::exists(fs::path(runDir(out_dir, seed)) / "metrics.csv");
}

namespace {

// The job's simulated run, written as WORK/sim.* without a camera.
SimulateOptions simulateOptions(const BatchJob& job, const fs::path& work) {
  SimulateOptions sim;
  sim.world_path = job.world_path;
  sim.trajectory_path = job.trajectory_path;
  sim.sensor = job.sensor;
  sim.config_path = job.sim_config_path;
  sim.seed = job.seed;
  sim.out_prefix = (work / "sim").string();
  sim.camera_every_scans = 0;
  return sim;
}

// Both methods on WORK/sim.rawlog against its ground truth, the outputs in WORK.
OdometryOptions odometryOptions(const BatchJob& job, const fs::path& work) {
  // The scanner's rotation frequency, for the rolling-shutter correction of lidarseg.
  sim::SimulationParams params;
  params.sensor = sim::sensorProfile(job.sensor);
  if (!job.sim_config_path.empty()) mrpt_adapter::loadSimulationParamsFile(params, job.sim_config_path);

  OdometryOptions o;
  o.input = (work / "sim.rawlog").string();
  o.config_path = job.odometry_config_path;
  o.baseline_icp = job.baseline_icp;
  o.out_dir = work.string();
  o.gt_path = (work / "sim.gt.tum").string();
  o.scanner_rotation_hz = params.rolling_shutter ? params.sensor.frequency_hz : 0.0;
  // The simulator's stamp convention is known: the correction assumes the same one (a
  // last-stamped simulation corrected as first-stamped deskews every sweep about the wrong beam).
  if (params.rolling_shutter) o.scan_stamp = toString(params.scan_stamp);
  o.progress = false;
  return o;
}

// The simulated data (large) removed from WORK; the ground truth stays beside the results.
void removeSimulatedData(const fs::path& work) {
  std::error_code ec;
  for (const char* name : {"sim.rawlog", "sim.odom.tum", "sim.features.csv", "sim.rois.csv"}) {
    fs::remove(work / name, ec);
  }
  fs::remove_all(work / "sim_Images", ec);
}

// What makes the runs of a folder one experiment: the inputs' contents, the sensor and the
// baselines. A folder resumed with another experiment would average two into one table.
std::string experimentOf(const BatchJob& job) {
  std::ostringstream os;
  os << "world " << pipeline::fileDigest(job.world_path) << "\ntrajectory " << pipeline::fileDigest(job.trajectory_path) << "\nsensor "
     << job.sensor << "\nsimulation_config " << pipeline::fileDigest(job.sim_config_path) << "\nodometry_config "
     << pipeline::fileDigest(job.odometry_config_path) << "\nbaseline_icp " << (job.baseline_icp ? 1 : 0) << "\n";
  return os.str();
}

}  // namespace

namespace {

// A job's command line checked before any job starts: an unknown sensor model is a usage
// error (it failed every job, with only "no finished run" at the end).
void checkJob(const BatchJob& job) {
  checkedOption("--sensor-model", [&] { (void)sim::sensorProfile(job.sensor); });
}

}  // namespace

void BatchApp::runOne(const BatchJob& job) {
  checkJob(job);
  // Before any work: the runner's own job inherits its lock; a job started by hand shares
  // the folder with other such jobs and is refused beside a runner or an aggregation.
  OutputSet folder;
  if (job.folder_lock_fd >= 0) {
    folder.claimInheritedFolder(job.out_dir, job.folder_lock_fd);
  } else {
    folder.claimFolderShared(job.out_dir);
  }
  {
    // Jobs sharing the folder record or check its experiment one at a time (a runner's own
    // job too: a descriptor opened by hand on the lock file passes while no one holds it).
    const pipeline::FileLock record((fs::path(job.out_dir) / ".locks" / "experiment.lock").string());
    report::claimExperiment(job.out_dir, experimentOf(job));
  }
  if (finished(job.out_dir, job.seed)) return;
  const pipeline::FileLock lock((fs::path(job.out_dir) / ".locks" / ("run_" + std::to_string(job.seed) + ".lock")).string());
  if (finished(job.out_dir, job.seed)) return;  // finished by the job that held the lock
  const fs::path final_dir = runDir(job.out_dir, job.seed);
  const fs::path work = final_dir.string() + ".partial";
  // A run folder that is not a finished run was never this runner's (a run is renamed into
  // place with its metrics.csv): it is the user's, and is refused, not removed.
  const std::string foreign = report::foreignEntry(final_dir.string(), [](const fs::directory_entry&) { return false; });
  if (!foreign.empty()) {
    throw std::runtime_error("'" + final_dir.string() + "' is not a finished run (no metrics.csv) and holds '" + foreign +
                             "', which lidarseg-batch did not write: move it, or choose another --out");
  }
  std::error_code ec;
  fs::remove_all(work, ec);
  fs::create_directories(work);

  SimulateApp(simulateOptions(job, work)).run();
  const OdometryReport report = OdometryApp(odometryOptions(job, work)).run();
  writeFileAtomically((work / "metrics.csv").string(),
                      report::metricsHeader() + report::metricsLine(job.seed, report::runMetrics(report)));
  if (!job.keep_data) removeSimulatedData(work);
  fs::remove(final_dir, ec);  // an empty folder only (checked above)
  fs::rename(work, final_dir);
}

namespace {

// Where the job for `seed` writes its stderr: OUT/run_<seed>.log (kept when it fails).
std::string jobLogPath(const std::string& out_dir, std::uint64_t seed) {
  return (fs::path(out_dir) / ("run_" + std::to_string(seed) + ".log")).string();
}

// The job's command line: `self_exe one` with the run's settings, `seed` and the runner's
// folder lock (base.folder_lock_fd), which the job inherits.
std::vector<std::string> jobCommand(const BatchJob& base, std::uint64_t seed,
                                    const std::string& self_exe) {
  std::vector<std::string> args = {self_exe, "one", "--world", base.world_path, "--trajectory",
                                   base.trajectory_path, "--sensor-model", base.sensor, "--seed",
                                   std::to_string(seed), "--out", base.out_dir, "--folder-lock-fd",
                                   std::to_string(base.folder_lock_fd)};
  if (!base.sim_config_path.empty()) args.insert(args.end(), {"--sim-config", base.sim_config_path});
  if (!base.odometry_config_path.empty()) args.insert(args.end(), {"--config", base.odometry_config_path});
  if (!base.baseline_icp) args.push_back("--no-icp");
  if (base.keep_data) args.push_back("--keep-data");
  return args;
}

}  // namespace

namespace {

// The seeds whose run has not finished, said on stderr with `progress`.
std::vector<std::uint64_t> unfinishedSeeds(const BatchJob& base, const std::vector<std::uint64_t>& seeds,
                                           std::size_t jobs, bool progress) {
  std::vector<std::uint64_t> todo;
  for (auto s : seeds) {
    if (!BatchApp::finished(base.out_dir, s)) todo.push_back(s);
  }
  if (progress) {
    std::cerr << "[lidarseg-batch] " << seeds.size() - todo.size() << " run(s) already finished, " << todo.size()
              << " to do, " << jobs << " at a time\n";
  }
  return todo;
}

// One child process per seed (`self_exe one ...`), `jobs` at a time; a run that ends well
// loses its log, the others are returned as "seed N: why".
std::vector<std::string> runSeeds(const BatchJob& base, const std::vector<std::uint64_t>& todo, std::size_t jobs,
                                  const std::string& self_exe, bool progress) {
  std::vector<pipeline::ChildJob> children;
  for (const std::uint64_t seed : todo) {
    children.push_back({jobCommand(base, seed, self_exe), jobLogPath(base.out_dir, seed), {base.folder_lock_fd}});
  }
  std::vector<std::string> failed;
  std::size_t done = 0;
  const auto start = std::chrono::steady_clock::now();
  pipeline::runChildJobs(children, jobs, [&](std::size_t k, int status) {
    const std::uint64_t seed = todo[k];
    ++done;
    const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && BatchApp::finished(base.out_dir, seed);
    if (ok) {
      std::error_code ec;
      fs::remove(children[k].log_path, ec);
    } else {
      failed.push_back("seed " + std::to_string(seed) + ": " + pipeline::exitDescription(status, children[k].log_path));
    }
    // A line per finished run (the runs' own progress is not shown): readable in a log file,
    // where report::Progress, redrawn in place on a terminal, is silent; the same estimate.
    if (progress) {
      const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::cerr << "[lidarseg-batch] " << done << "/" << todo.size() << " done (seed " << seed
                << (ok ? " ok" : " FAILED") << "), " << std::fixed << std::setprecision(0) << elapsed_s << " s";
      const double left_s = report::secondsLeft(elapsed_s, done, todo.size(), -1.0);
      if (left_s >= 0) std::cerr << ", ~" << left_s << " s left";
      std::cerr << std::defaultfloat << "\n";
    }
  });
  return failed;
}

}  // namespace

namespace {

// runMany() with the folder's lock taken in `claimed`, which the caller may keep holding.
std::vector<std::string> runManyClaimed(const BatchJob& given, const std::vector<std::uint64_t>& seeds, std::size_t jobs,
                                        const std::string& self_exe, bool progress, OutputSet& claimed) {
  // Before any work: a second runner, an aggregation or a job started by hand on this folder
  // is refused at once; the runner's own jobs inherit its lock (and lock their seeds).
  checkJob(given);
  claimed.claimOutputs({}, {{given.out_dir, "--out", {"table1.md", "aggregate.csv", "final_errors.png", "experiment.txt"}}},
                       {given.world_path, given.trajectory_path, given.sim_config_path, given.odometry_config_path});
  BatchJob base = given;
  base.folder_lock_fd = claimed.folderLockDescriptor(base.out_dir);
  report::claimExperiment(base.out_dir, experimentOf(base));
  // Progress only on a terminal (as every tool's): a line per finished run, with the time
  // so far and the time left at the rate of the runs done.
  progress = progress && ::isatty(STDERR_FILENO) == 1;
  const std::vector<std::uint64_t> todo = unfinishedSeeds(base, seeds, jobs, progress);
  fs::create_directories(base.out_dir);
  const std::vector<std::string> failed = runSeeds(base, todo, jobs, self_exe, progress);
  claimed.commit();  // nothing of its own to publish; the folder is kept
  return failed;
}

}  // namespace

std::vector<std::string> BatchApp::runMany(const BatchJob& base, const std::vector<std::uint64_t>& seeds,
                                           std::size_t jobs, const std::string& self_exe, bool progress) {
  OutputSet claimed;
  return runManyClaimed(base, seeds, jobs, self_exe, progress, claimed);
}

BatchOutcome BatchApp::runAndAggregate(const BatchJob& base, const std::vector<std::uint64_t>& seeds,
                                       std::size_t jobs, const std::string& self_exe, bool progress,
                                       const std::string& title, const std::function<void()>& between) {
  OutputSet claimed;  // held until the table is written: aggregate() shares this process's lock
  BatchOutcome outcome;
  outcome.failed = runManyClaimed(base, seeds, jobs, self_exe, progress, claimed);
  if (between) between();
  outcome.summary = aggregate(base.out_dir, title);
  return outcome;
}

BatchSummary BatchApp::aggregate(const std::string& out_dir, const std::string& title) {
  OutputSet outputs;
  outputs.claimFolder(out_dir);  // before reading: no runner may be adding runs meanwhile
  const report::FinishedRuns runs = report::readFinishedRuns(out_dir);
  const report::MetricRows& rows = runs.rows;
  const report::MetricStats stats = report::metricStats(rows);
  BatchSummary summary;
  summary.runs = rows.size();
  summary.seeds = runs.seeds;
  summary.warnings = runs.warnings;
  for (const std::string& w : runs.warnings) std::cerr << "lidarseg-batch: warning: " << w << "\n";
  summary.table_markdown = report::table1Markdown(title, summary.seeds, stats);
  const fs::path out(out_dir);
  outputs.add((out / "aggregate.csv").string(), report::aggregateCsv(runs));
  outputs.add((out / "table1.md").string(), summary.table_markdown);
  // Without gnuplot the table is written without its picture, with a warning (decision 55).
  try {
    outputs.add((out / "final_errors.png").string(),
                report::finalErrorsPng(rows, stats.at("icp_final_error_m").count > 0, title));
  } catch (const std::runtime_error& e) {
    std::cerr << "lidarseg-batch: warning: no picture final_errors.png: " << e.what() << "\n";
    std::error_code ec;
    fs::remove(out / "final_errors.png", ec);  // not a picture of earlier runs beside the new table
  }
  outputs.commit();
  return summary;
}

}  // namespace lidarseg::apps
