// lidarseg-batch: the paper's experiment as independent, resumable jobs.
//   lidarseg-batch run --world W --trajectory T --seeds 1-50 --jobs 2 --out DIR
//   lidarseg-batch one --world W --trajectory T --seed 7 --out DIR      (one job)
//   lidarseg-batch aggregate DIR
#include <unistd.h>

#include <cstring>
#include <iostream>
#include <thread>

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include "lidarseg/apps/CommandLine.h"
#include "lidarseg/apps/BatchApp.h"

namespace {

std::string selfExe(const char* argv0) {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n > 0) return std::string(buf, static_cast<std::size_t>(n));
  return argv0;
}

int usage() {
  std::cerr << "usage: lidarseg-batch run|one|aggregate [options]   (lidarseg-batch <command> --help)\n";
  return 2;
}

// `lidarseg-batch aggregate DIR`: the table of a results folder on stdout.
int aggregateMain(int argc, char** argv) {
  TCLAP::CmdLine cmd("lidarseg-batch aggregate", ' ', "0.1.0");
  TCLAP::UnlabeledValueArg<std::string> dir("dir", "results folder", true, "", "DIR", cmd);
  TCLAP::ValueArg<std::string> title("", "title", "title of the table", false, "", "TEXT", cmd);
  if (const auto status = lidarseg::apps::parseCommandLine(cmd, argc - 1, argv + 1, "lidarseg-batch aggregate")) return *status;
  const auto s = lidarseg::apps::BatchApp::aggregate(dir.getValue(), title.getValue().empty() ? dir.getValue() : title.getValue());
  std::cout << s.table_markdown;
  return lidarseg::apps::exitAfterStdout("lidarseg-batch", 0);
}

// The options of `run` and `one`, registered with their command line.
struct JobArguments {
  explicit JobArguments(TCLAP::CmdLine& cmd)
      : world("", "world", "world file", true, "", "FILE", cmd),
        trajectory("", "trajectory", "trajectory file", true, "", "FILE", cmd),
        sensor("", "sensor-model", "simulated sensor: lms100, utm30lx, sick180, rplidar360", false, "lms100", "NAME", cmd),
        sim_config("", "sim-config", "INI with [simulation]", false, "", "FILE", cmd),
        config("c", "config", "INI with lidarseg-odometry's sections", false, "", "FILE", cmd),
        out("o", "out", "results folder", true, "", "DIR", cmd),
        seeds("", "seeds", "seeds to run, e.g. 1-50 (run only)", false, "1-50", "LIST", cmd),
        seed("", "seed", "the seed (one only)", false, 1, "N", cmd),
        jobs("j", "jobs", "runs at a time (run only; default: all cores)", false, 0, "N", cmd),
        no_icp("", "no-icp", "do not run MRPT ICP", cmd),
        keep("", "keep-data", "keep the simulated rawlogs", cmd),
        quiet("q", "quiet", "no progress on stderr", cmd),
        title("", "title", "title of the aggregated table (run only)", false, "", "TEXT", cmd),
        lock_fd("", "folder-lock-fd",
                "(one; set by run for its jobs) the runner's lock on --out, inherited as descriptor N", false, -1, "N",
                cmd) {}

  // The job every seed runs.
  lidarseg::apps::BatchJob job() {  // TCLAP's getValue() is not const
    lidarseg::apps::BatchJob j;
    j.world_path = world.getValue();
    j.trajectory_path = trajectory.getValue();
    j.sensor = sensor.getValue();
    j.sim_config_path = sim_config.getValue();
    j.odometry_config_path = config.getValue();
    j.out_dir = out.getValue();
    j.baseline_icp = !no_icp.getValue();
    j.keep_data = keep.getValue();
    return j;
  }

  TCLAP::ValueArg<std::string> world, trajectory, sensor, sim_config, config, out, seeds;
  TCLAP::ValueArg<std::uint64_t> seed;
  TCLAP::ValueArg<std::size_t> jobs;
  TCLAP::SwitchArg no_icp, keep, quiet;
  TCLAP::ValueArg<std::string> title;
  TCLAP::ValueArg<int> lock_fd;
};

// The runner's own flag for its jobs: on `run` it would do nothing, and a negative
// descriptor would silently make the job one started by hand (decision 78).
bool lockFlagMisused(const std::string& command, JobArguments& a) {
  if (!a.lock_fd.isSet() || (command == "one" && a.lock_fd.getValue() >= 0)) return false;
  std::cerr << "lidarseg-batch " << command << ": usage error: --folder-lock-fd is set by 'lidarseg-batch run' "
            << "for its own 'one' jobs (a descriptor >= 0); not for use by hand\n";
  return true;
}

// A flag of the other sub-command would be ignored without a word (`run --seed 7` ran seeds
// 1-50): a usage error naming the flag and where it belongs (issue 16).
bool otherCommandsFlag(const std::string& command, JobArguments& a) {
  std::string flag, hint;
  if (command == "run" && a.seed.isSet()) {
    flag = "--seed", hint = "'run' takes --seeds LIST (e.g. --seeds 7)";
  } else if (command == "one" && a.seeds.isSet()) {
    flag = "--seeds", hint = "'one' runs one seed: --seed N";
  } else if (command == "one" && a.jobs.isSet()) {
    flag = "-j/--jobs", hint = "'one' is one run; 'run' runs several at a time";
  } else if (command == "one" && a.title.isSet()) {
    flag = "--title", hint = "the table's title is given to 'run' or 'aggregate'";
  } else {
    return false;
  }
  std::cerr << "lidarseg-batch " << command << ": usage error: " << flag << " is not an option of '" << command
            << "': " << hint << "\n";
  return true;
}

// `lidarseg-batch run`: every seed as its own `one` job, N at a time, then the table.
int runAll(JobArguments& a, const char* argv0) {
  using lidarseg::apps::BatchApp;
  std::size_t n = a.jobs.getValue();
  if (a.jobs.isSet() && (n < 1 || n > 256)) {
    std::cerr << "lidarseg-batch run: usage error: -j/--jobs must be in [1, 256] (got " << n
              << "; without -j: one per core)\n";
    return lidarseg::apps::kUsageError;
  }
  if (n == 0) n = std::max(1u, std::thread::hardware_concurrency());
  const auto seeds = lidarseg::apps::checkedOption("--seeds", [&] { return lidarseg::apps::parseSeeds(a.seeds.getValue()); });
  const lidarseg::apps::BatchJob job = a.job();
  // The folder stays locked from the first run to the table (no writer in between).
  const auto outcome = BatchApp::runAndAggregate(job, seeds, n, selfExe(argv0), !a.quiet.getValue(),
                                                 a.title.getValue().empty() ? job.out_dir : a.title.getValue());
  for (const auto& f : outcome.failed) std::cerr << "lidarseg-batch: failed: " << f << "\n";
  std::cout << outcome.summary.table_markdown;
  return lidarseg::apps::exitAfterStdout("lidarseg-batch", outcome.failed.empty() ? 0 : 3);
}

// `lidarseg-batch run` and `lidarseg-batch one`.
int jobsMain(const std::string& command, int argc, char** argv) {
  TCLAP::CmdLine cmd("lidarseg-batch " + command, ' ', "0.1.0");
  JobArguments a(cmd);
  if (const auto status = lidarseg::apps::parseCommandLine(cmd, argc - 1, argv + 1, "lidarseg-batch " + command,
                                                           {{"--sensor", "--sensor-model"}})) {
    return *status;
  }
  if (lockFlagMisused(command, a) || otherCommandsFlag(command, a)) return lidarseg::apps::kUsageError;
  if (command == "run") return runAll(a, argv[0]);
  lidarseg::apps::BatchJob job = a.job();
  job.seed = a.seed.getValue();
  job.folder_lock_fd = a.lock_fd.getValue();
  lidarseg::apps::BatchApp::runOne(job);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  const std::string command = argv[1];
  if (command == "--version") {
    std::cout << "lidarseg-batch  version: 0.1.0\n";
    return 0;
  }
  if (command == "--help" || command == "-h") {
    std::cout << "usage: lidarseg-batch run|one|aggregate [options]   (lidarseg-batch <command> --help)\n";
    return 0;
  }
  if (command != "run" && command != "one" && command != "aggregate") return usage();
  try {
    return command == "aggregate" ? aggregateMain(argc, argv) : jobsMain(command, argc, argv);
  } catch (const std::exception& e) {
    return lidarseg::apps::errorExit("lidarseg-batch", e);
  }
}
