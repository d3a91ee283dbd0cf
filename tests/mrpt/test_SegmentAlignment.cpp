// lidarseg's segment matcher behind MRPT's map-alignment interface.
#include <cmath>

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include "SyntheticScenes.h"
#include "lidarseg/mrpt/ScanConverter.h"
#include "lidarseg/mrpt/SegmentAlignment.h"

namespace lidarseg::mrpt_adapter {
namespace {

using lidarseg::testing::kDeg;

// The point map of the scan seen by an LMS100-like sensor at `pose` in the office scene.
mrpt::maps::CSimplePointsMap mapAt(const Pose2D& pose, std::uint64_t seed) {
  const auto sensor = lidarseg::testing::makeSensor(541, 270.0, 0.01);
  const Scan scan = lidarseg::testing::simulate(lidarseg::testing::officeScene(), sensor, pose, seed);
  const auto obs = makeRangeScanObservation(scan, "LIDAR", mrpt::poses::CPose3D(), 0.01);
  mrpt::maps::CSimplePointsMap map;
  map.insertionOptions.minDistBetweenLaserPoints = 0.0f;
  map.loadFromRangeScan(*obs);
  return map;
}

TEST(SegmentAlignment, RecoversTheMotionBetweenTwoScansWithItsCovariance) {
  const Pose2D a{1.0, 1.0, 0.0};
  const Pose2D b{1.25, 1.08, 4 * kDeg};
  const auto m1 = mapAt(a, 1), m2 = mapAt(b, 2);
  const Pose2D truth = relative(b, a);  // pose of b's frame in a's
  SegmentAlignment align;
  SegmentAlignment::TReturnInfo info;
  const auto pdf = align.AlignPDF(&m1, &m2, mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D()), info);
  const auto& g = dynamic_cast<const mrpt::poses::CPosePDFGaussian&>(*pdf);
  EXPECT_NEAR(g.mean.x(), truth.x, 0.02);
  EXPECT_NEAR(g.mean.y(), truth.y, 0.02);
  EXPECT_NEAR(g.mean.phi(), truth.yaw, 0.3 * kDeg);
  EXPECT_EQ(info.status, MatchStatus::kOk);
  EXPECT_GE(info.matches, 3u);
  EXPECT_GT(info.segments_m1, 3u);
  EXPECT_GT(info.executionTime, 0.0);
  // A real covariance: positive definite, centimetre-level or better.
  EXPECT_GT(g.cov.det(), 0.0);
  EXPECT_LT(g.cov(0, 0), 0.01 * 0.01);
  EXPECT_LT(g.cov(2, 2), std::pow(0.5 * kDeg, 2));
}

TEST(SegmentAlignment, Align3DHandlesThePlanarCaseAndRefusesTheOthers) {
  const auto m1 = mapAt({1.0, 1.0, 0.0}, 1), m2 = mapAt({1.2, 1.0, 0.0}, 2);
  SegmentAlignment align;
  const auto pdf = align.Align3DPDF(&m1, &m2, mrpt::poses::CPose3DPDFGaussian(mrpt::poses::CPose3D()));
  const auto& g = dynamic_cast<const mrpt::poses::CPose3DPDFGaussian&>(*pdf);
  EXPECT_NEAR(g.mean.x(), 0.2, 0.02);
  EXPECT_NEAR(g.mean.z(), 0.0, 1e-12);
  EXPECT_GT(g.cov(0, 0), 0.0);
  const mrpt::poses::CPose3DPDFGaussian tilted(mrpt::poses::CPose3D(0, 0, 0, 0, 0.1, 0));
  try {
    align.Align3DPDF(&m1, &m2, tilted);
    FAIL() << "a non-planar initial estimate was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("planar"), std::string::npos) << e.what();
  }
  EXPECT_THROW(align.AlignPDF(nullptr, &m2, mrpt::poses::CPosePDFGaussian()), std::invalid_argument);
}

TEST(SegmentAlignment, ParametersLoadLikeCicpsAndRejectBadKeys) {
  mrpt::config::CConfigFileMemory cfg;
  cfg.setContent(std::string("[align]\nwd_threshold_m = 0.03\nband_half_width = 4\nlevel = 2\n"));
  SegmentAlignment::TConfigParams p;
  p.loadFromConfigFile(cfg, "align");
  EXPECT_DOUBLE_EQ(p.segmentation.wall_danielsson.threshold_m, 0.03);
  EXPECT_EQ(p.matcher.band_half_width, 4u);
  EXPECT_EQ(p.level, CascadeLevel::kEroded);
  // Round trip through a file section.
  mrpt::config::CConfigFileMemory saved;
  p.saveToConfigFile(saved, "copy");
  SegmentAlignment::TConfigParams q;
  q.loadFromConfigFile(saved, "copy");
  EXPECT_DOUBLE_EQ(q.segmentation.wall_danielsson.threshold_m, 0.03);
  EXPECT_EQ(q.level, CascadeLevel::kEroded);
  // Unknown key, bad level.
  cfg.setContent(std::string("[align]\nwd_treshold_m = 0.03\n"));
  try {
    p.loadFromConfigFile(cfg, "align");
    FAIL() << "misspelt key accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("wd_treshold_m"), std::string::npos) << e.what();
  }
  cfg.setContent(std::string("[align]\nlevel = 7\n"));
  EXPECT_THROW(p.loadFromConfigFile(cfg, "align"), std::invalid_argument);
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
