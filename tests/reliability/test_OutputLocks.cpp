// Issue 16, class 4, for every tool but lidarseg-odometry (whose CTest
// app.lidarseg-odometry.signal-cleanup-and-lock covers it): the output folder is locked
// before any work, so a second writer is refused at once, and an output that is one of the
// tool's inputs is refused before anything is read or written.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "TempFiles.h"
#include "ErrorOf.h"
#include "lidarseg/apps/BatchApp.h"
#include "lidarseg/apps/CommandLine.h"
#include "lidarseg/apps/FeaturesApp.h"
#include "lidarseg/apps/InspectApp.h"
#include "lidarseg/apps/OdometryApp.h"
#include "lidarseg/apps/PeopleApp.h"
#include "lidarseg/apps/SegmentStatsApp.h"
#include "lidarseg/apps/SimulateApp.h"

namespace lidarseg::apps {
namespace {
namespace fs = std::filesystem;
const std::string kTmp = std::string(LIDARSEG_TEST_TMP_DIR) + "/output-locks";

// Another run writing into `dir`: its lock, taken the way the tools take it (flock on an open
// file of its own, so this process's tools are refused as another process's would be).
class AnotherWriter {
 public:
  explicit AnotherWriter(const std::string& dir) {
    fs::create_directories(dir);
    fd_ = ::open((dir + "/.lidarseg.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    locked_ = fd_ >= 0 && ::flock(fd_, LOCK_EX | LOCK_NB) == 0;
  }
  ~AnotherWriter() {
    if (fd_ >= 0) ::close(fd_);
  }
  AnotherWriter(const AnotherWriter&) = delete;
  AnotherWriter& operator=(const AnotherWriter&) = delete;
  bool locked() const { return locked_; }

 private:
  int fd_ = -1;
  bool locked_ = false;
};

using lidarseg::testing::errorOf;

using lidarseg::testing::slurp;

// The input of every run below does not exist: a tool that read it before claiming its
// output folder would report the missing input instead of the other writer.
const std::string kAbsent = kTmp + "/absent-input.rawlog";

void expectRefusedAtOnce(const std::string& error, const std::string& dir) {
  EXPECT_NE(error.find("another run is writing into '" + dir + "'"), std::string::npos) << error;
}

}  // namespace

TEST(OutputLocks, EveryToolClaimsItsOutputFolderBeforeItsWork) {
  const std::string dir = kTmp + "/held";
  fs::remove_all(dir);
  const AnotherWriter other(dir);
  ASSERT_TRUE(other.locked());

  FeaturesOptions f;
  f.input = kAbsent;
  f.out_csv = dir + "/features.csv";
  expectRefusedAtOnce(errorOf([&] { FeaturesApp(f).run(); }), dir);
  f.out_csv.clear();
  f.report_dir = dir;
  expectRefusedAtOnce(errorOf([&] { FeaturesApp(f).run(); }), dir);

  PeopleOptions p;
  p.input = kAbsent;
  p.rois = {"0,0,10,10"};
  p.draw_dir = dir;
  expectRefusedAtOnce(errorOf([&] { PeopleApp(p).run(); }), dir);

  SimulateOptions s;
  s.world_path = kAbsent;
  s.trajectory_path = kAbsent;
  s.out_prefix = dir + "/sim";
  expectRefusedAtOnce(errorOf([&] { SimulateApp(s).run(); }), dir);

  SegmentStatsOptions g;
  g.input = kAbsent;
  g.csv_path = dir + "/segments.csv";
  expectRefusedAtOnce(errorOf([&] { SegmentStatsApp(g).run(); }), dir);

  InspectOptions i;
  i.input = kAbsent;
  i.report_dir = dir;
  expectRefusedAtOnce(errorOf([&] { InspectApp(i).run(); }), dir);

  BatchJob b;
  b.world_path = kAbsent;
  b.trajectory_path = kAbsent;
  b.out_dir = dir;
  expectRefusedAtOnce(errorOf([&] { BatchApp::runMany(b, {1}, 1, "/bin/false", false); }), dir);
  expectRefusedAtOnce(errorOf([&] { BatchApp::aggregate(dir, "t"); }), dir);

  // Nothing was written beside the other writer's lock.
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) entries += e.path().filename() != ".lidarseg.lock";
  EXPECT_EQ(entries, 0u);
}

TEST(OutputLocks, AFreeFolderIsTakenAndLeftReusable) {
  // The same run once the other writer is gone: the missing input is now what is reported,
  // and the folder the tool created for nothing is removed again.
  const std::string dir = kTmp + "/free";
  fs::remove_all(dir);
  FeaturesOptions f;
  f.input = kAbsent;
  f.out_csv = dir + "/features.csv";
  const std::string e = errorOf([&] { FeaturesApp(f).run(); });
  EXPECT_NE(e.find("absent-input.rawlog"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(dir));
}

TEST(OutputLocks, AnOutputThatIsAnInputIsRefusedAndTheInputKept) {
  fs::create_directories(kTmp);
  const std::string log = kTmp + "/input.log";
  const std::string text = "FLASER 3 1 1 1 0 0 0 0 0 0 1 h 1\n";
  std::ofstream(log, std::ios::binary) << text;

  FeaturesOptions f;
  f.input = log;
  f.out_csv = log;
  std::string e = errorOf([&] { FeaturesApp(f).run(); });
  EXPECT_NE(e.find("--out '" + log + "' is the input"), std::string::npos) << e;
  f.out_csv.clear();
  f.rois_out = kTmp + "/./input.log";  // another spelling of the same file
  e = errorOf([&] { FeaturesApp(f).run(); });
  EXPECT_NE(e.find("--rois-out"), std::string::npos) << e;
  EXPECT_NE(e.find("an output never overwrites its input"), std::string::npos) << e;

  SegmentStatsOptions g;
  g.input = log;
  g.csv_path = log;
  e = errorOf([&] { SegmentStatsApp(g).run(); });
  EXPECT_NE(e.find("--csv '" + log + "' is the input"), std::string::npos) << e;

  PeopleOptions p;
  p.input = kTmp;
  p.rois_path = log;  // an input of lidarseg-people too
  p.out_csv = log;
  e = errorOf([&] { PeopleApp(p).run(); });
  EXPECT_NE(e.find("--out '" + log + "' is the input"), std::string::npos) << e;

  SimulateOptions s;
  s.world_path = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/maze.world";
  s.trajectory_path = kTmp + "/input.log.gt.tum";
  std::ofstream(s.trajectory_path) << "speed 1\n";
  s.out_prefix = kTmp + "/input.log";  // PREFIX.gt.tum would be the trajectory
  e = errorOf([&] { SimulateApp(s).run(); });
  EXPECT_NE(e.find("is the input '" + s.trajectory_path + "'"), std::string::npos) << e;
  EXPECT_EQ(slurp(s.trajectory_path), "speed 1\n");

  InspectOptions i;
  i.input = kTmp + "/input.png";
  std::ofstream(i.input) << "x";
  i.render_out = i.input;
  e = errorOf([&] { InspectApp(i).run(); });
  EXPECT_NE(e.find("--draw '" + i.input + "' is the input"), std::string::npos) << e;

  EXPECT_EQ(slurp(log), text);
}

// Issue 16: a file an output folder would get (lidarseg-odometry's timing.csv, the report's
// index.html) that is one of the inputs (the log, --gt) is refused as a usage error, before
// anything is read; the input is kept.
TEST(OutputLocks, AFileAnOutputFolderWouldWriteThatIsAnInputIsRefusedAndTheInputKept) {
  const std::string dir = kTmp + "/folder-file-is-input";
  fs::remove_all(dir);
  fs::create_directories(dir + "/oz");
  const std::string text = "FLASER 3 1 1 1 0 0 0 0 0 0 1 h 1\n";
  const std::string log = dir + "/oz/timing.csv";
  std::ofstream(log, std::ios::binary) << text;

  OdometryOptions o;
  o.input = log;
  o.out_dir = dir + "/oz";
  o.progress = false;
  EXPECT_THROW(OdometryApp(o).run(), UsageError);
  std::string e = errorOf([&] { OdometryApp(o).run(); });
  EXPECT_NE(e.find("-o '" + dir + "/oz/timing.csv' is the input '" + log + "'"), std::string::npos) << e;

  const std::string gt = dir + "/oz/lidarseg.tum";
  std::ofstream(gt) << "0 0 0 0 0 0 0 1\n";
  o.input = kAbsent;
  o.gt_path = gt;
  e = errorOf([&] { OdometryApp(o).run(); });
  EXPECT_NE(e.find("is the input '" + gt + "'"), std::string::npos) << e;
  EXPECT_EQ(slurp(gt), "0 0 0 0 0 0 0 1\n");

  InspectOptions i;
  i.input = dir + "/io/index.html";
  fs::create_directories(dir + "/io");
  std::ofstream(i.input) << text;
  i.report_dir = dir + "/io";
  EXPECT_THROW(InspectApp(i).run(), UsageError);
  EXPECT_EQ(slurp(i.input), text);
  EXPECT_EQ(slurp(log), text);
  EXPECT_FALSE(fs::exists(dir + "/oz/.lidarseg.lock"));
}

// Issue 16: two outputs on one path (two files, a file of a folder, a folder on a file's
// path) are refused before the run, naming both options: the second was silently lost, or
// the run failed after its whole work.
TEST(OutputLocks, TwoOutputsOnOnePathAreRefusedBeforeTheRun) {
  const std::string dir = kTmp + "/two-outputs";
  fs::remove_all(dir);
  OdometryOptions o;
  o.input = kAbsent;
  o.progress = false;
  o.out_dir = dir + "/oz";
  o.features_out = dir + "/x";
  o.write_rawlog = dir + "/x";
  std::string e = errorOf([&] { OdometryApp(o).run(); });
  EXPECT_NE(e.find("--write-rawlog '" + dir + "/x' and --features-out '" + dir + "/x'"), std::string::npos) << e;
  o.features_out.clear();
  o.write_rawlog = dir + "/oz/summary.json";
  e = errorOf([&] { OdometryApp(o).run(); });
  EXPECT_NE(e.find("--write-rawlog '" + dir + "/oz/summary.json' and -o"), std::string::npos) << e;
  o.write_rawlog.clear();
  o.features_out = dir + "/oz/lidarseg.tum";
  EXPECT_THROW(OdometryApp(o).run(), UsageError);
  o.features_out = dir + "/oz/";
  EXPECT_THROW(OdometryApp(o).run(), UsageError);

  FeaturesOptions f;
  f.input = kAbsent;
  f.out_csv = dir + "/fo/features.csv";
  f.report_dir = dir + "/fo";
  f.rois_out = dir + "/fo/features.csv";
  e = errorOf([&] { FeaturesApp(f).run(); });
  EXPECT_NE(e.find("--out '" + dir + "/fo/features.csv' and --rois-out"), std::string::npos) << e;
  f.rois_out = dir + "/y.png";
  f.figure_path = dir + "/y.png";
  f.figure_scan = 0;
  EXPECT_THROW(FeaturesApp(f).run(), UsageError);
  f.figure_path.clear();
  f.figure_scan.reset();
  f.rois_out.clear();
  f.images_out = dir + "/fo/features.csv";
  e = errorOf([&] { FeaturesApp(f).run(); });
  EXPECT_NE(e.find("--images-out"), std::string::npos) << e;

  PeopleOptions p;
  p.input = kAbsent;
  p.rois = {"0,0,300,300"};
  p.out_csv = dir + "/po/people.csv";
  p.report_dir = dir + "/po";
  p.draw_dir = dir + "/po/people.csv";
  e = errorOf([&] { PeopleApp(p).run(); });
  EXPECT_NE(e.find("--out '" + dir + "/po/people.csv' and --draw"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(dir));  // nothing made
}

// Issue 16: the folder's files checked against the inputs are those this run writes: the
// ICP trajectory is written only with --baseline icp, so `--gt OUT/icp.tum -o OUT` without it
// is no collision (it was refused: every file any run may write was checked), and with it
// the ground truth would be overwritten: refused.
TEST(OutputLocks, OnlyTheFilesThisRunWritesAreCheckedAgainstTheInputs) {
  const std::string dir = kTmp + "/files-this-run-writes";
  fs::remove_all(dir);
  fs::create_directories(dir + "/oz");
  const std::string gt = dir + "/oz/icp.tum";
  std::ofstream(gt) << "0 0 0 0 0 0 0 1\n";
  OdometryOptions o;
  o.input = kAbsent;
  o.out_dir = dir + "/oz";
  o.gt_path = gt;
  o.progress = false;
  std::string e = errorOf([&] { OdometryApp(o).run(); });
  EXPECT_EQ(e.find("is the input"), std::string::npos) << e;
  EXPECT_NE(e.find(kAbsent), std::string::npos) << e;  // the run went on to its input
  o.baseline_icp = true;
  EXPECT_THROW(OdometryApp(o).run(), UsageError);
  e = errorOf([&] { OdometryApp(o).run(); });
  EXPECT_NE(e.find("-o '" + gt + "' is the input '" + gt + "'"), std::string::npos) << e;
  // The plots likewise: trajectories.png is checked only when the run draws.
  o.baseline_icp = false;
  o.gt_path.clear();
  o.auto_gt = false;
  o.relations_path = dir + "/oz/trajectories.png";
  std::ofstream(o.relations_path) << "x\n";
  e = errorOf([&] { OdometryApp(o).run(); });
  EXPECT_NE(e.find("is the input '" + o.relations_path + "'"), std::string::npos) << e;
  o.plots = false;
  e = errorOf([&] { OdometryApp(o).run(); });
  EXPECT_EQ(e.find("is the input"), std::string::npos) << e;
  EXPECT_EQ(slurp(gt), "0 0 0 0 0 0 0 1\n");
}

// Issue 16: an input inside a folder the tool fills with numbered files, named like one of
// them (the inspector's frames/scan_N.png, lidarseg-features' rois_NNNNNN.png, lidarseg-people's
// people_NNNNNN.png), is refused before the run: the check knew only the fixed names.
TEST(OutputLocks, AnInputNamedLikeANumberedFileOfAnOutputFolderIsRefused) {
  const std::string dir = kTmp + "/numbered";
  fs::remove_all(dir);
  fs::create_directories(dir + "/ir/frames");
  const std::string text = "FLASER 3 1 1 1 0 0 0 0 0 0 1 h 1\n";

  InspectOptions i;
  i.input = dir + "/ir/frames/scan_3.png";
  std::ofstream(i.input) << text;
  i.report_dir = dir + "/ir";
  EXPECT_THROW(InspectApp(i).run(), UsageError);
  std::string e = errorOf([&] { InspectApp(i).run(); });
  EXPECT_NE(e.find("-o '" + dir + "/ir' gets numbered files frames/scan_N.png, and the input '" + i.input +
                   "' is named like one"),
            std::string::npos)
      << e;
  EXPECT_EQ(slurp(i.input), text);
  // Not a numbered name, or not in the numbered files' subfolder: no collision.
  for (const std::string& other : {dir + "/ir/frames/scan_x.png", dir + "/ir/scan_3.png", dir + "/ir/frames/scan_3.svg"}) {
    std::ofstream(other) << text;
    i.input = other;
    e = errorOf([&] { InspectApp(i).run(); });
    EXPECT_EQ(e.find("numbered"), std::string::npos) << other << ": " << e;
  }

  FeaturesOptions f;
  f.input = dir + "/fi/rois_000002.png";
  fs::create_directories(dir + "/fi");
  std::ofstream(f.input) << text;
  f.out_csv = dir + "/fo.csv";
  f.images_out = dir + "/fi/";
  e = errorOf([&] { FeaturesApp(f).run(); });
  EXPECT_NE(e.find("--images-out '" + dir + "/fi/' gets numbered files rois_N.png"), std::string::npos) << e;

  PeopleOptions p;
  p.input = kAbsent;
  p.rois_path = dir + "/pd/people_12.png";
  fs::create_directories(dir + "/pd");
  std::ofstream(p.rois_path) << text;
  p.out_csv = dir + "/po.csv";
  p.draw_dir = dir + "/pd";
  e = errorOf([&] { PeopleApp(p).run(); });
  EXPECT_NE(e.find("--draw '" + dir + "/pd' gets numbered files people_N.png"), std::string::npos) << e;
  EXPECT_EQ(slurp(p.rois_path), text);
}

}  // namespace lidarseg::apps
