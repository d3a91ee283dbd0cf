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

}  // namespace

int main(int argc, char** argv) {
  using lidarseg::apps::BatchApp;
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
  try {
    TCLAP::CmdLine cmd("lidarseg-batch " + command, ' ', "0.1.0");
    if (command == "aggregate") {
      TCLAP::UnlabeledValueArg<std::string> dir("dir", "results folder", true, "", "DIR", cmd);
      TCLAP::ValueArg<std::string> title("", "title", "title of the table", false, "", "TEXT", cmd);
      if (const auto status = lidarseg::apps::parseCommandLine(cmd, argc - 1, argv + 1, "lidarseg-batch " + command)) return *status;
      const auto s = BatchApp::aggregate(dir.getValue(), title.getValue().empty() ? dir.getValue() : title.getValue());
      std::cout << s.table_markdown;
      return 0;
    }
    if (command != "run" && command != "one") return usage();
    TCLAP::ValueArg<std::string> world("", "world", "world file", true, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> trajectory("", "trajectory", "trajectory file", true, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> sensor("", "sensor-model", "simulated sensor: lms100, utm30lx, sick180, rplidar360", false, "lms100",
                                        "NAME", cmd);
    TCLAP::ValueArg<std::string> sim_config("", "sim-config", "INI with [simulation]", false, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> config("c", "config", "INI with lidarseg-odometry's sections", false, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> out("o", "out", "results folder", true, "", "DIR", cmd);
    TCLAP::ValueArg<std::string> seeds("", "seeds", "seeds to run, e.g. 1-50 (run)", false, "1-50", "LIST", cmd);
    TCLAP::ValueArg<std::uint64_t> seed("", "seed", "the seed (one)", false, 1, "N", cmd);
    TCLAP::ValueArg<std::size_t> jobs("j", "jobs", "runs at a time (run; default: all cores)", false, 0, "N", cmd);
    TCLAP::SwitchArg no_icp("", "no-icp", "do not run MRPT ICP", cmd);
    TCLAP::SwitchArg keep("", "keep-data", "keep the simulated rawlogs", cmd);
    TCLAP::SwitchArg quiet("q", "quiet", "no progress on stderr", cmd);
    TCLAP::ValueArg<std::string> title("", "title", "title of the aggregated table", false, "", "TEXT", cmd);
    TCLAP::ValueArg<int> lock_fd("", "folder-lock-fd",
                                 "(one; set by run for its jobs) the runner's lock on --out, inherited as descriptor N",
                                 false, -1, "N", cmd);
    if (const auto status = lidarseg::apps::parseCommandLine(cmd, argc - 1, argv + 1, "lidarseg-batch " + command,
                                                             {{"--sensor", "--sensor-model"}})) {
      return *status;
    }
    // The runner's own flag for its jobs: on `run` it would do nothing, and a negative
    // descriptor would silently make the job one started by hand (decision 78).
    if (lock_fd.isSet() && (command != "one" || lock_fd.getValue() < 0)) {
      std::cerr << "lidarseg-batch " << command << ": usage error: --folder-lock-fd is set by 'lidarseg-batch run' "
                << "for its own 'one' jobs (a descriptor >= 0); not for use by hand\n";
      return lidarseg::apps::kUsageError;
    }

    lidarseg::apps::BatchJob job;
    job.world_path = world.getValue();
    job.trajectory_path = trajectory.getValue();
    job.sensor = sensor.getValue();
    job.sim_config_path = sim_config.getValue();
    job.odometry_config_path = config.getValue();
    job.out_dir = out.getValue();
    job.baseline_icp = !no_icp.getValue();
    job.keep_data = keep.getValue();
    if (command == "one") {
      job.seed = seed.getValue();
      job.folder_lock_fd = lock_fd.getValue();
      BatchApp::runOne(job);
      return 0;
    }
    std::size_t n = jobs.getValue();
    if (jobs.isSet() && (n < 1 || n > 256)) {
      std::cerr << "lidarseg-batch run: usage error: -j/--jobs must be in [1, 256] (got " << n
                << "; without -j: one per core)\n";
      return lidarseg::apps::kUsageError;
    }
    if (n == 0) n = std::max(1u, std::thread::hardware_concurrency());
    // The folder stays locked from the first run to the table (no writer in between).
    const auto outcome = BatchApp::runAndAggregate(job, lidarseg::apps::checkedOption("--seeds", [&] { return lidarseg::apps::parseSeeds(seeds.getValue()); }), n,
                                                   selfExe(argv[0]), !quiet.getValue(),
                                                   title.getValue().empty() ? job.out_dir : title.getValue());
    for (const auto& f : outcome.failed) std::cerr << "lidarseg-batch: failed: " << f << "\n";
    std::cout << outcome.summary.table_markdown;
    return outcome.failed.empty() ? 0 : 3;
  } catch (const std::exception& e) {
    return lidarseg::apps::errorExit("lidarseg-batch", e);
  }
}
