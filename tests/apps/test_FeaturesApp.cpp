#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>

#include "TempFiles.h"
#include "lidarseg/apps/FeaturesApp.h"
#include "lidarseg/apps/OdometryApp.h"
#include "lidarseg/apps/SimulateApp.h"
#include "lidarseg/vision/ImageFile.h"
#include "EmptyPath.h"

namespace lidarseg::apps {
namespace {
namespace fs = std::filesystem;
const std::string kWorlds = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/";
const std::string kTmp = std::string(LIDARSEG_TEST_TMP_DIR) + "/features";

// This test's own folder (see testing::testFolder).
std::string testDir() { return lidarseg::testing::testFolder(kTmp); }

// 12 m of the hospital's bottom corridor (doors of every kind on both sides), simulated
// once per test process under the test's own name.
const std::string& simulatedPrefix() {
  static const std::string prefix = [] {
    const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::create_directories(kTmp);
    const std::string traj = testDir() + "/corridor.traj";
    std::ofstream(traj) << "speed 1.0\nturn_radius 0.6\nwaypoint 5 0\nwaypoint 17 0\n";
    SimulateOptions o;
    o.world_path = kWorlds + "hospital.world";
    o.trajectory_path = traj;
    o.seed = 5;
    o.out_prefix = testDir() + "/corridor_" + name;
    o.camera_every_scans = 0;
    SimulateApp(o).run();
    return o.out_prefix;
  }();
  return prefix;
}

TEST(FeaturesApp, FindsTheHospitalsDoorsAndCornersAndWritesTheFiles) {
  const std::string prefix = simulatedPrefix();
  FeaturesOptions o;
  o.input = prefix + ".rawlog";
  o.truth_path = prefix + ".features.csv";
  o.out_csv = testDir() + "/found.csv";
  o.report_dir = testDir() + "/report";
  o.figure_scan = 100;
  o.figure_path = testDir() + "/scan100.png";
  const FeaturesReport r = FeaturesApp(o).run();
  EXPECT_GT(r.scans, 500u);
  ASSERT_TRUE(r.evaluation.has_value());
  const auto& ev = *r.evaluation;
  EXPECT_GT(ev.doors().truths, 100u);
  EXPECT_GE(ev.doors().recall(), 0.85);
  EXPECT_GE(ev.doors().precision(), 0.9);
  EXPECT_GT(ev.corners().truths, 20u);
  EXPECT_GE(ev.corners().recall(), 0.85);
  EXPECT_GE(ev.corners().precision(), 0.9);
  EXPECT_LT(r.position_error_m.median, 0.05);
  // The CSV: the documented columns first, one line per detection.
  std::ifstream csv(o.out_csv);
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("t,type,x,y,theta,width,confidence,", 0), 0u) << header;
  std::size_t lines = 0;
  while (std::getline(csv, line)) ++lines;
  std::size_t detections = 0;
  for (std::size_t n : r.detections) detections += n;
  EXPECT_EQ(lines, detections);
  EXPECT_TRUE(fs::exists(o.report_dir + "/features.md"));
  EXPECT_TRUE(fs::exists(o.report_dir + "/features.json"));
  // The paper's Fig. 6: a PNG of the figure's width (two panels drawn by gnuplot).
  const auto figure = vision::readImageHeader(o.figure_path);
  ASSERT_TRUE(figure.has_value()) << o.figure_path;
  EXPECT_EQ(figure->format, "PNG");
  EXPECT_EQ(figure->width, 1600u);
  EXPECT_GE(figure->height, 300u);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
}

// Without gnuplot the run goes on: a warning naming the figure and gnuplot, on stderr, none
// on stdout, and no file.
TEST(FeaturesApp, AFigureThatCannotBeDrawnIsAWarningAndNoFile) {
  const std::string prefix = simulatedPrefix();
  FeaturesOptions o;
  o.input = prefix + ".rawlog";
  o.max_scans = 40;
  o.progress = false;
  o.figure_scan = 20;
  o.figure_path = testDir() + "/scan20.png";
  FeaturesReport r;
  {
    const lidarseg::testing::EmptyPath no_gnuplot;
    r = FeaturesApp(o).run();
  }
  EXPECT_EQ(r.scans, 40u);
  EXPECT_FALSE(fs::exists(o.figure_path));
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("scan20.png"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("gnuplot is not installed"), std::string::npos) << r.warnings[0];
  std::ostringstream out, err;
  FeaturesApp::print(r, out);
  FeaturesApp::printWarnings(r, err);
  EXPECT_EQ(out.str().find("warning"), std::string::npos) << out.str();
  EXPECT_EQ(err.str(), "lidarseg-features: warning: " + r.warnings[0] + "\n");

}

// A figure gnuplot fails to draw was a warning with an empty reason (gnuplot's message starts
// with a blank line), exit 0 (issue 16). It is now the run's error, with what gnuplot said,
// raised once the other outputs are written. A stand-in gnuplot fails the way gnuplot does.
TEST(FeaturesApp, AFigureGnuplotFailsToDrawIsAnErrorWithGnuplotsReason) {
  const std::string prefix = simulatedPrefix();
  const std::string dir = testDir() + "/figure-fails";
  const std::string bin = testDir() + "/failing-gnuplot";
  fs::remove_all(dir);
  fs::create_directories(bin);
  std::ofstream(bin + "/gnuplot") << "#!/bin/sh\necho >&2\necho \"set title 'x\" >&2\necho '          ^' >&2\n"
                                  << "echo '\"plot.gp\" line 4: invalid character' >&2\nexit 1\n";
  fs::permissions(bin + "/gnuplot", fs::perms::owner_all);
  FeaturesOptions o;
  o.input = prefix + ".rawlog";
  o.max_scans = 10;
  o.progress = false;
  o.figure_scan = 2;
  o.figure_path = dir + "/scan2.png";
  o.out_csv = dir + "/features.csv";
  o.report_dir = dir;
  const char* old_path = std::getenv("PATH");
  const std::string saved = old_path != nullptr ? old_path : "";
  ::setenv("PATH", bin.c_str(), 1);
  std::string m;
  try {
    FeaturesApp(o).run();
  } catch (const std::runtime_error& e) {
    m = e.what();
  }
  ::setenv("PATH", saved.c_str(), 1);
  EXPECT_EQ(m, "--figure '" + o.figure_path + "' not written: gnuplot failed to draw a plot: set title 'x / "
               "\"plot.gp\" line 4: invalid character; the other outputs are");
  EXPECT_FALSE(fs::exists(o.figure_path));
  EXPECT_TRUE(fs::exists(dir + "/features.csv"));
  // A gnuplot that says nothing still gives a reason.
  std::ofstream(bin + "/gnuplot") << "#!/bin/sh\nexit 3\n";
  ::setenv("PATH", bin.c_str(), 1);
  m.clear();
  try {
    FeaturesApp(o).run();
  } catch (const std::runtime_error& e) {
    m = e.what();
  }
  ::setenv("PATH", saved.c_str(), 1);
  EXPECT_NE(m.find("gnuplot failed to draw a plot: gnuplot exited with status 3 and said nothing"), std::string::npos) << m;
}

// An input whose name holds a newline broke the figure's gnuplot script (its title): the
// control character is drawn as a space.
TEST(FeaturesApp, AFigureOfAnInputNamedWithANewlineIsDrawn) {
  const std::string prefix = simulatedPrefix();
  const std::string dir = testDir() + "/figure-newline";
  fs::remove_all(dir);
  fs::create_directories(dir);
  FeaturesOptions o;
  o.input = dir + "/two\nlines.rawlog";
  fs::copy_file(prefix + ".rawlog", o.input);
  o.max_scans = 5;
  o.progress = false;
  o.figure_scan = 2;
  o.figure_path = dir + "/scan2.png";
  o.out_csv = dir + "/features.csv";
  o.report_dir = dir;
  const FeaturesReport r = FeaturesApp(o).run();
  for (const std::string& w : r.warnings) {
    if (w.find("gnuplot is not installed") != std::string::npos) GTEST_SKIP() << w;
  }
  for (const std::string& w : r.warnings) EXPECT_EQ(w.find("figure"), std::string::npos) << w;
  EXPECT_TRUE(fs::exists(o.figure_path));
}

// A scan the log does not reach is an error, as `lidarseg-inspect -f` past the log is, raised
// once the other outputs are written: the figure is what the user asked for, and nothing
// else is lost.
TEST(FeaturesApp, AFigureScanPastTheLogIsAnErrorAfterTheOtherOutputs) {
  const std::string prefix = simulatedPrefix();
  const std::string dir = testDir() + "/figure-past";
  fs::remove_all(dir);
  FeaturesOptions o;
  o.input = prefix + ".rawlog";
  o.max_scans = 40;
  o.progress = false;
  o.figure_scan = 100;  // past the 40 scans read
  o.figure_path = testDir() + "/scan100-past.png";
  o.out_csv = dir + "/features.csv";
  o.report_dir = dir;
  fs::remove(o.figure_path);
  try {
    FeaturesApp(o).run();
    FAIL() << "a figure scan past the log ran to the end";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--figure-scan 100: no such scan among the 40 scans read from " + o.input), std::string::npos) << m;
    EXPECT_NE(m.find("scan100-past.png not written"), std::string::npos) << m;
  }
  EXPECT_FALSE(fs::exists(o.figure_path));
  EXPECT_TRUE(fs::exists(dir + "/features.csv"));
  EXPECT_TRUE(fs::exists(dir + "/features.json"));
}

// Issue 16: another log's truth (its scans stamped otherwise) was scored as this log's with
// no word; the run now says so. Its own truth gives no such warning.
TEST(FeaturesApp, ATruthStampedOtherwiseThanTheLogIsNamedInAWarning) {
  const std::string prefix = simulatedPrefix();
  const std::string shifted = testDir() + "/shifted.features.csv";
  {
    std::ifstream in(prefix + ".features.csv");
    std::ofstream out(shifted);
    std::string line;
    std::getline(in, line);
    out << line << '\n';
    while (std::getline(in, line)) {
      const auto a = line.find(','), b = line.find(',', a + 1);
      out << line.substr(0, a + 1) << std::setprecision(17) << std::stod(line.substr(a + 1, b - a - 1)) + 100.0
          << line.substr(b) << '\n';
    }
  }
  FeaturesOptions o;
  o.input = prefix + ".rawlog";
  o.max_scans = 40;
  o.progress = false;
  o.truth_path = prefix + ".features.csv";
  const FeaturesReport own = FeaturesApp(o).run();
  EXPECT_TRUE(own.warnings.empty()) << own.warnings.front();
  o.truth_path = shifted;
  const FeaturesReport other = FeaturesApp(o).run();
  ASSERT_EQ(other.warnings.size(), 1u);
  EXPECT_EQ(other.warnings[0].rfind("--gt " + shifted + ": the truth of ", 0), 0u) << other.warnings[0];
  EXPECT_NE(other.warnings[0].find("is stamped more than 1 ms from the scan of its number"), std::string::npos)
      << other.warnings[0];
}

TEST(FeaturesApp, BadInputsAreNamed) {
  const std::string prefix = simulatedPrefix();
  FeaturesOptions o;
  o.input = testDir() + "/no-such.rawlog";
  EXPECT_THROW(FeaturesApp(o).run(), std::exception);
  o.input = prefix + ".rawlog";
  o.truth_path = testDir() + "/bad_truth.csv";
  std::ofstream(o.truth_path) << "scan,t,type,x,y,theta,width,id\n0,1,door,1,2,0,1,0\n";
  try {
    FeaturesApp(o).run();
    FAIL() << "accepted a bad truth file";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("bad_truth.csv:2"), std::string::npos) << e.what();
  }
  o.truth_path.clear();
  o.config_path = testDir() + "/bad.ini";
  std::ofstream(o.config_path) << "[features]\ndoor_min_width_m = -1\n";
  try {
    FeaturesApp(o).run();
    FAIL() << "accepted a negative door width";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("door_min_width_m"), std::string::npos) << e.what();
  }
}

TEST(FeaturesApp, OdometryWritesTheFeaturesAndLandmarksForMrptsSlam) {
  const std::string prefix = simulatedPrefix();
  OdometryOptions o;
  o.input = prefix + ".rawlog";
  o.progress = false;
  o.features_out = testDir() + "/odometry_features.csv";
  o.write_rawlog = testDir() + "/odometry_landmarks.rawlog";
  o.write_landmarks = true;
  OdometryApp(o).run();
  // The same detections as lidarseg-features on the same log (same defaults), row for row
  // in count.
  std::ifstream csv(o.features_out);
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("t,type,x,y,theta,width,confidence,", 0), 0u) << header;
  std::size_t rows = 0, doors = 0;
  while (std::getline(csv, line)) {
    ++rows;
    doors += line.find(",door_") != std::string::npos ? 1 : 0;
  }
  EXPECT_GT(rows, 300u);
  EXPECT_GT(doors, 100u);
  // Every sensory frame of the written rawlog holds one range-bearing observation, whose
  // landmarks have positive ranges and finite covariances.
  mrpt::obs::CRawlog rawlog;
  ASSERT_TRUE(rawlog.loadFromRawLogFile(o.write_rawlog));
  std::size_t frames = 0, landmarks = 0;
  for (std::size_t i = 0; i < rawlog.size(); ++i) {
    if (rawlog.getType(i) != mrpt::obs::CRawlog::etSensoryFrame) continue;
    ++frames;
    const auto sf = rawlog.getAsObservations(i);
    const auto br = sf->getObservationByClass<mrpt::obs::CObservationBearingRange>();
    ASSERT_TRUE(br) << "frame " << i;
    EXPECT_TRUE(br->validCovariances);
    for (const auto& m : br->sensedData) {
      ++landmarks;
      EXPECT_GT(m.range, 0.0f);
      EXPECT_EQ(m.landmarkID, -1);
      EXPECT_GT(m.covariance(0, 0), 0.0);
      EXPECT_GT(m.covariance(1, 1), 0.0);
    }
  }
  EXPECT_GT(frames, 500u);
  EXPECT_EQ(landmarks, rows);
}

// Issue 16: --figure (a file outside -o) is published with the run's other outputs, never
// while the log is read: a run that fails after drawing it (a truncated log here; SIGINT in
// the reproduction) leaves the figure of the previous run, like its CSV files.
TEST(FeaturesApp, TheFigureIsPublishedWithTheOtherOutputsOnlyWhenTheRunSucceeds) {
  const std::string prefix = simulatedPrefix();
  const std::string dir = testDir() + "/figure-with-set";
  fs::remove_all(dir);
  fs::create_directories(dir);
  FeaturesOptions o;
  o.input = prefix + ".rawlog";
  o.figure_scan = 0;
  o.figure_path = dir + "/x.png";
  o.rois_out = dir + "/x.csv";
  o.progress = false;
  FeaturesApp(o).run();
  ASSERT_TRUE(fs::exists(o.figure_path));
  const auto slurp = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string first_png = slurp(o.figure_path);
  const std::string first_csv = slurp(o.rois_out);

  // The same log cut in the middle of an entry: scan 30 is read and drawn, then the error.
  const std::string cut = dir + "/cut.rawlog";
  fs::copy_file(o.input, cut);
  fs::resize_file(cut, fs::file_size(cut) * 3 / 5 + 7);
  o.input = cut;
  o.figure_scan = 30;
  EXPECT_THROW(FeaturesApp(o).run(), std::exception);
  EXPECT_EQ(slurp(o.figure_path), first_png) << "the figure was replaced by a run that failed";
  EXPECT_EQ(slurp(o.rois_out), first_csv);
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
  }
}

}  // namespace
}  // namespace lidarseg::apps
