#include <cmath>

#include <gtest/gtest.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <algorithm>

#include <mrpt/core/Clock.h>

#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/mrpt/ScanConverter.h"

namespace lidarseg::mrpt_adapter {
namespace {

mrpt::obs::CObservation2DRangeScan makeObs(std::size_t n, float aperture, bool ccw) {
  mrpt::obs::CObservation2DRangeScan obs;
  obs.aperture = aperture;
  obs.rightToLeft = ccw;
  obs.maxRange = 30.0f;
  obs.resizeScan(n);
  for (std::size_t i = 0; i < n; ++i) {
    obs.setScanRange(i, 1.0f + 0.01f * static_cast<float>(i));
    obs.setScanRangeValidity(i, i % 7 != 3);
  }
  return obs;
}

TEST(ScanConverter, AnglesFollowMrptsConventionInBothDirections) {
  ScanConverter conv;
  for (bool ccw : {true, false}) {
    for (std::size_t n : {181u, 361u, 541u}) {
      const auto obs = makeObs(n, static_cast<float>(M_PI * (n == 541 ? 1.5 : 1.0)), ccw);
      const Scan scan = conv.convert(obs);
      ASSERT_EQ(scan.size(), n);
      for (std::size_t i = 0; i < n; i += 10) {
        EXPECT_NEAR(scan.layout->angle(i), obs.getScanAngle(i), 1e-6) << "beam " << i;
      }
    }
  }
}

TEST(ScanConverter, RangesValidityAndLimits) {
  ScanConverter conv(0.1);
  auto obs = makeObs(181, static_cast<float>(M_PI), true);
  obs.setScanRange(5, 30.0f);  // at max range
  const Scan scan = conv.convert(obs);
  EXPECT_DOUBLE_EQ(scan.ranges_m[10], static_cast<double>(obs.getScanRange(10)));
  EXPECT_EQ(scan.max_range_m, 30.0);
  EXPECT_EQ(scan.min_range_m, 0.1);
  EXPECT_FALSE(scan.beamValid(3));  // flagged invalid by the driver
  EXPECT_FALSE(scan.beamValid(5));  // no return
  EXPECT_TRUE(scan.beamValid(4));
}

TEST(ScanConverter, LayoutIsSharedBetweenScansOfOneSensor) {
  ScanConverter conv;
  const auto obs = makeObs(181, static_cast<float>(M_PI), true);
  EXPECT_EQ(conv.convert(obs).layout.get(), conv.convert(obs).layout.get());
}

// MRPT's 360-degree scans run from -pi to +pi inclusive: the last beam looks where the
// first does. The layout must still wrap around, so that the wall behind the sensor is
// one segment.
TEST(ScanConverter, FullTurnMrptScanWrapsAround) {
  ScanConverter conv;
  mrpt::obs::CObservation2DRangeScan obs;
  const std::size_t n = 361;
  obs.aperture = static_cast<float>(2 * M_PI);
  obs.rightToLeft = true;
  obs.maxRange = 30.0f;
  obs.resizeScan(n);
  // Square room [-2, 2] x [-2, 2] around the sensor.
  for (std::size_t i = 0; i < n; ++i) {
    const double a = obs.getScanAngle(i);
    const double r = 2.0 / std::max(std::abs(std::cos(a)), std::abs(std::sin(a)));
    obs.setScanRange(i, static_cast<float>(r));
    obs.setScanRangeValidity(i, true);
  }
  const Scan scan = conv.convert(obs);
  EXPECT_TRUE(scan.layout->wrapsAround());
  const auto seg = ScanSegmenter().process(scan);
  const auto& top = seg.level(CascadeLevel::kFusedAgain).segments;
  EXPECT_EQ(top.size(), 4u);
  EXPECT_EQ(std::count_if(top.begin(), top.end(), [](const Segment& s) { return s.first_beam > s.last_beam; }), 1);
}

TEST(ScanConverter, ObservationRoundTrip) {
  ScanConverter conv;
  const auto obs = makeObs(181, static_cast<float>(M_PI), false);
  Scan scan = conv.convert(obs);
  scan.stamp_s = 1767225600.25;
  const auto back = makeRangeScanObservation(scan, "LASER", mrpt::poses::CPose3D(0.1, 0, 0.3, 0, 0, 0), 0.02);
  EXPECT_EQ(back->getScanSize(), 181u);
  EXPECT_FALSE(back->rightToLeft);
  EXPECT_NEAR(back->aperture, M_PI, 1e-6);
  EXPECT_NEAR(mrpt::Clock::toDouble(back->timestamp), 1767225600.25, 1e-6);
  for (std::size_t i = 0; i < 181; i += 7) {
    EXPECT_EQ(back->getScanRange(i), obs.getScanRange(i));
    EXPECT_EQ(back->getScanRangeValidity(i), obs.getScanRangeValidity(i));
    EXPECT_NEAR(back->getScanAngle(i), obs.getScanAngle(i), 1e-6);
  }
  Scan skewed = scan;
  skewed.layout = std::make_shared<BeamLayout>(BeamLayout::uniform(181, 0.0, 0.01));
  EXPECT_THROW(makeRangeScanObservation(skewed, "L", {}, 0.01), std::invalid_argument);
}

TEST(ScanConverter, RejectsDegenerateObservations) {
  ScanConverter conv;
  EXPECT_THROW(conv.convert(makeObs(1, 1.0f, true)), std::invalid_argument);
  EXPECT_THROW(conv.convert(makeObs(10, 0.0f, true)), std::invalid_argument);
  EXPECT_THROW(conv.convert(makeObs(10, NAN, true)), std::invalid_argument);
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
