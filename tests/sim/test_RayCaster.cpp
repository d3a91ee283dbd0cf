#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "SyntheticScenes.h"
#include "lidarseg/sim/RayCaster.h"
#include "lidarseg/sim/ScanSimulator.h"
#include "lidarseg/sim/WorldFile.h"

namespace lidarseg::sim {
namespace {
using lidarseg::kPi;

// The grid must give exactly what testing every wall gives.
TEST(RayCaster, AgreesWithBruteForceOnRandomRays) {
  const World worlds[] = {loadWorldFile(std::string(LIDARSEG_CONFIG_DIR) + "/worlds/hospital.world"),
                          loadWorldFile(std::string(LIDARSEG_CONFIG_DIR) + "/worlds/maze.world"),
                          lidarseg::testing::officeScene()};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-5.0, 45.0), a(-kPi, kPi);
  for (const World& w : worlds) {
    const RayCaster caster(w);
    for (int i = 0; i < 20000; ++i) {
      const Eigen::Vector2d o(u(rng), 0.5 * u(rng));
      const double t = a(rng);
      const Eigen::Vector2d d(std::cos(t), std::sin(t));
      const double expected = w.castRay(o, d);
      const RayHit hit = caster.cast(o, d);
      if (std::isinf(expected)) {
        EXPECT_FALSE(hit.hit());
      } else {
        ASSERT_TRUE(hit.hit());
        EXPECT_NEAR(hit.range, expected, 1e-9);
      }
    }
  }
}

TEST(RayCaster, MaxRangeAndWallKinds) {
  const World w = loadWorldFile(std::string(LIDARSEG_CONFIG_DIR) + "/worlds/hospital.world");
  const RayCaster caster(w);
  // A closed door 20 cm deep at x in [21.5, 22.4] on the bottom corridor.
  const RayHit door = caster.cast({22.0, 0.0}, {0, 1});
  ASSERT_TRUE(door.hit());
  EXPECT_NEAR(door.range, 1.4, 1e-9);
  EXPECT_EQ(caster.walls()[door.wall].kind, SurfaceKind::kDoor);
  EXPECT_FALSE(caster.cast({22.0, 0.0}, {0, 1}, 1.0).hit());
  EXPECT_EQ(caster.walls()[caster.cast({19.0, 0.0}, {0, -1}).wall].kind, SurfaceKind::kWall);
}

// Rolling shutter: a sensor moving at v along x while it sweeps sees each beam from
// where it is at that beam's time.
TEST(ScanSimulator, RollingShutterDisplacementIsSpeedTimesBeamTime) {
  World w;
  w.addWall({-50, 3}, {50, 3});   // wall ahead (+y)
  w.addWall({10, -50}, {10, 50});  // wall to the right (+x)
  SensorModel m = SensorModel::lms100();
  m.range_sigma_m = 0.0;
  ScanSimulator sim(w, m, 1);
  const double v = 2.0;  // m/s along +x
  const double T = sim.sweepDuration();
  EXPECT_NEAR(T, 540 * 0.5 / 360.0 / 50.0, 1e-12);
  const Scan s = sim.scan({0, 0, kPi / 2}, {v * T, 0, kPi / 2});
  for (std::size_t i : {0u, 100u, 270u, 400u, 540u}) {
    EXPECT_NEAR(s.time_offsets_s[i], static_cast<double>(i) * sim.beamPeriod(), 1e-15);
  }
  // Beam 270 looks at +y: the wall y = 3 is at 3 m whatever x. Beams at angle a (sensor
  // frame) that hit the wall x = 10 measure (10 - x_i) / cos(a - (-pi/2)) from x_i = v t_i.
  for (std::size_t i = 0; i < 60; ++i) {
    const double a = s.layout->angle(i) + kPi / 2;  // world direction
    if (std::cos(a) <= 0.3) continue;
    const double x_i = v * s.time_offsets_s[i];
    const double expected = (10.0 - x_i) / std::cos(a);
    if (expected * std::sin(a) > -50 && expected * std::sin(a) < 3) {
      EXPECT_NEAR(s.ranges_m[i], expected, 1e-9) << "beam " << i;
    }
  }
  // Against a sensor standing still at the first pose, the last beams differ by v * T.
  const Scan still = sim.scan({0, 0, kPi / 2});
  EXPECT_NEAR(still.ranges_m[0] - s.ranges_m[0], 0.0, 1e-12);
}

}  // namespace
}  // namespace lidarseg::sim
