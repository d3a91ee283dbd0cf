/// @file test_FuzzFindings.cpp
/// One test per finding of the fuzz targets (docs/reliability.md, "Findings"): the input
/// class that failed, reduced to what matters, with the behaviour now expected. The inputs
/// themselves are replayed by the fuzz-replay.* tests (tests/fuzz/regressions/).

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "ErrorOf.h"
#include "lidarseg/vision/RegionTable.h"
#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/eval/FeatureEvaluation.h"
#include "lidarseg/mrpt/ExceptionMessage.h"
#include "lidarseg/mrpt/SegmentationConfig.h"
#include "lidarseg/sim/RayCaster.h"
#include "lidarseg/sim/WorldFile.h"

namespace lidarseg {
namespace {

std::string write(const std::string& name, const std::string& text) {
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/fuzz-finding-" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

using lidarseg::testing::errorOf;

// F1 (fuzz_sim_inputs): a wall at 2.6e58 m made the ray caster's grid size overflow an int
// (undefined behaviour). World files now refuse |value| > 1e6 with file:line, and the ray
// caster sizes its grid in floating point before converting.
TEST(FuzzFindings, F1_HugeWorldCoordinatesAreRefusedAndTheRayCasterStaysDefined) {
  std::istringstream in("wall 0 0 26105200000000000000000000000000000000000000000000000000000 1\n");
  const std::string e = errorOf([&] { sim::parseWorld(in, "huge.world"); });
  EXPECT_NE(e.find("huge.world:1: '2610520"), std::string::npos) << e;
  EXPECT_NE(e.find("out of range"), std::string::npos) << e;

  sim::World w;  // built in code, bypassing the file's bound
  w.addWall({0, 0}, {2.6e58, 1.0});
  w.addWall({0, 0}, {0, 3});
  const sim::RayCaster caster(w);
  const sim::RayHit hit = caster.cast({-1.0, 1.0}, {1.0, 0.0}, 10.0);
  ASSERT_TRUE(hit.hit());
  EXPECT_NEAR(hit.range, 1.0, 1e-9);
}

// F2 (fuzz_config): MRPT's INI preprocessor threw "Line 33: Expected closing `}`" for a
// `$env{` without its brace, and the message reached the user without the file's name.
TEST(FuzzFindings, F2_IniPreprocessorErrorsNameTheFile) {
  const std::string path = write("bad-env.ini", "[segmentation]\nwd_threshold_m = $env{HOME\n");
  const std::string e = errorOf([&] { mrpt_adapter::loadSegmentationParamsFile(path); });
  EXPECT_NE(e.find(path + ": not a valid INI file"), std::string::npos) << e;
}

// An expression MRPT's INI preprocessor cannot evaluate ($eval{1+}) is reported with MRPT's
// message in one line after the file's name, not with its banner "==== MRPT exception ===="
// in place of the message (issue 16, class 6: found by the audit of 2026-11-26).
TEST(FuzzFindings, AnIniEvalErrorGivesMrptsMessageInOneLineNotItsBanner) {
  const std::string path = write("bad-eval.ini", "[segmentation]\nwd_threshold_m = $eval{1+}\n");
  const std::string e = errorOf([&] { mrpt_adapter::loadSegmentationParamsFile(path); });
  const std::string prefix = path + ": not a valid INI file: ";
  ASSERT_EQ(e.rfind(prefix, 0), 0u) << e;
  EXPECT_GT(e.size(), prefix.size() + 3) << e;
  EXPECT_EQ(e.find("MRPT exception"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

// The one-line form of an MRPT exception is never empty and never MRPT's banner, whatever
// the text after "Message:" (review finding).
TEST(FuzzFindings, AnMrptExceptionsOneLineIsNeitherEmptyNorItsBanner) {
  EXPECT_EQ(mrpt_adapter::exceptionMessage("==== MRPT exception ====\nFile: a.cpp:1\nMessage: bad key 'x'\n"), "bad key 'x'");
  EXPECT_EQ(mrpt_adapter::exceptionMessage("==== MRPT exception ====\nFile: a.cpp:1\nMessage:"), "File: a.cpp:1");
  EXPECT_EQ(mrpt_adapter::exceptionMessage("\nplain failure\n"), "plain failure");
  // THROW_EXCEPTION's banner with the reason on the next line and a backtrace after it (a
  // rawlog written to a full disk): the reason, not the banner.
  EXPECT_EQ(mrpt_adapter::exceptionMessage("==== MRPT exception ====\ncannot write 'f.rawlog': No space left on "
                                           "device\nCall stack backtrace:\n[0 ] 0x7f\n"),
            "cannot write 'f.rawlog': No space left on device");
  EXPECT_EQ(mrpt_adapter::exceptionMessage(""), "unknown error");
  EXPECT_EQ(mrpt_adapter::exceptionMessage("\n\n"), "unknown error");
  EXPECT_EQ(mrpt_adapter::exceptionMessage("one line"), "one line");
}

// F3 (fuzz_tables): a true-features CSV with scan = 6.7e22 was converted to size_t
// (undefined behaviour). Now an error naming file, line and column.
TEST(FuzzFindings, F3_HugeScanIndexInTrueFeaturesIsAnError) {
  const std::string path = write("truth.csv", "scan,t,type,x,y,theta,width,id\n6.7e22,1.0,door_open,1,2,0,0.9,3\n");
  const std::string e = errorOf([&] { eval::readTrueFeatures(path); });
  EXPECT_NE(e.find(path + ":2"), std::string::npos) << e;
  EXPECT_NE(e.find("column 'scan'"), std::string::npos) << e;
}

// F4 (fuzz_scan_pipeline): a range of 4.9e-324 m (a denormal) was a valid beam; the line
// fit weighs points by 1 / range^2, which became infinite, and the segment's covariance
// NaN. Ranges at or below 1 mm are now invalid beams.
TEST(FuzzFindings, F4_DenormalRangesAreInvalidBeamsAndSegmentsStayFinite) {
  constexpr std::size_t kBeams = 181;
  Scan scan;
  scan.layout = std::make_shared<const BeamLayout>(BeamLayout::centred(kBeams, M_PI));
  scan.ranges_m.resize(kBeams);
  for (std::size_t i = 0; i < kBeams; ++i) {
    const double a = scan.layout->angle(i);
    scan.ranges_m[i] = 2.0 / std::max(0.2, std::abs(std::cos(a)));  // a wall 2 m ahead
  }
  for (std::size_t i = 80; i < 100; i += 3) scan.ranges_m[i] = std::numeric_limits<double>::denorm_min();
  scan.ranges_m[120] = 1e-3;
  EXPECT_FALSE(scan.beamValid(80));
  EXPECT_FALSE(scan.beamValid(120));
  EXPECT_TRUE(scan.beamValid(81));
  const Segmentation s = ScanSegmenter().process(scan);
  ASSERT_FALSE(s.levels[0].segments.empty());
  for (const auto& level : s.levels) {
    for (const Segment& seg : level.segments) {
      EXPECT_TRUE(std::isfinite(seg.rho_m) && seg.covariance.allFinite() && seg.cog.allFinite());
    }
  }
}

// F5 (read while writing fuzz_tables): region coordinates near LONG_MAX overflowed
// `u_max - u_min + 1` (undefined behaviour) and negative ones were accepted from files.
TEST(FuzzFindings, F5_RegionCoordinatesAreBounded) {
  vision::RegionTable table;
  std::istringstream in("frame,u_min,v_min,u_max,v_max\n0,-9223372036854775807,0,9223372036854775807,5\n");
  const std::string e = errorOf([&] { table.read(in, "r.csv"); });
  EXPECT_NE(e.find("r.csv:2: need 0 <= u_min <= u_max <= 1000000"), std::string::npos) << e;
  EXPECT_NE(errorOf([] { vision::parseRegion("0,0,2000000,5", "--roi"); }).find("--roi '0,0,2000000,5'"),
            std::string::npos);
  std::istringstream good("frame,u_min,v_min,u_max,v_max\n3,10,20,30,40\n*,0,0,1,1\n");
  vision::RegionTable ok;
  ok.read(good, "g.csv");
  ASSERT_EQ(ok.of(3, "").size(), 2u);
  EXPECT_EQ(ok.of(3, "")[1], cv::Rect(10, 20, 21, 21));
  EXPECT_EQ(ok.of(4, "").size(), 1u);
}

// F7 (fuzz_config, in CI): a YAML "%" directive line after a mapping made libfyaml loop
// forever (SIGALRM after 20 s in every tool taking -c). Directives are now refused first,
// naming file and line.
TEST(FuzzFindings, F7_YamlDirectivesAreRefusedBeforeTheParserLoops) {
  const std::string path = write("directive.yaml", "segmentation:\n  wd_threshold_m: 0.02\n%matc+++1+\n");
  const std::string e = errorOf([&] { mrpt_adapter::loadSegmentationParamsFile(path); });
  EXPECT_NE(e.find(path + ":3: YAML directives"), std::string::npos) << e;
}

}  // namespace
}  // namespace lidarseg
