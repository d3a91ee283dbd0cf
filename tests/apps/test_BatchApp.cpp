// lidarseg-batch's jobs: one run, resuming, aggregation.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "EmptyPath.h"
#include "ErrorOf.h"
#include "lidarseg/apps/BatchApp.h"
#include "lidarseg/eval/Csv.h"
#include "lidarseg/report/BatchResults.h"

namespace lidarseg::apps {
namespace {
namespace fs = std::filesystem;
const std::string kWorlds = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/";
const std::string kTmp = std::string(LIDARSEG_TEST_TMP_DIR) + "/batch";
using lidarseg::testing::errorOf;

TEST(BatchApp, ParseSeeds) {
  EXPECT_EQ(parseSeeds("1-3"), (std::vector<std::uint64_t>{1, 2, 3}));
  EXPECT_EQ(parseSeeds("7,2,4-5,2"), (std::vector<std::uint64_t>{2, 4, 5, 7}));
  EXPECT_THROW(parseSeeds("3-1"), std::invalid_argument);
  EXPECT_THROW(parseSeeds("a"), std::invalid_argument);
  EXPECT_THROW(parseSeeds(""), std::invalid_argument);
  // The top of uint64: no wrap-around, no endless loop.
  EXPECT_EQ(parseSeeds("18446744073709551614-18446744073709551615"),
            (std::vector<std::uint64_t>{18446744073709551614ull, 18446744073709551615ull}));
  EXPECT_THROW(parseSeeds("1-60000,100001-160000"), std::invalid_argument);  // 120,000 runs
  // The cap is checked before a range is expanded: 30,000 ranges of 100,001 seeds (24 GB
  // expanded) are refused at once, as too many runs (not as a malformed range after a
  // bad_alloc).
  std::string many;
  for (int i = 0; i < 30000; ++i) many += (i ? ",0-100000" : "0-100000");
  try {
    parseSeeds(many);
    ADD_FAILURE() << "3e9 runs accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("more than 100000 runs"), std::string::npos) << e.what();
  }
}

// A job of 6 m through the maze, its trajectory and results in `dir` (emptied first): its
// own folder, since CTest runs this file's tests as parallel processes under kTmp.
BatchJob shortMazeJob(const std::string& dir) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string traj = dir + "/short.traj";
  std::ofstream(traj) << "speed 1.0\nturn_radius 0.6\nwaypoint 24 0\nwaypoint 30 0\n";
  BatchJob job;
  job.world_path = kWorlds + "maze.world";
  job.trajectory_path = traj;
  job.out_dir = dir + "/out";
  return job;
}

TEST(BatchApp, RunsResumeAndAggregate) {
  const std::string dir = kTmp + "/resume";
  BatchJob job = shortMazeJob(dir);
  for (std::uint64_t seed : {1, 2}) {
    job.seed = seed;
    BatchApp::runOne(job);
    EXPECT_TRUE(BatchApp::finished(job.out_dir, seed));
    EXPECT_FALSE(fs::exists(BatchApp::runDir(job.out_dir, seed) + ".partial"));
    EXPECT_FALSE(fs::exists(BatchApp::runDir(job.out_dir, seed) + "/sim.rawlog"));  // data not kept
  }
  // Resuming: a finished run is not redone.
  const auto metrics = BatchApp::runDir(job.out_dir, 1) + "/metrics.csv";
  const auto before = fs::last_write_time(metrics);
  job.seed = 1;
  BatchApp::runOne(job);
  EXPECT_EQ(fs::last_write_time(metrics), before);
  // A killed run (left as .partial) is not counted.
  fs::create_directories(BatchApp::runDir(job.out_dir, 3) + ".partial");
  const BatchSummary s = BatchApp::aggregate(job.out_dir, "test");
  EXPECT_EQ(s.runs, 2u);
  EXPECT_EQ(s.seeds, (std::vector<std::uint64_t>{1, 2}));
  EXPECT_NE(s.table_markdown.find("| lidarseg |"), std::string::npos);
  EXPECT_NE(s.table_markdown.find("| MRPT ICP |"), std::string::npos);
  EXPECT_TRUE(fs::exists(job.out_dir + "/table1.md"));
  EXPECT_TRUE(fs::exists(job.out_dir + "/aggregate.csv"));
  EXPECT_TRUE(fs::exists(job.out_dir + "/final_errors.png"));
  EXPECT_NE(s.table_markdown.find("µs; speed-up"), std::string::npos) << s.table_markdown;
  EXPECT_THROW(BatchApp::aggregate(dir + "/nothing-here", "x"), std::runtime_error);
  // Without ICP there is no ratio to give: no "0.0x" speed-up, no ICP time, empty cells in
  // the CSV (no "nan" in an output).
  BatchJob alone = job;
  alone.baseline_icp = false;
  alone.out_dir = dir + "/out-no-icp";
  alone.seed = 1;
  BatchApp::runOne(alone);
  const BatchSummary a = BatchApp::aggregate(alone.out_dir, "test");
  EXPECT_EQ(a.table_markdown.find("speed-up"), std::string::npos) << a.table_markdown;
  EXPECT_EQ(a.table_markdown.find("| MRPT ICP |"), std::string::npos);
  EXPECT_NE(a.table_markdown.find("(MRPT ICP not run)"), std::string::npos) << a.table_markdown;
  std::ifstream csv(alone.out_dir + "/aggregate.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  const std::vector<std::string> names = eval::splitCsvLine(header), values = eval::splitCsvLine(row);
  ASSERT_EQ(names.size(), values.size()) << header << "\n" << row;
  const auto at = std::find(names.begin(), names.end(), "speedup_median");
  ASSERT_NE(at, names.end()) << header;
  EXPECT_EQ(values[static_cast<std::size_t>(at - names.begin())], "") << header << "\n" << row;
  EXPECT_EQ(row.find("nan"), std::string::npos) << row;
  const auto icp_error = std::find(names.begin(), names.end(), "icp_final_error_m");
  ASSERT_NE(icp_error, names.end()) << header;
  EXPECT_EQ(values[static_cast<std::size_t>(icp_error - names.begin())], "") << row;
  // Without gnuplot: the table and a warning, no picture (none of the earlier runs left).
  ::testing::internal::CaptureStderr();
  {
    const lidarseg::testing::EmptyPath no_gnuplot;
    EXPECT_EQ(BatchApp::aggregate(job.out_dir, "test").runs, 2u);
  }
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("lidarseg-batch: warning: no picture final_errors.png: gnuplot is not installed"),
            std::string::npos)
      << err;
  EXPECT_TRUE(fs::exists(job.out_dir + "/table1.md"));
  EXPECT_FALSE(fs::exists(job.out_dir + "/final_errors.png"));
}

// The simulator's stamp convention reaches the correction: a last-stamped simulation was
// deskewed as first-stamped (about the wrong beam), which summary.json now says.
TEST(BatchApp, TheSimulatedStampConventionReachesTheCorrection) {
  const std::string dir = kTmp + "/stamp";
  fs::create_directories(dir);
  const std::string sim_config = dir + "/sim.ini";
  std::ofstream(sim_config) << "[simulation]\nscan_stamp = last\n";
  BatchJob job = shortMazeJob(dir + "/out");
  job.sim_config_path = sim_config;
  job.baseline_icp = false;
  job.seed = 1;
  BatchApp::runOne(job);
  std::ifstream in(BatchApp::runDir(job.out_dir, 1) + "/summary.json");
  const std::string summary((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(summary.find("stamped at the last beam"), std::string::npos) << summary.substr(0, 800);
}

TEST(BatchApp, AFailingJobLeavesNothingThatLooksFinished) {
  BatchJob job;
  job.world_path = kWorlds + "no-such.world";
  job.trajectory_path = kWorlds + "maze.traj";
  job.out_dir = kTmp + "/failing";
  job.seed = 4;
  EXPECT_THROW(BatchApp::runOne(job), std::exception);
  EXPECT_FALSE(BatchApp::finished(job.out_dir, 4));
}

TEST(BatchApp, RunManyReportsFailedAndCrashedJobsAndFinishesTheOthers) {
  // A stand-in for the job program: seed 2 fails with a message, seed 3 is killed, the
  // others finish (they write their metrics.csv as a real job does).
  const std::string dir = kTmp + "/many";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string script = dir + "/job.sh";
  std::ofstream(script) << "#!/bin/sh\n"
                           "while [ $# -gt 0 ]; do case \"$1\" in --seed) seed=$2;; --out) out=$2;; esac; shift; done\n"
                           "if [ \"$seed\" = 2 ]; then echo \"bad world file\" >&2; exit 1; fi\n"
                           "if [ \"$seed\" = 3 ]; then kill -9 $$; fi\n"
                           "mkdir -p \"$out/run_$seed\" && echo seed > \"$out/run_$seed/metrics.csv\"\n";
  fs::permissions(script, fs::perms::owner_all);
  BatchJob job;
  job.world_path = "w";
  job.trajectory_path = "t";
  job.out_dir = dir + "/out";
  std::vector<std::string> failed = BatchApp::runMany(job, {1, 2, 3, 4, 5}, 2, script, false);
  std::sort(failed.begin(), failed.end());
  ASSERT_EQ(failed.size(), 2u);
  EXPECT_NE(failed[0].find("seed 2: exit code 1 (bad world file)"), std::string::npos) << failed[0];
  EXPECT_NE(failed[1].find("seed 3: killed by signal 9"), std::string::npos) << failed[1];
  for (std::uint64_t s : {1, 4, 5}) EXPECT_TRUE(BatchApp::finished(job.out_dir, s)) << s;
  EXPECT_TRUE(fs::exists(job.out_dir + "/run_2.log"));  // the failed job's stderr is kept
  // Resuming runs only the unfinished ones.
  const auto again = BatchApp::runMany(job, {1, 2, 3, 4, 5}, 2, script, false);
  EXPECT_EQ(again.size(), 2u);
  // The folder records its experiment: resumed with another sensor or world, it is refused
  // (its finished runs would be averaged with the new ones into one table).
  EXPECT_TRUE(fs::exists(job.out_dir + "/experiment.txt"));
  BatchJob other = job;
  other.sensor = "utm30lx";
  try {
    BatchApp::runMany(other, {6}, 1, script, false);
    FAIL() << "a second experiment was run into the same folder";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("another experiment"), std::string::npos) << e.what();
  }
  other = job;
  other.world_path = script;  // another file's contents
  EXPECT_THROW(BatchApp::runMany(other, {6}, 1, script, false), std::runtime_error);
  EXPECT_FALSE(BatchApp::finished(job.out_dir, 6));
}

// Whether another writer could take the folder's lock now (a separate open file, as another
// process's: flock refuses it even within this process).
bool anotherWriterCouldLock(const std::string& dir) {
  const int fd = ::open((dir + "/.lidarseg.lock").c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) return true;  // no lock file: nothing held
  const bool locked = ::flock(fd, LOCK_EX | LOCK_NB) == 0;
  ::close(fd);
  return locked;
}

// `lidarseg-batch run` runs, then aggregates: no other writer may slip in between (issue 16).
TEST(BatchApp, TheFolderStaysLockedFromTheRunsToTheirTable) {
  const std::string dir = kTmp + "/run-and-aggregate";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // A stand-in job writing a metrics.csv with its seed and every figure 1.
  std::string values = report::metricsLine(0, std::vector<double>(report::batchMetricNames().size(), 1.0));
  values = values.substr(values.find(','));
  std::ofstream(dir + "/metrics.head") << report::metricsHeader();
  std::ofstream(dir + "/metrics.values") << values;
  // It also checks that it inherited the runner's folder lock under the number it is given.
  const std::string script = dir + "/job.sh";
  std::ofstream(script) << "#!/bin/sh\n"
                           "while [ $# -gt 0 ]; do case \"$1\" in --seed) seed=$2;; --out) out=$2;; --folder-lock-fd) fd=$2;; esac; shift; done\n"
                           "case $(readlink /proc/$$/fd/$fd) in */.lidarseg.lock) ;; *) echo 'no lock inherited' >&2; exit 1;; esac\n"
                           "mkdir -p \"$out/run_$seed\" && { cat '" << dir << "/metrics.head'; printf %s \"$seed\"; cat '"
                        << dir << "/metrics.values'; } > \"$out/run_$seed/metrics.csv\"\n";
  fs::permissions(script, fs::perms::owner_all);
  BatchJob job;
  job.world_path = "w";
  job.trajectory_path = "t";
  job.out_dir = dir + "/out";
  bool between_called = false, locked_between = false;
  const BatchOutcome outcome = BatchApp::runAndAggregate(job, {1, 2, 3}, 2, script, false, "locked", [&] {
    between_called = true;
    locked_between = !anotherWriterCouldLock(job.out_dir);
  });
  EXPECT_TRUE(between_called);
  EXPECT_TRUE(locked_between) << "the folder was free between the runs and the aggregation";
  EXPECT_TRUE(outcome.failed.empty()) << outcome.failed.front();
  EXPECT_EQ(outcome.summary.runs, 3u);
  EXPECT_EQ(outcome.summary.seeds, (std::vector<std::uint64_t>{1, 2, 3}));
  EXPECT_TRUE(fs::exists(job.out_dir + "/table1.md"));
  EXPECT_TRUE(anotherWriterCouldLock(job.out_dir)) << "released once the table is written";
}

// The folder's lock as another process would hold it: its own open file, locked `how`
// (LOCK_EX: a runner or an aggregation; LOCK_SH: a job started by hand).
int holdFolderLock(const std::string& dir, int how) {
  fs::create_directories(dir);
  const int fd = ::open((dir + "/.lidarseg.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0 || ::flock(fd, how | LOCK_NB) != 0) ADD_FAILURE() << "cannot lock " << dir;
  return fd;
}

// `lidarseg-batch one` started by hand is a writer like any other (issue 16): refused while a
// runner or an aggregation holds the folder; jobs started by hand share it with each other
// (a cluster's array job), and an aggregation is refused while one runs; a runner's own job
// inherits the runner's lock and nothing else passes for it.
TEST(BatchApp, AJobStartedByHandIsRefusedBesideARunnerAndSharesTheFolderWithOtherJobs) {
  BatchJob job = shortMazeJob(kTmp + "/one-by-hand");
  const std::string traj = job.trajectory_path;
  job.baseline_icp = false;
  job.seed = 1;

  // A runner (another process) holds the folder: a job by hand is refused before any work.
  const int runner = holdFolderLock(job.out_dir, LOCK_EX);
  const std::string refused = errorOf([&] { BatchApp::runOne(job); });
  EXPECT_NE(refused.find("another run is writing into '" + job.out_dir + "'"), std::string::npos) << refused;
  EXPECT_FALSE(BatchApp::finished(job.out_dir, 1));
  EXPECT_FALSE(fs::exists(BatchApp::runDir(job.out_dir, 1) + ".partial"));
  // Another open file of the lock, or another file, does not pass for the runner's.
  const int other = ::open((job.out_dir + "/.lidarseg.lock").c_str(), O_RDWR | O_CLOEXEC);
  job.folder_lock_fd = other;
  EXPECT_NE(errorOf([&] { BatchApp::runOne(job); }).find("is not the held lock"), std::string::npos);
  ::close(other);
  const int not_lock = ::open(traj.c_str(), O_RDONLY | O_CLOEXEC);
  job.folder_lock_fd = not_lock;
  EXPECT_NE(errorOf([&] { BatchApp::runOne(job); }).find("is not the held lock"), std::string::npos);
  ::close(not_lock);
  EXPECT_FALSE(BatchApp::finished(job.out_dir, 1));
  // The runner's own job: the runner's open file, inherited (a copy of its descriptor).
  job.folder_lock_fd = ::dup(runner);
  BatchApp::runOne(job);
  EXPECT_TRUE(BatchApp::finished(job.out_dir, 1));
  EXPECT_FALSE(anotherWriterCouldLock(job.out_dir)) << "the job released its runner's lock";
  ::close(runner);
  job.folder_lock_fd = -1;

  // Jobs by hand share the folder (each holds its seed); an aggregation waits for them.
  const int by_hand = holdFolderLock(job.out_dir, LOCK_SH);
  EXPECT_NO_THROW(BatchApp::runOne(job));  // finished: returns once it has shared the lock
  const std::string aggregation = errorOf([&] { BatchApp::aggregate(job.out_dir, "x"); });
  EXPECT_NE(aggregation.find("another run is writing into"), std::string::npos) << aggregation;
  ::close(by_hand);
  EXPECT_EQ(BatchApp::aggregate(job.out_dir, "x").runs, 1u);

  // A job by hand checks the folder's experiment as the runner does.
  BatchJob other_sensor = job;
  other_sensor.sensor = "utm30lx";
  other_sensor.seed = 2;
  const std::string experiment = errorOf([&] { BatchApp::runOne(other_sensor); });
  EXPECT_NE(experiment.find("another experiment"), std::string::npos) << experiment;
  EXPECT_FALSE(BatchApp::finished(job.out_dir, 2));
}

// A run folder made by hand: OUT/run_<folder>/metrics.csv holding `seed` and `values`
// (batchMetricNames() order; 1 everywhere unless given).
void writeRun(const std::string& out, const std::string& folder, const std::string& seed,
              const std::vector<std::pair<std::string, std::string>>& cells = {}) {
  std::vector<std::string> values(report::batchMetricNames().size(), "1");
  for (const auto& [name, text] : cells) values[report::metricColumn(name) - 1] = text;
  fs::create_directories(out + "/" + folder);
  std::ofstream f(out + "/" + folder + "/metrics.csv");
  f << report::metricsHeader() << seed;
  for (const auto& v : values) f << ',' << v;
  f << '\n';
}

// Seeds beyond 2^53 were read back through a double: 2^64-2 and 2^64-1 became seed 0 (an
// out-of-range conversion) and 2^53+1 became 2^53 (issue 16). They are read exactly.
TEST(BatchApp, AggregationReadsSeedsExactly) {
  const std::string out = kTmp + "/big-seeds";
  fs::remove_all(out);
  for (const char* seed : {"18446744073709551614", "18446744073709551615", "9007199254740993"}) {
    writeRun(out, std::string("run_") + seed, seed);
  }
  const BatchSummary s = BatchApp::aggregate(out, "t");
  EXPECT_EQ(s.seeds, (std::vector<std::uint64_t>{9007199254740993ull, 18446744073709551614ull, 18446744073709551615ull}));
  EXPECT_NE(s.table_markdown.find("3 runs (seeds 9007199254740993–18446744073709551615)"), std::string::npos)
      << s.table_markdown;
  std::ifstream csv(out + "/aggregate.csv");
  std::string line;
  std::vector<std::string> seeds;
  std::getline(csv, line);
  while (std::getline(csv, line)) seeds.push_back(line.substr(0, line.find(',')));
  EXPECT_EQ(seeds, (std::vector<std::string>{"9007199254740993", "18446744073709551614", "18446744073709551615"}));
}

// A run folder without metrics.csv was dropped silently; a metrics.csv of another seed, a
// negative final error or one of 1e308 entered the table (issue 16).
TEST(BatchApp, AggregationNamesRunFoldersItCannotTrust) {
  const std::string out = kTmp + "/untrusted";
  fs::remove_all(out);
  writeRun(out, "run_1", "1");
  fs::create_directories(out + "/run_2");
  ::testing::internal::CaptureStderr();
  const BatchSummary s = BatchApp::aggregate(out, "t");
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(s.seeds, (std::vector<std::uint64_t>{1}));
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0], "'" + out + "/run_2' holds no metrics.csv (a run not finished); left out");
  EXPECT_NE(err.find("lidarseg-batch: warning: '" + out + "/run_2' holds no metrics.csv"), std::string::npos) << err;

  writeRun(out, "run_2", "7");
  EXPECT_EQ(errorOf([&] { BatchApp::aggregate(out, "t"); }),
            out + "/run_2/metrics.csv:2:1: seed '7' is not its folder's (run_2)");
  writeRun(out, "run_2", "2", {{"lidarseg_final_error_m", "-0.5"}});
  EXPECT_EQ(errorOf([&] { BatchApp::aggregate(out, "t"); }),
            out + "/run_2/metrics.csv:2:3: lidarseg_final_error_m = '-0.5' is not a run's figure (finite, from 0 to 1e+06)");
  writeRun(out, "run_2", "2", {{"icp_ate_rmse_m", "1e308"}});
  EXPECT_EQ(errorOf([&] { BatchApp::aggregate(out, "t"); }),
            out + "/run_2/metrics.csv:2:16: icp_ate_rmse_m = '1e308' is not a run's figure (finite, from 0 to 1e+06)");
  writeRun(out, "run_2", "2", {{"lidarseg_edx_m", "inf"}});
  EXPECT_NE(errorOf([&] { BatchApp::aggregate(out, "t"); }).find(":2:9: lidarseg_edx_m = 'inf'"), std::string::npos);
  // A signed mean may be negative.
  writeRun(out, "run_2", "2", {{"lidarseg_edx_m", "-0.01"}});
  EXPECT_EQ(BatchApp::aggregate(out, "t").runs, 2u);
}

}  // namespace
}  // namespace lidarseg::apps
