#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "TempFiles.h"
#include "EmptyPath.h"
#include "lidarseg/apps/InspectApp.h"
#include "lidarseg/apps/OdometryApp.h"
#include "lidarseg/apps/SimulateApp.h"
#include "lidarseg/inspect/Session.h"

namespace lidarseg::apps {
namespace {
namespace fs = std::filesystem;
const std::string kTmp = std::string(LIDARSEG_TEST_TMP_DIR) + "/inspect";

// This test's own folder (see testing::testFolder).
std::string testDir() { return lidarseg::testing::testFolder(kTmp); }

// 10 m of the hospital's corridor with a camera image every 10 scans, simulated once per
// test process under the test's own name (CTest runs the tests of this file in parallel).
const std::string& simulatedLog() {
  static const std::string log = [] {
    const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::create_directories(kTmp);
    const std::string traj = testDir() + "/corridor_" + name + ".traj";
    std::ofstream(traj) << "speed 1.0\nturn_radius 0.6\nwaypoint 5 0\nwaypoint 15 0\n";
    SimulateOptions o;
    o.world_path = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/hospital.world";
    o.trajectory_path = traj;
    o.seed = 4;
    o.out_prefix = testDir() + "/corridor_" + name;
    o.camera_every_scans = 10;
    SimulateApp(o).run();
    return o.out_prefix + ".rawlog";
  }();
  return log;
}

std::size_t pixelsOfColour(const cv::Mat& img, const cv::Vec3b& bgr, int tolerance) {
  std::size_t n = 0;
  for (int v = 0; v < img.rows; ++v) {
    for (int u = 0; u < img.cols; ++u) {
      const cv::Vec3b p = img.at<cv::Vec3b>(v, u);
      n += std::abs(p[0] - bgr[0]) <= tolerance && std::abs(p[1] - bgr[1]) <= tolerance &&
           std::abs(p[2] - bgr[2]) <= tolerance;
    }
  }
  return n;
}

// The inspector runs the same pipeline as lidarseg-odometry: the same poses, scan by scan.
void expectSamePosesAsTheOdometryApp(const std::string& log, std::size_t scans) {
  OdometryOptions o;
  o.input = log;
  o.config_path = std::string(LIDARSEG_CONFIG_DIR) + "/default.ini";
  o.max_scans = scans;
  o.progress = false;
  o.auto_gt = false;
  const OdometryReport report = OdometryApp(o).run();
  ASSERT_EQ(report.lidarseg.trajectory.size(), scans);
  inspect::Session session(log, "", inspect::InspectorParams::fromFile(o.config_path));
  const eval::StampedTrajectory poses = session.robotTrajectory(scans - 1);
  ASSERT_EQ(poses.size(), scans);
  double moved = 0.0;
  for (std::size_t k = 0; k < scans; ++k) {
    const auto& a = report.lidarseg.trajectory[k];
    EXPECT_DOUBLE_EQ(poses[k].stamp_s, a.stamp_s) << k;
    EXPECT_NEAR(poses[k].pose.x, a.pose.x, 1e-12) << k;
    EXPECT_NEAR(poses[k].pose.y, a.pose.y, 1e-12) << k;
    EXPECT_NEAR(poses[k].pose.yaw, a.pose.yaw, 1e-12) << k;
    moved = std::max(moved, std::hypot(a.pose.x, a.pose.y));
  }
  EXPECT_GT(moved, 0.5);  // the comparison covers a real motion, not a robot at rest
}

TEST(InspectSession, PosesEqualLidarsegOdometryOnARealLog) {
  expectSamePosesAsTheOdometryApp(
      std::string(LIDARSEG_MRPT_DATASETS_DIR) + "/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog", 80);
}

TEST(InspectSession, PosesEqualLidarsegOdometryOnASimulatedLog) { expectSamePosesAsTheOdometryApp(simulatedLog(), 60); }

TEST(InspectSession, ReadsOnDemandStepsBothWaysAndReprocessesOnNewParameters) {
  inspect::Session s(simulatedLog(), "", {});
  EXPECT_EQ(s.scansRead(), 1u) << "opening must not read the log";
  const inspect::Frame& f20 = s.frame(20);
  EXPECT_EQ(f20.index, 20u);
  EXPECT_LE(s.scansRead(), 22u) << "frame 20 read " << s.scansRead() << " scans";
  EXPECT_FALSE(s.complete());
  EXPECT_FALSE(f20.step.first);
  EXPECT_GT(f20.segmentation.levels[0].segments.size(), f20.segmentation.levels[3].segments.size());
  ASSERT_TRUE(f20.keyframe_segments);
  EXPECT_FALSE(f20.camera.empty()) << "scan 20 has a camera image";
  const std::size_t l0 = f20.segmentation.levels[0].segments.size();
  EXPECT_EQ(s.frame(19).index, 19u);
  EXPECT_EQ(s.frame(21).index, 21u);
  EXPECT_THROW(s.frame(100000), std::out_of_range);
  EXPECT_TRUE(s.complete());

  // A much coarser Wall-Danielsson threshold: fewer level-0 segments on the same scan.
  inspect::InspectorParams p = s.params();
  p.odometry.segmentation.wall_danielsson.threshold_m *= 20;
  s.setParams(p);
  EXPECT_LT(s.frame(20).segmentation.levels[0].segments.size(), l0);
  inspect::InspectorParams bad = s.params();
  bad.odometry.segmentation.wall_danielsson.threshold_m = -1;
  EXPECT_THROW(s.setParams(bad), std::invalid_argument);
  EXPECT_DOUBLE_EQ(s.params().odometry.segmentation.wall_danielsson.threshold_m,
                   p.odometry.segmentation.wall_danielsson.threshold_m);
  // The tuned set saved as INI is what the other apps read.
  const std::string ini = testDir() + "/tuned.ini";
  s.params().saveIni(ini);
  EXPECT_DOUBLE_EQ(inspect::InspectorParams::fromFile(ini).odometry.segmentation.wall_danielsson.threshold_m,
                   p.odometry.segmentation.wall_danielsson.threshold_m);
}

TEST(InspectApp, RendersPngAndSvgWithTheLayersAsked) {
  InspectOptions o;
  o.input = simulatedLog();
  o.frame = 150;
  o.render_out = testDir() + "/frame150.png";
  ASSERT_EQ(InspectApp(o).run(), 0);
  const cv::Mat all = cv::imread(o.render_out);
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(all.size(), cv::Size(1100, 850));
  // Doors are drawn red (220, 20, 20), corners green; the trajectory dark red.
  const std::size_t red = pixelsOfColour(all, {20, 20, 220}, 10);
  EXPECT_GT(red, 50u);
  o.layers = "raw";
  o.render_out = testDir() + "/frame150_raw.png";
  ASSERT_EQ(InspectApp(o).run(), 0);
  EXPECT_EQ(pixelsOfColour(cv::imread(o.render_out), {20, 20, 220}, 10), 0u);

  o.layers = "all";
  o.render_out = testDir() + "/frame150.svg";
  ASSERT_EQ(InspectApp(o).run(), 0);
  std::ifstream in(o.render_out);
  const std::string svg((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(svg.rfind("<svg ", 0), 0u);
  EXPECT_NE(svg.find("<line "), std::string::npos);
  EXPECT_NE(svg.find("stroke=\"#dc1414\""), std::string::npos) << "no door circle";
  EXPECT_NE(svg.find("scan 150"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);

  InspectOptions bad;
  bad.input = simulatedLog();
  bad.render_out = testDir() + "/x.jpg";
  EXPECT_THROW(InspectApp{bad}, std::invalid_argument);
  bad.render_out.clear();
  bad.layers = "raw,segments";
  try {
    InspectApp{bad};
    FAIL() << "unknown layer accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'segments'"), std::string::npos) << e.what();
  }
  o.layers.clear();
  o.frame = 1000000;
  o.render_out = testDir() + "/past.png";
  EXPECT_THROW(InspectApp(o).run(), std::out_of_range);
  EXPECT_FALSE(fs::exists(o.render_out));
}

TEST(InspectApp, ReportHasTheTablePlotsAndWorstFramesFirst) {
  InspectOptions o;
  o.input = simulatedLog();
  o.report_dir = testDir() + "/report";
  o.gallery = 5;
  InspectApp app(o);
  inspect::Session s(o.input, "", {});
  const std::string stem = o.input.substr(0, o.input.size() - 7);
  s.addReference({"ground truth", eval::readTum(stem + ".gt.tum")});
  const InspectReport r = app.writeReport(s);
  EXPECT_GT(r.scans, 400u);
  ASSERT_TRUE(r.final_error_m.has_value());
  EXPECT_LT(*r.final_error_m, 1.0);
  EXPECT_GT(r.length_m, 5.0);
  ASSERT_EQ(r.gallery.size(), 5u);
  std::ifstream in(o.report_dir + "/index.html");
  const std::string html((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(html.find("<table id=\"results\">"), std::string::npos);
  for (const char* f : {"trajectory.png", "error_over_time.png", "timing.png"}) {
    EXPECT_NE(html.find(f), std::string::npos) << f;
    EXPECT_GT(fs::file_size(o.report_dir + "/" + f), 1000u) << f;
  }
  for (std::size_t i : r.gallery) {
    const std::string png = "frames/scan_" + std::to_string(i) + ".png";
    EXPECT_NE(html.find(png), std::string::npos) << png;
    EXPECT_TRUE(fs::exists(o.report_dir + "/" + png)) << png;
  }
  // Worst first: the gallery's order follows the table's.
  EXPECT_LT(html.find("scan_" + std::to_string(r.gallery[0]) + ".png"),
            html.find("scan_" + std::to_string(r.gallery[1]) + ".png"));
  // A second report of fewer frames into the folder leaves none of the first's (issue 16:
  // frames/ held both galleries); a file of another name stays.
  std::ofstream(o.report_dir + "/frames/notes.txt") << "the user's";
  o.gallery = 2;
  const InspectReport again = InspectApp(o).writeReport(s);
  std::vector<std::string> frames;
  for (const auto& e : fs::directory_iterator(o.report_dir + "/frames")) {
    const std::string name = e.path().filename().string();
    if (name[0] != '.') frames.push_back(name);  // not the folder's lock
  }
  std::sort(frames.begin(), frames.end());
  std::vector<std::string> expected = {"notes.txt"};
  for (std::size_t i : again.gallery) expected.push_back("scan_" + std::to_string(i) + ".png");
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(frames, expected);
}

// Without gnuplot the report is still written, table and gallery, with a warning on stderr
// and a line in the page saying why there are no plots (no broken images).
TEST(InspectApp, ReportWithoutGnuplotHasNoPlotsAndSaysWhy) {
  InspectOptions o;
  o.input = simulatedLog();
  o.report_dir = testDir() + "/report";
  o.gallery = 2;
  o.progress = false;
  InspectApp app(o);
  inspect::Session s(o.input, "", {});
  ::testing::internal::CaptureStderr();
  {
    const lidarseg::testing::EmptyPath no_gnuplot;
    app.writeReport(s);
  }
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("lidarseg-inspect: warning: no plots in the report: gnuplot is not installed"), std::string::npos)
      << err;
  std::ifstream in(o.report_dir + "/index.html");
  const std::string html((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(html.find("<table id=\"results\">"), std::string::npos);
  EXPECT_NE(html.find("<p>No plots: gnuplot is not installed"), std::string::npos);
  for (const char* f : {"trajectory.png", "error_over_time.png", "timing.png"}) {
    EXPECT_EQ(html.find(f), std::string::npos) << f;
    EXPECT_FALSE(fs::exists(o.report_dir + "/" + f)) << f;
  }
  EXPECT_NE(html.find("frames/scan_"), std::string::npos);  // the gallery is still there
}

// Another log's ground truth (no pose within the scans' span): a warning naming the file and
// both spans, the truth left out of the figures, and the plots still drawn (gnuplot refused
// the error plot's empty series and the report lost every plot; issue 16).
TEST(InspectApp, AnotherLogsGroundTruthIsLeftOutWithAWarningAndThePlotsStay) {
  InspectOptions o;
  o.input = simulatedLog();
  o.report_dir = testDir() + "/report";
  o.gallery = 2;
  o.progress = false;
  InspectApp app(o);
  inspect::Session s(o.input, "", {});
  eval::StampedTrajectory truth = eval::readTum(o.input.substr(0, o.input.size() - 7) + ".gt.tum");
  ASSERT_GT(truth.size(), 2u);
  for (auto& p : truth) p.stamp_s += 1.0e5;  // a day later: another run's clock
  s.addReference({"ground truth", truth});
  ::testing::internal::CaptureStderr();
  const InspectReport r = app.writeReport(s);
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("lidarseg-inspect: warning: ground truth"), std::string::npos) << err;
  EXPECT_NE(err.find(" 0 of the "), std::string::npos) << err;
  EXPECT_NE(err.find("truth from "), std::string::npos) << err;
  EXPECT_EQ(err.find("no plots"), std::string::npos) << err;
  EXPECT_FALSE(r.final_error_m.has_value());
  EXPECT_FALSE(r.truth_problem.empty());
  EXPECT_TRUE(r.no_plots.empty()) << r.no_plots;
  std::ifstream in(o.report_dir + "/index.html");
  const std::string html((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(html.find("Ground truth left out"), std::string::npos);
  EXPECT_NE(html.find("Match uncertainty over time"), std::string::npos);  // the plot without the truth
  for (const char* f : {"trajectory.png", "error_over_time.png", "timing.png"}) {
    EXPECT_NE(html.find(f), std::string::npos) << f;
    EXPECT_GT(fs::file_size(o.report_dir + "/" + f), 1000u) << f;
  }
}

// The inspector finds the ground truth beside a CARMEN log as beside a rawlog, as
// lidarseg-odometry does: PREFIX.gt.tum beside the simulator's PREFIX.carmen.log, and
// NAME.gt.tum beside NAME.log (issue 15).
TEST(InspectApp, FindsTheGroundTruthBesideACarmenLogAsTheOdometryDoes) {
  const std::string dir = testDir();
  const std::string traj = dir + "/short.traj";
  std::ofstream(traj) << "speed 1.0\nturn_radius 0.6\nwaypoint 5 0\nwaypoint 8 0\n";
  SimulateOptions sim;
  sim.world_path = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/hospital.world";
  sim.trajectory_path = traj;
  sim.out_prefix = dir + "/sim";
  sim.camera_every_scans = 0;
  sim.write_carmen = true;
  SimulateApp(sim).run();
  const std::string truth = sim.out_prefix + ".gt.tum";
  const std::size_t truth_poses = eval::readTum(truth).size();
  ASSERT_GT(truth_poses, 0u);
  fs::copy_file(sim.out_prefix + ".carmen.log", dir + "/copy.log", fs::copy_options::overwrite_existing);
  fs::copy_file(truth, dir + "/copy.gt.tum", fs::copy_options::overwrite_existing);
  for (const std::string& log : {sim.out_prefix + ".carmen.log", dir + "/copy.log", sim.out_prefix + ".rawlog"}) {
    InspectOptions o;
    o.input = log;
    const auto session = InspectApp(o).open();
    ASSERT_EQ(session->references().size(), 1u) << log;
    EXPECT_EQ(session->references()[0].name, "ground truth") << log;
    EXPECT_EQ(session->references()[0].poses.size(), truth_poses) << log;
    OdometryOptions odometry;
    odometry.input = log;
    odometry.progress = false;
    odometry.max_scans = 5;
    EXPECT_FALSE(OdometryApp(odometry).run().gt_path.empty()) << log;
  }
}

TEST(InspectApp, KeysAreListed) {
  const auto keys = InspectApp::keyHelp();
  std::string all;
  for (const auto& k : keys) all += k + "\n";
  for (const char* needle : {"next scan", "go to scan", "play", "W-D threshold", "save parameters", "quit"}) {
    EXPECT_NE(all.find(needle), std::string::npos) << needle;
  }
}

}  // namespace
}  // namespace lidarseg::apps
