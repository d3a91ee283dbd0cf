#include <cmath>

#include <gtest/gtest.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

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

TEST(ScanConverter, RejectsDegenerateObservations) {
  ScanConverter conv;
  EXPECT_THROW(conv.convert(makeObs(1, 1.0f, true)), std::invalid_argument);
  EXPECT_THROW(conv.convert(makeObs(10, 0.0f, true)), std::invalid_argument);
  EXPECT_THROW(conv.convert(makeObs(10, NAN, true)), std::invalid_argument);
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
