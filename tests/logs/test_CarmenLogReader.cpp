#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <utility>
#include <vector>

#include <zlib.h>

#include "lidarseg/logs/CarmenLogReader.h"
#include "lidarseg/logs/CarmenScan.h"

using namespace lidarseg;
using namespace lidarseg::logs;

namespace {

std::string tmp(const std::string& name) { return std::string(LIDARSEG_TEST_TMP_DIR) + "/" + name; }

std::string writeText(const std::string& name, const std::string& text) {
  std::ofstream(tmp(name), std::ios::binary) << text;
  return tmp(name);
}

std::string writeGz(const std::string& name, const std::string& text) {
  gzFile f = gzopen(tmp(name).c_str(), "wb");
  gzwrite(f, text.data(), static_cast<unsigned>(text.size()));
  gzclose(f);
  return tmp(name);
}

std::string flaser(int n, double r, double x, double ts) {
  std::string s = "FLASER " + std::to_string(n);
  for (int i = 0; i < n; ++i) s += " " + std::to_string(r);
  s += " " + std::to_string(x) + " 0.5 0.1 " + std::to_string(x + 1) + " 0 0 " + std::to_string(ts) + " host " +
       std::to_string(ts) + "\n";
  return s;
}

}  // namespace

TEST(CarmenLogReader, ReadsFlaserFieldsAndGeometry) {
  const std::string log = "# comment\nPARAM robot_front_laser_max 30 host 0\n" + flaser(181, 2.5, 1.0, 10.25) +
                          flaser(180, 3.0, 2.0, 10.5);
  const std::string path = writeText("a.log", log);
  CarmenLogReader reader(path);
  auto a = reader.next();
  ASSERT_TRUE(a);
  EXPECT_EQ(a->type, "FLASER");
  EXPECT_EQ(a->line, 3u);
  EXPECT_DOUBLE_EQ(a->stamp_s, 10.25);
  ASSERT_EQ(a->ranges_m.size(), 181u);
  EXPECT_DOUBLE_EQ(a->ranges_m[0], 2.5);
  EXPECT_NEAR(a->start_angle_rad, -M_PI / 2, 1e-12);
  EXPECT_NEAR(a->angular_resolution_rad, M_PI / 180, 1e-12);  // 181 beams: both ends
  EXPECT_DOUBLE_EQ(a->max_range_m, 30.0);
  EXPECT_DOUBLE_EQ(a->laser_pose.x, 1.0);
  EXPECT_DOUBLE_EQ(a->laser_pose.y, 0.5);
  EXPECT_DOUBLE_EQ(a->robot_pose.x, 2.0);
  auto b = reader.next();
  ASSERT_TRUE(b);
  EXPECT_NEAR(b->angular_resolution_rad, M_PI / 180, 1e-12);  // 180 beams over 180 degrees
  EXPECT_FALSE(reader.next());
  EXPECT_EQ(reader.malformedLines(), 0u);
}

TEST(CarmenLogReader, GzipAndPlainGiveTheSameRecords) {
  const std::string text = flaser(5, 1.0, 0.0, 1.0) + "ODOM 1 2 0.3 0 0 0 1.5 h 1.5\n" + flaser(5, 2.0, 1.0, 2.0);
  CarmenLogReader plain(writeText("b.log", text)), gz(writeGz("b.log.gz", text));
  for (int k = 0; k < 2; ++k) {
    auto p = plain.next(), g = gz.next();
    ASSERT_TRUE(p && g);
    EXPECT_EQ(p->ranges_m, g->ranges_m);
    EXPECT_EQ(p->line, g->line);
  }
  ASSERT_TRUE(gz.lastOdometry());
  EXPECT_DOUBLE_EQ(gz.lastOdometry()->y, 2.0);
  EXPECT_FALSE(gz.next());
}

// The share of the file read (a progress's time left): from 0, never back, small after the
// first line of a 2 MB log (64 KiB read ahead), about half at the middle one, 1 at the end;
// the same for gzip (compressed bytes).
TEST(CarmenLogReader, TheShareReadGrowsToOne) {
  std::string text;
  for (int k = 0; k < 1500; ++k) text += flaser(181, 2.0 + 0.001 * k, 0.01 * k, 1.0 + 0.1 * k);
  ASSERT_GT(text.size(), std::size_t{2} << 20);
  for (const std::string& path : {writeText("share.log", text), writeGz("share.log.gz", text)}) {
    CarmenLogReader reader(path);
    EXPECT_EQ(reader.fractionRead(), 0.0) << path;
    double last = 0.0, after_first = -1.0, middle = -1.0;
    std::size_t n = 0;
    while (reader.next()) {
      const double f = reader.fractionRead();
      EXPECT_GE(f, last) << path << " record " << n;
      if (n == 0) after_first = f;
      if (n == 750) middle = f;
      ++n;
      last = f;
    }
    EXPECT_EQ(n, 1500u);
    EXPECT_GT(after_first, 0.0) << path;
    EXPECT_LT(after_first, 0.2) << path;
    EXPECT_GT(middle, 0.4) << path;
    EXPECT_LT(middle, 0.6) << path;
    EXPECT_DOUBLE_EQ(last, 1.0) << path;
  }
}

TEST(CarmenLogReader, MalformedLinesAreSkippedWithTheirLineAndUnknownTypesCounted) {
  const std::string text = flaser(5, 1.0, 0.0, 1.0) +      // line 1: good
                           "FLASER 5 1 2 3\n" +              // line 2: too few fields
                           "FLASER 3 1 x 3 0 0 0 0 0 0 3 h 3\n" +  // line 3: not a number
                           "FLASER -2 0 0 0 0 0 0 0 0 h 0\n" +     // line 4: bad count
                           "WEIRDTYPE 1 2 3\nWEIRDTYPE\nNEFF 1 2\n" + flaser(5, 1.0, 0.0, 4.0);
  CarmenLogReader reader(writeText("c.log", text));
  int good = 0;
  while (reader.next()) ++good;
  EXPECT_EQ(good, 2);
  EXPECT_EQ(reader.malformedLines(), 3u);
  ASSERT_EQ(reader.issues().size(), 3u);
  EXPECT_NE(reader.issues()[0].find("c.log:2"), std::string::npos) << reader.issues()[0];
  EXPECT_NE(reader.issues()[1].find("c.log:3"), std::string::npos) << reader.issues()[1];
  EXPECT_NE(reader.issues()[1].find("'x'"), std::string::npos) << reader.issues()[1];
  EXPECT_NE(reader.issues()[2].find("c.log:4"), std::string::npos) << reader.issues()[2];
  ASSERT_EQ(reader.unknownTypes().count("WEIRDTYPE"), 1u);
  EXPECT_EQ(reader.unknownTypes().at("WEIRDTYPE"), 2u);
  EXPECT_EQ(reader.unknownTypes().count("NEFF"), 0u);
}

TEST(CarmenLogReader, SickErrorCodesAreNoReturn) {
  std::string line = "FLASER 4 1.0 81.91 32.767 81.83 0 0 0 0 0 0 1 h 1\n";
  CarmenLogReader reader(writeText("d.log", line));
  auto a = reader.next();
  ASSERT_TRUE(a);
  EXPECT_DOUBLE_EQ(a->ranges_m[0], 1.0);
  EXPECT_TRUE(std::isinf(a->ranges_m[1]));
  EXPECT_TRUE(std::isinf(a->ranges_m[2]));
  EXPECT_TRUE(std::isinf(a->ranges_m[3]));
}

TEST(CarmenLogReader, RobotLaser1AndTypeSelection) {
  // ROBOTLASER1 type start fov res maxr acc rem n r.. nrem laser(3) robot(3) tv rv fs ss ta ts host lts
  const std::string rl = "ROBOTLASER1 0 -1.5 3.0 0.5 20 0.01 0 7 1 1 1 1 1 1 1 0 1 2 0.5 0.9 2 0.5 0 0 0 0 0 5.5 h 5.5\n";
  const std::string text = flaser(5, 1.0, 0.0, 1.0) + rl;
  CarmenLogReader reader(writeText("e.log", text), {"ROBOTLASER1", 50.0});
  auto a = reader.next();
  ASSERT_TRUE(a);
  EXPECT_EQ(a->type, "ROBOTLASER1");
  EXPECT_EQ(a->ranges_m.size(), 7u);
  EXPECT_DOUBLE_EQ(a->start_angle_rad, -1.5);
  EXPECT_DOUBLE_EQ(a->angular_resolution_rad, 0.5);
  EXPECT_DOUBLE_EQ(a->stamp_s, 5.5);
  // Laser at (1, 2), robot at (0.9, 2), both heading 0.5 rad: the laser is 0.1 m ahead
  // along the world x axis, i.e. rotated by -0.5 rad in the robot frame.
  EXPECT_NEAR(a->laser_on_robot.x, 0.1 * std::cos(0.5), 1e-12);
  EXPECT_NEAR(a->laser_on_robot.y, -0.1 * std::sin(0.5), 1e-12);
  EXPECT_NEAR(a->laser_on_robot.yaw, 0.0, 1e-12);
  EXPECT_FALSE(reader.next());
}

// Issue 16, class 5: the first laser line of a log used to decide its type even when it did
// not parse, and every later line of the real type was then ignored.
TEST(CarmenLogReader, AMalformedFirstLaserLineDoesNotDecideTheType) {
  const std::string text = std::string("PARAM robot_front_laser_max 30 host 0\n") +
                           "ROBOTLASER1 0 -1.5 garbage\n" +                // line 2: malformed
                           "FLASER 1 2.0 0 0 0 0 0 0 0.5 host 0.5\n" +     // line 3: one beam
                           flaser(5, 1.0, 0.0, 1.0) + flaser(5, 1.5, 0.1, 1.1) + flaser(5, 2.0, 0.2, 1.2);
  CarmenLogReader reader(writeText("g.log", text));
  int good = 0;
  while (auto l = reader.next()) {
    EXPECT_EQ(l->type, "FLASER");
    ++good;
  }
  EXPECT_EQ(good, 3);
  EXPECT_EQ(reader.laserType(), "FLASER");
  EXPECT_EQ(reader.malformedLines(), 2u);
  ASSERT_EQ(reader.issues().size(), 2u);
  EXPECT_NE(reader.issues()[0].find("g.log:2: ROBOTLASER1"), std::string::npos) << reader.issues()[0];
  EXPECT_NE(reader.issues()[1].find("g.log:3: FLASER: 1 beam(s)"), std::string::npos) << reader.issues()[1];
}

// Issue 16: a line whose geometry cannot make a scan is skipped with the field and the
// value that stopped it (not with a beam count it does not lack).
TEST(CarmenLogReader, AZeroResolutionOrANonPositiveMaximumRangeIsNamedWithItsValue) {
  // ROBOTLASER1 type start fov res maxr acc rem n r.. nrem laser(3) robot(3) tv rv fs ss ta ts host lts
  const auto robotLaser = [](const std::string& res, const std::string& max_range, double ts) {
    const std::string t = std::to_string(ts);
    return "ROBOTLASER1 0 -1.0 2.0 " + res + " " + max_range + " 0.01 0 5 1 1 1 1 1 0 0 0 0 0 0 0 0 0 0 0 0 " +
           t + " h " + t + "\n";
  };
  const std::string text = robotLaser("0", "20", 1.0) + robotLaser("0.5", "0", 2.0) + robotLaser("0.5", "-3", 3.0) +
                           robotLaser("0.5", "20", 4.0);
  CarmenLogReader reader(writeText("h.log", text));
  int good = 0;
  while (reader.next()) ++good;
  EXPECT_EQ(good, 1);
  ASSERT_EQ(reader.issues().size(), 3u);
  EXPECT_NE(reader.issues()[0].find("h.log:1: ROBOTLASER1: angular resolution 0 rad"), std::string::npos)
      << reader.issues()[0];
  EXPECT_NE(reader.issues()[1].find("h.log:2: ROBOTLASER1: maximum range 0 m"), std::string::npos)
      << reader.issues()[1];
  EXPECT_NE(reader.issues()[2].find("h.log:3: ROBOTLASER1: maximum range -3 m"), std::string::npos)
      << reader.issues()[2];
  for (const std::string& issue : reader.issues()) EXPECT_EQ(issue.find("beam"), std::string::npos) << issue;
}

TEST(CarmenLogReader, AnUnknownLaserTypeIsRefusedAtOnce) {
  const std::string path = writeText("h.log", flaser(5, 1.0, 0.0, 1.0));
  try {
    CarmenLogReader reader(path, {"NOPE", 50.0});
    FAIL() << "laser type NOPE accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'" + path + "': laser type 'NOPE' is not one of FLASER, RLASER, ROBOTLASER1"),
              std::string::npos)
        << e.what();
  }
}

TEST(CarmenLogReader, CorruptGzipIsAnErrorNamingTheFile) {
  std::string text;
  for (int k = 0; k < 2000; ++k) text += flaser(50, 1.0 + k * 1e-3, k, k);
  const std::string path = writeGz("f.log.gz", text);
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream(tmp("f_trunc.log.gz"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  CarmenLogReader reader(tmp("f_trunc.log.gz"));
  try {
    while (reader.next()) {
    }
    FAIL() << "a truncated gzip file read to the end without error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("f_trunc.log.gz:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(CarmenLogReader(tmp("missing.log")), std::runtime_error);
}

// A gzip file of several members is read whole; a damaged or cut later member, or garbage
// after the last, is an error naming the file and line: zlib's gzread() ended the log there
// without a word (half of it lost, exit 0). Zero padding after the last member is allowed
// (as gzip allows it). Issue 16.
TEST(CarmenLogReader, EveryGzipMemberIsReadAndNothingAfterTheLastIsIgnored) {
  std::string first, second;
  for (int k = 0; k < 300; ++k) first += flaser(50, 1.0 + k * 1e-3, k, k);
  for (int k = 300; k < 600; ++k) second += flaser(50, 1.0 + k * 1e-3, k, k);
  const auto bytesOf = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string a = bytesOf(writeGz("m1.log.gz", first)), b = bytesOf(writeGz("m2.log.gz", second));
  const auto count = [](const std::string& path) {
    CarmenLogReader reader(path);
    std::size_t n = 0;
    while (reader.next()) ++n;
    return n;
  };
  const auto write = [](const std::string& name, const std::string& bytes) {
    std::ofstream(tmp(name), std::ios::binary) << bytes;
    return tmp(name);
  };
  EXPECT_EQ(count(write("two.log.gz", a + b)), 600u);
  EXPECT_EQ(count(write("padded.log.gz", a + b + std::string(100, '\0'))), 600u);
  std::string flipped = a + b;
  flipped[a.size()] = static_cast<char>(flipped[a.size()] ^ 0xff);
  for (const auto& [name, bytes] : std::vector<std::pair<std::string, std::string>>{
           {"cut_member.log.gz", a + b.substr(0, 1)},
           {"cut_header.log.gz", a + b.substr(0, 5)},
           {"cut_data.log.gz", a + b.substr(0, b.size() / 2)},
           {"flipped_member.log.gz", flipped},
           {"garbage.log.gz", a + b + "garbage"}}) {
    try {
      const std::size_t n = count(write(name, bytes));
      ADD_FAILURE() << name << ": read to the end without error (" << n << " scans)";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(name + ":"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("corrupt or truncated compressed data"), std::string::npos) << e.what();
    }
  }
}

TEST(CarmenLogReader, ReadsEveryRadishLogToTheEnd) {
  const std::string dir = std::string(LIDARSEG_SHARED_DATASETS_DIR) + "/radish-corrected/";
  if (!std::ifstream(dir + "aces-corrected.log.gz")) GTEST_SKIP() << "no " << dir;
  for (const char* name : {"aces", "intel", "orebro", "seattle"}) {
    CarmenLogReader reader(dir + name + "-corrected.log.gz");
    std::size_t n = 0;
    while (auto l = reader.next()) {
      ++n;
      ASSERT_GE(l->ranges_m.size(), 180u);
    }
    EXPECT_GT(n, 200u) << name;
    EXPECT_EQ(reader.malformedLines(), 0u) << name;
  }
}

// A stamp beyond 1e10 s (the year 2286) is a corrupt field, not a clock reading: its line
// is skipped with its place. At 1e15 s the runs' 1 ms nudge of a repeated stamp was lost to
// rounding, so the outputs' stamps stopped increasing while the summary counted nothing.
TEST(CarmenLogReader, AStampBeyondTheYear2286SkipsItsLineWithItsPlace) {
  const std::string text = flaser(5, 1.0, 0.0, 1.0) + flaser(5, 1.0, 0.1, 1e15) + flaser(5, 1.0, 0.2, -2e10) +
                           flaser(5, 1.0, 0.3, 9.9e9) + flaser(5, 1.0, 0.4, 2.0);
  CarmenLogReader reader(writeText("stamps.log", text));
  std::vector<double> stamps;
  while (auto l = reader.next()) stamps.push_back(l->stamp_s);
  EXPECT_EQ(stamps, (std::vector<double>{1.0, 9.9e9, 2.0}));
  ASSERT_EQ(reader.issues().size(), 2u);
  EXPECT_NE(reader.issues()[0].find("stamps.log:2"), std::string::npos) << reader.issues()[0];
  EXPECT_NE(reader.issues()[0].find("ipc_timestamp"), std::string::npos) << reader.issues()[0];
  EXPECT_NE(reader.issues()[0].find("not a time stamp"), std::string::npos) << reader.issues()[0];
  EXPECT_NE(reader.issues()[1].find("stamps.log:3"), std::string::npos) << reader.issues()[1];
}

// A ROBOTLASER1 line's field of view must be what its beams span, and no laser line may span
// more than a full turn: a field of view of 0.1 rad on 181 beams of 1 degree was read as
// the resolution says (1031 degrees for the attack's line), silently.
TEST(CarmenLogReader, ALineWhoseBeamsSpanMoreThanATurnOrDisagreeWithItsFieldOfViewIsSkipped) {
  const auto robotlaser = [](double fov, double res, double ts) {
    std::string s = "ROBOTLASER1 0 " + std::to_string(-0.5 * fov) + " " + std::to_string(fov) + " " +
                    std::to_string(res) + " 30 0.01 0 5 1 1 1 1 1 0";
    s += " 0 0 0 0 0 0 0 0 0 0 0 " + std::to_string(ts) + " host " + std::to_string(ts) + "\n";
    return s;
  };
  const double quarter = 0.785398;  // 5 beams of 45 degrees span 180
  const std::string text = robotlaser(4 * quarter, quarter, 1.0) + robotlaser(0.1, quarter, 2.0) +
                           robotlaser(12.0, 3.0, 3.0) + robotlaser(5 * quarter, quarter, 4.0) +
                           robotlaser(-4 * quarter, -quarter, 5.0);
  CarmenLogReader reader(writeText("fov.log", text));
  std::vector<double> stamps;
  while (auto l = reader.next()) stamps.push_back(l->stamp_s);
  // Over n - 1 or n steps (writers differ), and clockwise, the field of view is the beams'.
  EXPECT_EQ(stamps, (std::vector<double>{1.0, 4.0, 5.0}));
  ASSERT_EQ(reader.issues().size(), 2u);
  EXPECT_NE(reader.issues()[0].find("fov.log:2: ROBOTLASER1: field of view 0.1 rad disagrees with 5 beams of 0.785398 rad"),
            std::string::npos)
      << reader.issues()[0];
  EXPECT_NE(reader.issues()[1].find("fov.log:3: ROBOTLASER1: 5 beams of 3 rad span 12 rad, more than a full turn"), std::string::npos)
      << reader.issues()[1];
}

// A UTF-8 byte-order mark before the first line (an editor's) made its first scan an
// unknown line type "\ufeffFLASER"; it is read.
TEST(CarmenLogReader, AByteOrderMarkBeforeTheFirstLineLosesNoScan) {
  CarmenLogReader reader(writeText("bom.log", "\xEF\xBB\xBF" + flaser(5, 1.0, 0.0, 1.0) + flaser(5, 1.0, 0.1, 2.0)));
  std::vector<double> stamps;
  while (auto l = reader.next()) stamps.push_back(l->stamp_s);
  EXPECT_EQ(stamps, (std::vector<double>{1.0, 2.0}));
  EXPECT_TRUE(reader.unknownTypes().empty());
  EXPECT_TRUE(reader.issues().empty());
}

// A hexadecimal float ("0x1p0", which strtod reads as 1) is no number of any CARMEN writer:
// a fuzzed or corrupted range or pose field written so skips its line, with its place,
// instead of becoming a plausible value.
TEST(CarmenLogReader, AHexadecimalFloatSkipsItsLineWithItsPlace) {
  std::string range_hex = flaser(5, 1.0, 0.1, 2.0);
  range_hex.replace(range_hex.find("1.000000"), 8, "0x1p0");
  std::string pose_hex = flaser(5, 1.0, 0.2, 3.0);
  pose_hex.replace(pose_hex.find("0.200000"), 8, "0x1.8p-3");
  const std::string text = flaser(5, 1.0, 0.0, 1.0) + range_hex + pose_hex + flaser(5, 1.0, 0.3, 4.0);
  CarmenLogReader reader(writeText("hex.log", text));
  std::vector<double> stamps;
  while (auto l = reader.next()) stamps.push_back(l->stamp_s);
  EXPECT_EQ(stamps, (std::vector<double>{1.0, 4.0}));
  EXPECT_EQ(reader.malformedLines(), 2u);
  ASSERT_EQ(reader.issues().size(), 2u);
  EXPECT_NE(reader.issues()[0].find("hex.log:2"), std::string::npos) << reader.issues()[0];
  EXPECT_NE(reader.issues()[0].find("'0x1p0' is not a number"), std::string::npos) << reader.issues()[0];
  EXPECT_NE(reader.issues()[1].find("hex.log:3"), std::string::npos) << reader.issues()[1];
  EXPECT_NE(reader.issues()[1].find("'0x1.8p-3'"), std::string::npos) << reader.issues()[1];
}

// A laser line becomes the core's scan with no MRPT in between (issue 15): beams evenly
// spaced over the aperture, centred on the scan frame's x axis, which carmenSensorOnRobot()
// puts on the robot; the valid ranges are the line's own doubles; no return, zero and
// non-finite ranges are invalid; a clockwise resolution reverses the beams' order.
TEST(CarmenScan, ALineBecomesTheCoreScanAndItsMounting) {
  CarmenLaser l;
  l.type = "ROBOTLASER1";
  l.stamp_s = 7.25;
  l.start_angle_rad = -0.5 * M_PI;
  l.angular_resolution_rad = M_PI / 180.0;
  l.max_range_m = 30.0;
  l.ranges_m.assign(181, 2.0);
  l.ranges_m[3] = 2.123456789012345;  // more digits than a float holds
  l.ranges_m[4] = 30.0;               // no return
  l.ranges_m[5] = 0.0;
  l.ranges_m[6] = std::nan("");
  l.laser_on_robot = {0.2, -0.1, 0.05};
  CentredLayoutCache layouts;
  const Scan scan = carmenScan(l, layouts);
  ASSERT_EQ(scan.size(), 181u);
  EXPECT_DOUBLE_EQ(scan.stamp_s, 7.25);
  EXPECT_NEAR(scan.layout->angle(0), -0.5 * M_PI, 1e-6);
  EXPECT_NEAR(scan.layout->angle(90), 0.0, 1e-9);
  EXPECT_NEAR(scan.layout->angle(180), 0.5 * M_PI, 1e-6);
  EXPECT_EQ(scan.ranges_m[3], 2.123456789012345);
  EXPECT_TRUE(scan.valid[3]);
  EXPECT_FALSE(scan.valid[4]);
  EXPECT_FALSE(scan.valid[5]);
  EXPECT_FALSE(scan.valid[6]);
  EXPECT_TRUE(std::isfinite(scan.ranges_m[6]));
  EXPECT_NEAR(scan.max_range_m, 30.0, 1e-6);
  // The scan frame's x axis is the middle of the aperture: here the laser's own axis.
  const Pose2D mount = carmenSensorOnRobot(l);
  EXPECT_NEAR(mount.x, 0.2, 1e-12);
  EXPECT_NEAR(mount.y, -0.1, 1e-12);
  EXPECT_NEAR(mount.yaw, 0.05, 1e-12);
  // One layout per geometry for the whole log.
  EXPECT_EQ(carmenScan(l, layouts).layout, scan.layout);

  // A clockwise line starting at +60 degrees: its middle is at +30 degrees on the laser.
  l.start_angle_rad = M_PI / 3.0;
  l.angular_resolution_rad = -M_PI / 180.0;
  l.ranges_m.assign(61, 1.5);
  const Scan cw = carmenScan(l, layouts);
  EXPECT_GT(cw.layout->angle(0), cw.layout->angle(60));
  EXPECT_NEAR(cw.layout->angle(0), M_PI / 6.0, 1e-6);
  EXPECT_NEAR(carmenSensorOnRobot(l).yaw, 0.05 + M_PI / 6.0, 1e-12);

  // What the core cannot represent is refused, naming the line type.
  l.angular_resolution_rad = 1e300;
  try {
    carmenScan(l, layouts);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("ROBOTLASER1 has an invalid aperture"), std::string::npos) << e.what();
  }
  l.ranges_m.assign(1, 1.0);
  l.angular_resolution_rad = 0.01;
  EXPECT_THROW(carmenScan(l, layouts), std::invalid_argument);
}

// A negative field of view (or resolution) would turn the beams the other way and mirror
// every pose; a laser offset of 1e300 m is no mounting: the line is skipped with the PARAM
// named.
TEST(CarmenLogReader, ANegativeFieldOfViewOrResolutionOrAFarMountingSkipsTheLinesWithTheParamNamed) {
  for (const std::string param : {"laser_front_laser_fov -180", "laser_front_laser_resolution -1"}) {
    CarmenLogReader reader(writeText("fov.log", "PARAM " + param + " host 0\n" + flaser(181, 2.5, 1.0, 10.0)));
    EXPECT_FALSE(reader.next()) << param;
    ASSERT_EQ(reader.issues().size(), 1u) << param;
    const std::string key = param.substr(0, param.find(' '));
    EXPECT_NE(reader.issues()[0].find("fov.log:2: FLASER: PARAM " + key + " = -"), std::string::npos)
        << reader.issues()[0];
  }
  CarmenLogReader far(writeText("fov.log", "PARAM robot_frontlaser_offset 1e300 host 0\n" + flaser(181, 2.5, 1.0, 10.0)));
  EXPECT_FALSE(far.next());
  ASSERT_EQ(far.issues().size(), 1u);
  EXPECT_NE(far.issues()[0].find("PARAM robot_frontlaser_offset = 1e+300 is beyond +-1e6 m"), std::string::npos)
      << far.issues()[0];
  CarmenLogReader fine(writeText("fov.log", "PARAM laser_front_laser_fov 100 host 0\n" + flaser(101, 2.5, 1.0, 10.0)));
  const auto scan = fine.next();
  ASSERT_TRUE(scan);
  EXPECT_NEAR(scan->start_angle_rad, -50.0 * M_PI / 180.0, 1e-12);
  EXPECT_GT(scan->angular_resolution_rad, 0.0);
}

// A PARAM that is there but holds no number ("90deg", "nan", "0.5abc") was read as absent:
// the scans then had the default field of view or mounting, exit 0, without a word (issue 16).
TEST(CarmenLogReader, AParamThatIsNoNumberSkipsTheLinesWithTheParamAndItsValueNamed) {
  for (const std::string param : {"laser_front_laser_fov 90deg", "laser_front_laser_fov nan",
                                  "laser_front_laser_resolution 0.5abc", "laser_front_laser_resolution inf",
                                  "robot_frontlaser_offset 0.5m", "robot_front_laser_max abc"}) {
    CarmenLogReader reader(writeText("param.log", "PARAM " + param + " host 0\n" + flaser(181, 2.5, 1.0, 10.0)));
    EXPECT_FALSE(reader.next()) << param;
    ASSERT_EQ(reader.issues().size(), 1u) << param;
    const std::string key = param.substr(0, param.find(' ')), value = param.substr(param.find(' ') + 1);
    EXPECT_NE(reader.issues()[0].find("param.log:2: FLASER: PARAM " + key + " = '" + value + "' is not a finite number"),
              std::string::npos)
        << reader.issues()[0];
  }
}

// A log of laser lines this reader does not read: they are counted by type, so that the
// "no usable laser scan" error can say what the log holds.
TEST(CarmenLogReader, LaserLinesOfTypesNotReadAreCounted) {
  const std::string raw = "RAWLASER1 0 -1.5708 3.14159 0.0174533 80 0.01 0 3 1 1 1 0 1.0 host 1.0\n";
  CarmenLogReader reader(writeText("raw.log", raw + raw + flaser(5, 1.0, 0.0, 2.0)));
  ASSERT_TRUE(reader.next());
  EXPECT_FALSE(reader.next());
  ASSERT_EQ(reader.unreadLaserLines().size(), 1u);
  EXPECT_EQ(reader.unreadLaserLines().at("RAWLASER1"), 2u);
  EXPECT_TRUE(reader.unknownTypes().empty());
}

TEST(CarmenLogReader, AMissingFileIsNamedWithTheSystemsReason) {
  try {
    CarmenLogReader reader(tmp("no-such-dir/missing.log"));
    FAIL() << "a missing file opened";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open '" + tmp("no-such-dir/missing.log") + "': No such file or directory"),
              std::string::npos)
        << e.what();
  }
}
