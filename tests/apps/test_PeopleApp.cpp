#include <algorithm>
#include <cstdio>
#include <fcntl.h>
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "TempFiles.h"
#include "ErrorOf.h"
#include "lidarseg/apps/FeaturesApp.h"
#include "lidarseg/apps/PeopleApp.h"
#include "lidarseg/apps/SimulateApp.h"

namespace lidarseg::apps {
namespace {
namespace fs = std::filesystem;
const std::string kTmp = std::string(LIDARSEG_TEST_TMP_DIR) + "/people";

// This test's own folder (see testing::testFolder).
std::string testDir() { return lidarseg::testing::testFolder(kTmp); }
const std::string kVideo = "/usr/share/doc/opencv-doc/examples/data/vtest.avi";

using lidarseg::testing::errorOf;

// The whole chain on a simulated hospital corridor: doors and corners of the lidar become
// regions of each camera image (lidarseg-features --rois-out / --images-out), and the
// people detector reads those regions back by file name.
TEST(PeopleApp, RegionsFromTheLidarDriveTheDetectorOnTheCameraImages) {
  fs::create_directories(kTmp);
  const std::string traj = testDir() + "/corridor.traj";
  std::ofstream(traj) << "speed 1.0\nturn_radius 0.6\nwaypoint 5 0\nwaypoint 15 0\n";
  SimulateOptions s;
  s.world_path = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/hospital.world";
  s.trajectory_path = traj;
  s.seed = 2;
  s.out_prefix = testDir() + "/corridor";
  s.camera_every_scans = 25;
  const SimulateReport sim = SimulateApp(s).run();
  ASSERT_GT(sim.images, 5u);

  FeaturesOptions f;
  f.input = s.out_prefix + ".rawlog";
  f.rois_out = testDir() + "/rois.csv";
  f.images_out = testDir() + "/rois_images";
  const FeaturesReport fr = FeaturesApp(f).run();
  // Every image but possibly the last (written after the last scan) is paired with a scan.
  EXPECT_GE(fr.images + 1, sim.images);
  EXPECT_GT(fr.images_with_rois, fr.images / 2);
  EXPECT_GT(fr.roi_coverage.median, 0.0);
  EXPECT_LT(fr.roi_coverage.median, 0.5);
  std::ifstream rois(f.rois_out);
  std::string line;
  std::getline(rois, line);
  EXPECT_EQ(line, "image,scan,t,file,feature,type,u_min,v_min,u_max,v_max,clipped");
  std::size_t rows = 0;
  while (std::getline(rois, line)) ++rows;
  EXPECT_EQ(rows, fr.rois);
  std::size_t drawn = 0;
  for (const auto& e : fs::directory_iterator(f.images_out)) drawn += e.path().extension() == ".png";
  EXPECT_GE(drawn, fr.images_with_rois);
  EXPECT_LE(drawn, fr.images);

  PeopleOptions p;
  p.input = s.out_prefix + "_Images";
  p.rois_path = f.rois_out;
  p.report_dir = testDir() + "/report";
  const PeopleReport pr = PeopleApp(p).run();
  EXPECT_EQ(pr.frames, sim.images);
  EXPECT_GT(pr.analysed_fraction.max, 0.0);
  EXPECT_LT(pr.analysed_fraction.median, 0.5);
  EXPECT_EQ(pr.people_full, 0u) << "the simulator draws no people";
  EXPECT_TRUE(fs::exists(p.report_dir + "/people.md"));
  EXPECT_TRUE(fs::exists(p.report_dir + "/people.json"));
}

// Real pedestrians (opencv-doc's vtest.avi) with regions given on the command line: the
// people the whole-frame detector finds inside the regions are found again.
TEST(PeopleApp, PeopleInsideCommandLineRegionsAreStillFoundOnARealVideo) {
  ASSERT_TRUE(fs::exists(kVideo)) << kVideo << " missing: run ./run.sh deps (package opencv-doc)";
  fs::create_directories(kTmp);
  PeopleOptions p;
  p.input = kVideo;
  p.rois = {"560,60,767,420", "180,130,330,300"};
  p.every = 20;
  p.max_frames = 12;
  p.out_csv = testDir() + "/vtest.csv";
  p.draw_dir = testDir() + "/vtest_frames";
  p.draw_every = 6;
  const PeopleReport r = PeopleApp(p).run();
  EXPECT_EQ(r.frames, 12u);
  EXPECT_EQ(r.frame_size, cv::Size(768, 576));
  EXPECT_GT(r.people_in_regions, 10u);
  EXPECT_GE(r.recallInRegions(), 0.8) << r.people_still_found << " of " << r.people_in_regions;
  EXPECT_GT(r.analysed_fraction.median, 0.2);
  EXPECT_LT(r.analysed_fraction.median, 0.6);
  EXPECT_LE(r.people_rois_confirmed, r.people_rois);
  std::ifstream csv(p.out_csv);
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "frame,mode,u_min,v_min,u_max,v_max,score");
  std::size_t rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, r.people_full + r.people_rois);
  EXPECT_TRUE(fs::exists(p.draw_dir + "/people_000000.png"));
  EXPECT_TRUE(fs::exists(p.draw_dir + "/people_000120.png"));
}

// Issue 16: a corrupt frame of a Motion-JPEG video is skipped and counted with its number in
// people.json and on stderr; the frames after it keep their numbers (their drawings' names).
TEST(PeopleApp, ACorruptMotionJpegFrameIsSkippedAndCountedInTheReport) {
  const std::string dir = testDir();
  const std::string path = dir + "/corrupt.avi";
  {
    cv::VideoWriter out(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10.0, cv::Size(160, 240));
    if (!out.isOpened()) GTEST_SKIP() << "this OpenCV cannot write an MJPEG video";
    for (int k = 0; k < 5; ++k) out.write(cv::Mat(240, 160, CV_8UC3, cv::Scalar(30.0 * k, 90, 150)));
  }
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::vector<std::size_t> soi;
  for (std::size_t i = 0; i + 1 < bytes.size(); ++i) {
    if (static_cast<unsigned char>(bytes[i]) == 0xFF && static_cast<unsigned char>(bytes[i + 1]) == 0xD8) soi.push_back(i);
  }
  ASSERT_EQ(soi.size(), 5u);
  bytes[soi[2] + 1] = 0x00;  // frame 2 is no JPEG image
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;

  PeopleOptions p;
  p.input = path;
  p.rois = {"0,0,79,119"};
  p.progress = false;
  p.report_dir = dir + "/report";
  p.draw_dir = dir + "/frames";
  p.draw_every = 1;
  const PeopleReport r = PeopleApp(p).run();
  EXPECT_EQ(r.frames, 4u);
  EXPECT_EQ(r.frames_skipped, 1u);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0].rfind("'" + path + "', frame 2: not a Motion-JPEG frame", 0), 0u) << r.warnings[0];
  std::ifstream json_in(p.report_dir + "/people.json");
  const std::string json((std::istreambuf_iterator<char>(json_in)), {});
  EXPECT_NE(json.find("\"frames_skipped\": 1"), std::string::npos) << json;
  EXPECT_NE(json.find("frame 2: not a Motion-JPEG frame"), std::string::npos) << json;
  EXPECT_TRUE(fs::exists(p.draw_dir + "/people_000003.png"));
  EXPECT_FALSE(fs::exists(p.draw_dir + "/people_000002.png")) << "frame 3 drawn under the number of the frame skipped";
  std::ostringstream err;
  PeopleApp::printWarnings(r, err);
  EXPECT_EQ(err.str(), "lidarseg-people: warning: 1 frames skipped, the first: " + r.warnings[0] + "\n");
}

// Issue 16: a region wholly outside the frame (a --roi made for another camera) analyses
// nothing; the run says so on stderr and in people.json instead of reporting a share of 0.
TEST(PeopleApp, ARegionWhollyOutsideTheFrameIsCountedAndWarned) {
  const std::string dir = testDir();
  const std::string images = dir + "/images";
  fs::create_directories(images);
  for (int k = 0; k < 3; ++k) {
    cv::imwrite(images + "/img" + std::to_string(k) + ".png", cv::Mat(240, 160, CV_8UC3, cv::Scalar(40.0 * k, 90, 150)));
  }
  PeopleOptions p;
  p.input = images;
  p.rois = {"0,0,79,119", "500,500,600,600", "160,0,200,50"};  // the last starts at the frame's right edge
  p.progress = false;
  p.report_dir = dir + "/report";
  const PeopleReport r = PeopleApp(p).run();
  EXPECT_EQ(r.frames, 3u);
  EXPECT_EQ(r.regions_outside, 6u);
  EXPECT_EQ(r.first_region_outside, "frame 0: region 500,500,600,600 outside the 160 x 240 frame");
  std::ostringstream err;
  PeopleApp::printWarnings(r, err);
  EXPECT_EQ(err.str(), "lidarseg-people: warning: 6 regions lie wholly outside their frame and were not analysed, "
                       "the first: frame 0: region 500,500,600,600 outside the 160 x 240 frame\n");
  std::ifstream json_in(p.report_dir + "/people.json");
  const std::string json((std::istreambuf_iterator<char>(json_in)), {});
  EXPECT_NE(json.find("\"regions_outside\": 6"), std::string::npos) << json;

  p.rois = {"0,0,79,119"};
  p.report_dir = dir + "/report-inside";
  const PeopleReport inside = PeopleApp(p).run();
  EXPECT_EQ(inside.regions_outside, 0u);
  EXPECT_EQ(inside.frames_with_regions, 3u);
  std::ostringstream none;
  PeopleApp::printWarnings(inside, none);
  EXPECT_EQ(none.str(), "");
}

// Issue 16: a regions file that names no frame or image of the input (another video's)
// analysed nothing inside regions with no word; the run now says so.
TEST(PeopleApp, RegionsNamingNoFrameOfTheInputAreNamedInAWarning) {
  const std::string dir = testDir();
  const std::string images = dir + "/images";
  fs::create_directories(images);
  for (int k = 0; k < 2; ++k) cv::imwrite(images + "/img" + std::to_string(k) + ".png", cv::Mat(240, 160, CV_8UC3, cv::Scalar(90)));
  const std::string table = dir + "/other.csv";
  std::ofstream(table) << "frame,u_min,v_min,u_max,v_max\n99,0,0,100,100\n";
  PeopleOptions p;
  p.input = images;
  p.rois_path = table;
  p.progress = false;
  const PeopleReport r = PeopleApp(p).run();
  EXPECT_EQ(r.frames, 2u);
  EXPECT_EQ(r.frames_with_regions, 0u);
  std::ostringstream err;
  PeopleApp::printWarnings(r, err);
  EXPECT_EQ(err.str(), "lidarseg-people: warning: no frame of the 2 analysed has a region of interest (the regions "
                       "name no frame or image of this input)\n");
}

// Issue 16: a Motion-JPEG frame whose JPEG data is cut (the second half of its scan, end of
// image included, zeroed) is skipped and counted in people.json, not analysed grey-filled.
TEST(PeopleApp, ATruncatedMotionJpegFrameIsSkippedAndCountedInTheReport) {
  const std::string dir = testDir();
  const std::string path = dir + "/truncated.avi";
  {
    cv::VideoWriter out(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10.0, cv::Size(160, 240));
    if (!out.isOpened()) GTEST_SKIP() << "this OpenCV cannot write an MJPEG video";
    for (int k = 0; k < 4; ++k) out.write(cv::Mat(240, 160, CV_8UC3, cv::Scalar(30.0 * k, 90, 150)));
  }
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::vector<std::size_t> sos, eoi;
  for (std::size_t i = 0; i + 1 < bytes.size(); ++i) {
    if (static_cast<unsigned char>(bytes[i]) != 0xFF) continue;
    if (static_cast<unsigned char>(bytes[i + 1]) == 0xDA) sos.push_back(i);
    if (static_cast<unsigned char>(bytes[i + 1]) == 0xD9) eoi.push_back(i);
  }
  ASSERT_EQ(sos.size(), 4u);
  ASSERT_EQ(eoi.size(), 4u);
  const std::size_t half = sos[1] + (eoi[1] + 2 - sos[1]) / 2;
  std::fill(bytes.begin() + static_cast<std::ptrdiff_t>(half), bytes.begin() + static_cast<std::ptrdiff_t>(eoi[1] + 2), '\0');
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;

  PeopleOptions p;
  p.input = path;
  p.rois = {"0,0,79,119"};
  p.progress = false;
  p.report_dir = dir + "/report-truncated";
  const PeopleReport r = PeopleApp(p).run();
  EXPECT_EQ(r.frames, 3u);
  EXPECT_EQ(r.frames_skipped, 1u);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0], "'" + path + "', frame 1: its JPEG data is truncated; frame skipped");
  std::ifstream json_in(p.report_dir + "/people.json");
  const std::string json((std::istreambuf_iterator<char>(json_in)), {});
  EXPECT_NE(json.find("\"frames_skipped\": 1"), std::string::npos) << json;
  EXPECT_NE(json.find("frame 1: its JPEG data is truncated; frame skipped"), std::string::npos) << json;
}

// Issue 16: a camera image whose header declares 20000 x 20000 pixels is refused before
// decoding, naming the file and the cap, by both tools that read images: lidarseg-features
// (a rawlog's externally stored images) skips it with that reason, lidarseg-people (a
// folder or one file) stops with it.
TEST(PeopleApp, AnImageDeclaringAHugeSizeIsRefusedByEveryTool) {
  const std::string dir = testDir() + "/huge";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string traj = dir + "/short.traj";
  std::ofstream(traj) << "speed 1.0\nturn_radius 0.6\nwaypoint 5 0\nwaypoint 7 0\n";
  SimulateOptions s;
  s.world_path = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/hospital.world";
  s.trajectory_path = traj;
  s.out_prefix = dir + "/sim";
  s.camera_every_scans = 10;
  ASSERT_GT(SimulateApp(s).run().images, 1u);
  const std::string image = s.out_prefix + "_Images/img_000000.png";
  std::string bytes;
  {
    std::ifstream in(image, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  ASSERT_GT(bytes.size(), 24u);
  for (std::size_t at : {16u, 20u}) {  // IHDR width and height, big-endian: 20000
    bytes[at] = 0;
    bytes[at + 1] = 0;
    bytes[at + 2] = static_cast<char>(0x4E);
    bytes[at + 3] = static_cast<char>(0x20);
  }
  std::ofstream(image, std::ios::binary) << bytes;

  // lidarseg-features skips an image it cannot read, with the reason, and draws the others.
  FeaturesOptions f;
  f.input = s.out_prefix + ".rawlog";
  f.images_out = dir + "/drawn";
  const FeaturesReport fr = FeaturesApp(f).run();
  ASSERT_GT(fr.images, 1u);
  std::string skipped;
  for (const std::string& m : fr.skipped) skipped += m + "\n";
  EXPECT_NE(skipped.find("image 0: '" + image + "': PNG image of 20000 x 20000 pixels"), std::string::npos)
      << skipped;
  EXPECT_NE(skipped.find("8192 x 8192"), std::string::npos) << skipped;
  EXPECT_FALSE(fs::exists(f.images_out + "/rois_000000.png"));
  EXPECT_TRUE(fs::exists(f.images_out + "/rois_000001.png"));

  // lidarseg-people: given alone, the image is the input and the run's error; in a folder it
  // is skipped and counted like a corrupt video frame, and the other images are read (a
  // reliability attack found one bad image ending a folder's run).
  PeopleOptions p;
  p.rois = {"0,0,10,10"};
  p.input = image;
  const std::string people_error = errorOf([&] { PeopleApp(p).run(); });
  EXPECT_NE(people_error.find("'" + image + "': PNG image of 20000 x 20000 pixels"), std::string::npos) << people_error;
  EXPECT_NE(people_error.find("8192 x 8192"), std::string::npos) << people_error;
  p.input = s.out_prefix + "_Images";
  const PeopleReport folder = PeopleApp(p).run();
  EXPECT_EQ(folder.frames_skipped, 1u);
  ASSERT_FALSE(folder.warnings.empty());
  EXPECT_NE(folder.warnings.front().find("'" + image + "': PNG image of 20000 x 20000 pixels"), std::string::npos)
      << folder.warnings.front();
  EXPECT_NE(folder.warnings.front().find("image skipped"), std::string::npos) << folder.warnings.front();
  EXPECT_GE(folder.frames, 1u);
}

TEST(PeopleApp, BadRegionsAndInputsAreNamed) {
  fs::create_directories(kTmp);
  PeopleOptions p;
  p.input = kTmp;
  EXPECT_NE(errorOf([&] { PeopleApp{p}; }).find("no regions of interest"), std::string::npos);
  p.rois = {"1,2,3"};
  EXPECT_NE(errorOf([&] { PeopleApp{p}; }).find("--roi '1,2,3'"), std::string::npos);
  p.rois = {"10,10,5,20"};
  EXPECT_NE(errorOf([&] { PeopleApp{p}; }).find("u_min <= u_max"), std::string::npos);

  const std::string no_column = testDir() + "/no_column.csv";
  std::ofstream(no_column) << "frame,u_min,v_min,u_max\n0,1,2,3\n";
  const std::string bad_line = testDir() + "/bad_line.csv";
  std::ofstream(bad_line) << "frame,u_min,v_min,u_max,v_max\n0,1,2,30,40\n1,1,two,30,40\n";
  const std::string short_line = testDir() + "/short_line.csv";
  std::ofstream(short_line) << "frame,u_min,v_min,u_max,v_max\n0,1,2,30\n";
  const std::string empty_dir = testDir() + "/empty_dir";
  fs::create_directories(empty_dir);
  {
    // A one-image input for the region errors to be reached.
    const std::string pgm = testDir() + "/one.pgm";
    std::ofstream(pgm, std::ios::binary) << "P5\n64 128\n255\n" << std::string(64 * 128, '\x80');
    p.input = pgm;
  }
  p.rois.clear();
  p.rois_path = no_column;
  EXPECT_NE(errorOf([&] { PeopleApp(p).run(); }).find("no_column.csv:1: no column 'v_max'"), std::string::npos)
      << errorOf([&] { PeopleApp(p).run(); });
  p.rois_path = bad_line;
  EXPECT_NE(errorOf([&] { PeopleApp(p).run(); }).find("bad_line.csv:3 v_min: 'two'"), std::string::npos)
      << errorOf([&] { PeopleApp(p).run(); });
  p.rois_path = short_line;
  EXPECT_NE(errorOf([&] { PeopleApp(p).run(); }).find("short_line.csv:2: 4 fields"), std::string::npos)
      << errorOf([&] { PeopleApp(p).run(); });
  p.rois_path = testDir() + "/absent.csv";
  EXPECT_NE(errorOf([&] { PeopleApp(p).run(); }).find("absent.csv"), std::string::npos);
  p.rois_path.clear();
  p.rois = {"0,0,10,10"};
  p.input = empty_dir;
  EXPECT_NE(errorOf([&] { PeopleApp(p).run(); }).find("empty_dir': no image files"), std::string::npos);
  p.input = testDir() + "/nothing_here.avi";
  EXPECT_NE(errorOf([&] { PeopleApp(p).run(); }).find("nothing_here.avi': no such file"), std::string::npos);
}

// Issue 16: an empty or broken file named as an image is read as an image and its error
// names it; it never reaches OpenCV's video backends, whose GStreamer and FFmpeg messages
// used to fill stderr before the error (the process's stderr is captured to check that).
TEST(PeopleApp, AnEmptyOrBrokenImageIsNamedWithoutTheVideoBackendsNoise) {
  const std::string dir = testDir();
  const std::string empty_png = dir + "/empty.png", broken_png = dir + "/broken.png", empty_avi = dir + "/empty.avi";
  std::ofstream(empty_png, std::ios::binary).flush();
  std::ofstream(broken_png, std::ios::binary) << "not a png at all, just text";
  std::ofstream(empty_avi, std::ios::binary).flush();
  const std::string captured = dir + "/stderr.txt";
  std::string empty_error, broken_error, avi_error;
  {
    std::fflush(stderr);
    const int saved = ::dup(2);
    ASSERT_GE(saved, 0);
    const int file = ::open(captured.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ASSERT_GE(file, 0);
    ::dup2(file, 2);
    ::close(file);
    PeopleOptions p;
    p.rois = {"0,0,10,10"};
    p.progress = false;
    p.input = empty_png;
    empty_error = errorOf([&] { PeopleApp(p).run(); });
    p.input = broken_png;
    broken_error = errorOf([&] { PeopleApp(p).run(); });
    p.input = empty_avi;
    avi_error = errorOf([&] { PeopleApp(p).run(); });
    std::fflush(stderr);
    ::dup2(saved, 2);
    ::close(saved);
  }
  EXPECT_EQ(empty_error, "'" + empty_png + "': empty file (no image or video)");
  EXPECT_EQ(broken_error, "cannot read image '" + broken_png + "' (not a PNG, JPEG, BMP or PNM file)");
  EXPECT_EQ(avi_error, "'" + empty_avi + "': empty file (no image or video)");
  std::ifstream in(captured);
  const std::string noise((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(noise, "");
}

}  // namespace
}  // namespace lidarseg::apps
