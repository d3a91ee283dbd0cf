#include "lidarseg/apps/BatchApp.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "lidarseg/pipeline/OutputFiles.h"
#include "Plots.h"
#include "lidarseg/apps/OdometryApp.h"
#include "lidarseg/apps/SimulateApp.h"
#include "lidarseg/core/Statistics.h"
#include "lidarseg/mrpt/SimulationConfig.h"
#include "lidarseg/sim/Simulation.h"
#include "lidarseg/eval/Csv.h"

namespace lidarseg::apps {

using pipeline::writeFileAtomically;
using pipeline::OutputSet;

namespace fs = std::filesystem;

namespace {

// The per-run figures aggregated over runs, in metrics.csv's column order.
const std::vector<std::string>& metricNames() {
  static const std::vector<std::string> names = {
      "frames",
      "lidarseg_final_error_m", "lidarseg_ate_rmse_m", "lidarseg_t_ms", "lidarseg_sigma_t_ms",
      "lidarseg_median_ms", "lidarseg_p99_ms", "lidarseg_edx_m", "lidarseg_sigma_edx_m", "lidarseg_edy_m",
      "lidarseg_sigma_edy_m", "lidarseg_edtheta_rad", "lidarseg_sigma_edtheta_rad",
      "icp_final_error_m", "icp_ate_rmse_m", "icp_t_ms", "icp_sigma_t_ms", "icp_median_ms", "icp_p99_ms",
      "icp_edx_m", "icp_sigma_edx_m", "icp_edy_m", "icp_sigma_edy_m", "icp_edtheta_rad",
      "icp_sigma_edtheta_rad", "speedup_median", "path_length_m"};
  return names;
}

// One row per run read back from metrics.csv: the seed, then metricNames() (NaN: not measured).
using MetricRows = std::vector<std::vector<double>>;
// Each metric summarised over the runs that measured it, by name.
using MetricStats = std::map<std::string, Summary>;

// The column of a metric in a MetricRows row (column 0 is the seed).
std::size_t rowColumn(const std::string& name) {
  const auto& names = metricNames();
  return 1 + static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
}

// One run's figures in metricNames() order; NaN for what was not measured.
std::vector<double> metricsOf(const OdometryReport& r) {
  const auto method = [](const std::optional<MethodReport>& m, std::vector<double>& out) {
    if (!m || !m->errors) {
      out.insert(out.end(), 12, std::nan(""));
      return;
    }
    const auto& e = *m->errors;
    const auto& t = m->time_summary_us;
    out.insert(out.end(), {e.final_position_error_m, e.ate_rmse_m, t.mean * 1e-3, t.stddev * 1e-3, t.median * 1e-3,
                           t.p99 * 1e-3, e.motion.dx_m.mean, e.motion.dx_m.stddev, e.motion.dy_m.mean,
                           e.motion.dy_m.stddev, e.motion.dtheta_rad.mean, e.motion.dtheta_rad.stddev});
  };
  std::vector<double> out = {static_cast<double>(r.frames)};
  method(std::optional<MethodReport>(r.lidarseg), out);
  method(r.icp, out);
  out.push_back(r.speedup_median);
  out.push_back(r.lidarseg.errors ? r.lidarseg.errors->path_length_m : std::nan(""));
  return out;
}

// The header line of metrics.csv and aggregate.csv: "seed", then metricNames().
std::string metricsHeader() {
  std::string header = "seed";
  for (const auto& n : metricNames()) header += ',' + n;
  return header + '\n';
}

// A line of metrics.csv and aggregate.csv: the seed, then the figures (10 significant digits).
std::string metricsLine(std::uint64_t seed, const std::vector<double>& values) {
  std::ostringstream line;
  line << seed << std::setprecision(10);
  for (double v : values) line << ',' << v;
  line << '\n';
  return line.str();
}

// The metrics.csv of every finished run in OUT: run_<seed>/, not run_<seed>.partial/.
std::vector<fs::path> finishedMetricsFiles(const std::string& out_dir) {
  if (!fs::is_directory(out_dir)) throw std::runtime_error("'" + out_dir + "' is not a folder");
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(out_dir)) {
    const auto name = entry.path().filename().string();
    if (entry.is_directory() && name.rfind("run_", 0) == 0 && name.find('.') == std::string::npos &&
        fs::exists(entry.path() / "metrics.csv")) {
      files.push_back(entry.path() / "metrics.csv");
    }
  }
  return files;
}

// The data line of one metrics.csv: the seed, then one value per metric.
std::vector<double> readMetricsRow(const fs::path& f) {
  std::ifstream in(f);
  std::string header, line;
  std::getline(in, header);
  if (!std::getline(in, line)) throw std::runtime_error(f.string() + ":2: missing the data line");
  std::vector<double> row;
  for (const std::string& cell : eval::splitCsvLine(line)) {
    char* end = nullptr;
    const double v = std::strtod(cell.c_str(), &end);
    if (end == cell.c_str()) throw std::runtime_error(f.string() + ":2: '" + cell + "' is not a number");
    row.push_back(v);
  }
  const std::size_t columns = metricNames().size() + 1;
  if (row.size() != columns) {
    throw std::runtime_error(f.string() + ":2: " + std::to_string(row.size()) + " values, expected " +
                             std::to_string(columns));
  }
  return row;
}

// Every finished run's row, in seed order.
MetricRows readFinishedRuns(const std::string& out_dir) {
  MetricRows rows;
  for (const auto& f : finishedMetricsFiles(out_dir)) rows.push_back(readMetricsRow(f));
  if (rows.empty()) throw std::runtime_error("no finished run (run_*/metrics.csv) in '" + out_dir + "'");
  std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a[0] < b[0]; });
  return rows;
}

// Mean (and spread) of each metric over the runs; NaN values are left out.
MetricStats metricStats(const MetricRows& rows) {
  MetricStats stats;
  for (std::size_t c = 0; c < metricNames().size(); ++c) {
    std::vector<double> v;
    for (const auto& r : rows) {
      if (std::isfinite(r[c + 1])) v.push_back(r[c + 1]);
    }
    stats[metricNames()[c]] = summarize(v);
  }
  return stats;
}

// table1.md: the paper's Table I, one row per method that ran, then the median times per scan.
std::string table1Markdown(const std::string& title, const std::vector<std::uint64_t>& seeds,
                           const MetricStats& stats) {
  std::ostringstream md;
  md << std::fixed;
  md << "## " << title << "\n\n" << seeds.size() << " runs (seeds " << seeds.front() << "–" << seeds.back()
     << "), mean over runs of each run's figures (paper Table I).\n\n";
  md << "| method | t (ms) | σt (ms) | edx (mm) | σedx (mm) | edy (mm) | σedy (mm) | edθ (mrad) | σedθ (mrad) | final error (m): mean | median | max | ATE RMSE (m) |\n";
  md << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const std::string m : {"lidarseg", "icp"}) {
    const auto g = [&](const std::string& k) { return stats.at(m + "_" + k); };
    if (g("final_error_m").count == 0) continue;
    md << "| " << (m == "icp" ? "MRPT ICP" : m) << std::setprecision(4) << " | " << g("t_ms").mean << " | "
       << g("sigma_t_ms").mean << std::setprecision(2) << " | " << g("edx_m").mean * 1e3 << " | "
       << g("sigma_edx_m").mean * 1e3 << " | " << g("edy_m").mean * 1e3 << " | " << g("sigma_edy_m").mean * 1e3
       << " | " << g("edtheta_rad").mean * 1e3 << " | " << g("sigma_edtheta_rad").mean * 1e3
       << std::setprecision(3) << " | " << g("final_error_m").mean << " | " << g("final_error_m").median << " | "
       << g("final_error_m").max << " | " << g("ate_rmse_m").mean << " |\n";
  }
  if (stats.at("speedup_median").count > 0) {
    md << "\nMedian time per scan: lidarseg " << std::setprecision(4) << stats.at("lidarseg_median_ms").median * 1e3
       << " µs, MRPT ICP " << stats.at("icp_median_ms").median * 1e3 << " µs; speed-up (median over runs of each "
       << "run's median ratio) " << std::setprecision(1) << stats.at("speedup_median").median << "x. Path length "
       << std::setprecision(1) << stats.at("path_length_m").mean << " m.\n";
  }
  return md.str();
}

// aggregate.csv: every run's metrics.csv line under one header.
std::string aggregateCsv(const MetricRows& rows) {
  std::string csv = metricsHeader();
  for (const auto& r : rows) {
    csv += metricsLine(static_cast<std::uint64_t>(r[0]), {r.begin() + 1, r.end()});
  }
  return csv;
}

// final_errors.png: each method's final position error against the seed (MRPT ICP's when it ran).
std::string finalErrorsPng(const MetricRows& rows, bool with_icp, const std::string& title) {
  const std::size_t lidarseg = rowColumn("lidarseg_final_error_m");
  const std::size_t icp = rowColumn("icp_final_error_m");
  PlotSeries a = makeSeries("lidarseg", pipeline::kLidarsegColour, PlotStyle::kMarkers);
  PlotSeries b = makeSeries("MRPT ICP keyframed", pipeline::kIcpColour, PlotStyle::kMarkers);
  for (const auto& r : rows) {
    a.x.push_back(r[0]);
    a.y.push_back(r[lidarseg]);
    b.x.push_back(r[0]);
    b.y.push_back(r[icp]);
  }
  std::vector<PlotSeries> series = {a};
  if (with_icp) series.push_back(b);
  return plotXYPng(series, "Final position error per run: " + title, "seed", "final error (m)", true);
}

}  // namespace

std::vector<std::uint64_t> parseSeeds(const std::string& text) {
  std::vector<std::uint64_t> seeds;
  for (const std::string& part : eval::splitCsvLine(text)) {
    const auto dash = part.find('-');
    try {
      std::size_t used = 0;
      if (dash == std::string::npos) {
        const auto v = std::stoull(part, &used);
        if (used != part.size()) throw std::invalid_argument(part);
        seeds.push_back(v);
      } else {
        const std::string a = part.substr(0, dash), b = part.substr(dash + 1);
        std::size_t ua = 0, ub = 0;
        const auto lo = std::stoull(a, &ua), hi = std::stoull(b, &ub);
        if (ua != a.size() || ub != b.size() || hi < lo || hi - lo > 100000) throw std::invalid_argument(part);
        for (std::uint64_t k = 0; k <= hi - lo; ++k) seeds.push_back(lo + k);  // no wrap at the top of uint64
      }
    } catch (const std::exception&) {
      throw std::invalid_argument("seeds: '" + part + "' is not a seed or a range like 1-50");
    }
  }
  if (seeds.empty()) throw std::invalid_argument("seeds: none given");
  if (seeds.size() > 100000) throw std::invalid_argument("seeds: more than 100000 runs asked for");
  std::sort(seeds.begin(), seeds.end());
  seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
  return seeds;
}

std::string BatchApp::runDir(const std::string& out_dir, std::uint64_t seed) {
  return (fs::path(out_dir) / ("run_" + std::to_string(seed))).string();
}

bool BatchApp::finished(const std::string& out_dir, std::uint64_t seed) {
  return fs::exists(fs::path(runDir(out_dir, seed)) / "metrics.csv");
}

namespace {

// An exclusive lock on one seed's run, held while it is worked on: a runner started again
// while a job of an earlier (killed) runner still works on the same seed waits for it
// instead of writing into the same folder, then finds the run finished.
class SeedLock {
 public:
  explicit SeedLock(const fs::path& path) {
    fs::create_directories(path.parent_path());
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw std::runtime_error("cannot create the lock file '" + path.string() + "'");
    while (::flock(fd_, LOCK_EX) != 0) {
      if (errno != EINTR) throw std::runtime_error("cannot lock '" + path.string() + "'");
    }
  }
  ~SeedLock() { ::close(fd_); }  // releases the lock
  SeedLock(const SeedLock&) = delete;
  SeedLock& operator=(const SeedLock&) = delete;

 private:
  int fd_ = -1;
};

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

}  // namespace

void BatchApp::runOne(const BatchJob& job) {
  if (finished(job.out_dir, job.seed)) return;
  const SeedLock lock(fs::path(job.out_dir) / ".locks" / ("run_" + std::to_string(job.seed) + ".lock"));
  if (finished(job.out_dir, job.seed)) return;  // finished by the job that held the lock
  const fs::path final_dir = runDir(job.out_dir, job.seed);
  const fs::path work = final_dir.string() + ".partial";
  std::error_code ec;
  fs::remove_all(work, ec);
  fs::create_directories(work);

  SimulateApp(simulateOptions(job, work)).run();
  const OdometryReport report = OdometryApp(odometryOptions(job, work)).run();
  writeFileAtomically((work / "metrics.csv").string(),
                      metricsHeader() + metricsLine(job.seed, metricsOf(report)));
  if (!job.keep_data) removeSimulatedData(work);
  fs::remove_all(final_dir, ec);
  fs::rename(work, final_dir);
}

namespace {

// Where the job for `seed` writes its stderr: OUT/run_<seed>.log (kept when it fails).
std::string jobLogPath(const std::string& out_dir, std::uint64_t seed) {
  return (fs::path(out_dir) / ("run_" + std::to_string(seed) + ".log")).string();
}

// The job's command line: `self_exe one` with the run's settings and `seed`.
std::vector<std::string> jobCommand(const BatchJob& base, std::uint64_t seed,
                                    const std::string& self_exe) {
  std::vector<std::string> args = {self_exe, "one", "--world", base.world_path, "--trajectory",
                                   base.trajectory_path, "--sensor", base.sensor, "--seed",
                                   std::to_string(seed), "--out", base.out_dir};
  if (!base.sim_config_path.empty()) args.insert(args.end(), {"--sim-config", base.sim_config_path});
  if (!base.odometry_config_path.empty()) args.insert(args.end(), {"--config", base.odometry_config_path});
  if (!base.baseline_icp) args.push_back("--no-icp");
  if (base.keep_data) args.push_back("--keep-data");
  return args;
}

// Starts `args` (args[0] is the program) in a child process with its stderr in `log`.
pid_t startJob(std::vector<std::string> args, const std::string& log) {
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("cannot start a job (fork failed)");
  if (pid == 0) {
    // A job dies with its runner (killed or not), so that no orphan keeps writing
    // while a new runner resumes; the seed lock covers the instant in between.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    FILE* f = std::freopen(log.c_str(), "w", stderr);
    (void)f;
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(args[0].c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

// "seed N: exit code C (last line of its log)" or "seed N: killed by signal S (...)".
std::string failureOf(std::uint64_t seed, int status, const std::string& log) {
  const std::string why = WIFSIGNALED(status) ? "killed by signal " + std::to_string(WTERMSIG(status))
                                              : "exit code " + std::to_string(WEXITSTATUS(status));
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  return "seed " + std::to_string(seed) + ": " + why + (last.empty() ? "" : " (" + last + ")");
}

// FNV-1a (64 bit) of a file's bytes, as hex: a stable digest for the experiment record.
std::string digestOf(const std::string& path) {
  if (path.empty()) return "-";
  std::ifstream in(path, std::ios::binary);
  if (!in) return "unreadable";
  std::uint64_t h = 14695981039346656037ull;
  char c = 0;
  while (in.get(c)) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  std::ostringstream os;
  os << std::hex << h;
  return os.str();
}

// What makes the runs of a folder one experiment: the inputs' contents, the sensor and the
// baselines. A folder resumed with another experiment would average two into one table.
std::string experimentOf(const BatchJob& job) {
  std::ostringstream os;
  os << "world " << digestOf(job.world_path) << "\ntrajectory " << digestOf(job.trajectory_path) << "\nsensor "
     << job.sensor << "\nsimulation_config " << digestOf(job.sim_config_path) << "\nodometry_config "
     << digestOf(job.odometry_config_path) << "\nbaseline_icp " << (job.baseline_icp ? 1 : 0) << "\n";
  return os.str();
}

// Records the experiment in a new folder; refuses a folder that holds another one.
void claimExperiment(const BatchJob& job) {
  const std::string path = (fs::path(job.out_dir) / "experiment.txt").string();
  const std::string mine = experimentOf(job);
  std::ifstream in(path);
  if (in) {
    const std::string theirs((std::istreambuf_iterator<char>(in)), {});
    if (theirs != mine) {
      throw std::runtime_error("'" + job.out_dir + "' holds the runs of another experiment (" + path +
                               " differs: world, trajectory, sensor, configurations or baselines); choose another --out");
    }
    return;
  }
  fs::create_directories(job.out_dir);
  writeFileAtomically(path, mine);
}

}  // namespace

std::vector<std::string> BatchApp::runMany(const BatchJob& base, const std::vector<std::uint64_t>& seeds,
                                           std::size_t jobs, const std::string& self_exe, bool progress) {
  // Before any work: a second runner on this folder is refused at once (the jobs lock their
  // own run folders and seeds).
  OutputSet claimed;
  claimed.claimOutputs({}, {{base.out_dir, "--out"}},
                       {base.world_path, base.trajectory_path, base.sim_config_path, base.odometry_config_path});
  claimExperiment(base);
  std::vector<std::uint64_t> todo;
  for (auto s : seeds) {
    if (!finished(base.out_dir, s)) todo.push_back(s);
  }
  // Progress only on a terminal (as every tool's): a line per finished run, with the time
  // so far and the time left at the rate of the runs done.
  progress = progress && ::isatty(STDERR_FILENO) == 1;
  const auto start = std::chrono::steady_clock::now();
  if (progress) {
    std::cerr << "[lidarseg-batch] " << seeds.size() - todo.size() << " run(s) already finished, " << todo.size()
              << " to do, " << jobs << " at a time\n";
  }
  fs::create_directories(base.out_dir);
  std::vector<std::string> failed;
  std::map<pid_t, std::uint64_t> running;
  std::size_t next = 0, done = 0;
  while (next < todo.size() || !running.empty()) {
    while (next < todo.size() && running.size() < std::max<std::size_t>(jobs, 1)) {
      const std::uint64_t seed = todo[next++];
      const pid_t pid = startJob(jobCommand(base, seed, self_exe), jobLogPath(base.out_dir, seed));
      running[pid] = seed;
    }
    int status = 0;
    const pid_t pid = wait(&status);
    if (pid < 0) break;
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const std::uint64_t seed = it->second;
    running.erase(it);
    ++done;
    const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && finished(base.out_dir, seed);
    if (ok) {
      std::error_code ec;
      fs::remove(jobLogPath(base.out_dir, seed), ec);
    } else {
      failed.push_back(failureOf(seed, status, jobLogPath(base.out_dir, seed)));
    }
    if (progress) {
      const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::cerr << "[lidarseg-batch] " << done << "/" << todo.size() << " done (seed " << seed
                << (ok ? " ok" : " FAILED") << "), " << std::fixed << std::setprecision(0) << elapsed_s << " s";
      if (done < todo.size()) {
        std::cerr << ", ~" << elapsed_s / static_cast<double>(done) * static_cast<double>(todo.size() - done)
                  << " s left";
      }
      std::cerr << std::defaultfloat << "\n";
    }
  }
  claimed.commit();  // nothing of its own to publish; the folder is kept
  return failed;
}

BatchSummary BatchApp::aggregate(const std::string& out_dir, const std::string& title) {
  OutputSet outputs;
  outputs.claimFolder(out_dir);  // before reading: no runner may be adding runs meanwhile
  const MetricRows rows = readFinishedRuns(out_dir);
  const MetricStats stats = metricStats(rows);
  BatchSummary summary;
  summary.runs = rows.size();
  for (const auto& r : rows) summary.seeds.push_back(static_cast<std::uint64_t>(r[0]));
  summary.table_markdown = table1Markdown(title, summary.seeds, stats);
  const fs::path out(out_dir);
  outputs.add((out / "aggregate.csv").string(), aggregateCsv(rows));
  outputs.add((out / "table1.md").string(), summary.table_markdown);
  // Without gnuplot the table is written without its picture, with a warning (decision 55).
  try {
    outputs.add((out / "final_errors.png").string(),
                finalErrorsPng(rows, stats.at("icp_final_error_m").count > 0, title));
  } catch (const std::runtime_error& e) {
    std::cerr << "lidarseg-batch: warning: no picture final_errors.png: " << e.what() << "\n";
    std::error_code ec;
    fs::remove(out / "final_errors.png", ec);  // not a picture of earlier runs beside the new table
  }
  outputs.commit();
  return summary;
}

}  // namespace lidarseg::apps
