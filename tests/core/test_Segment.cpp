// Line fit from moments and the (rho, theta) noise model, checked against Monte Carlo.
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "lidarseg/core/Angles.h"
#include "lidarseg/core/Segment.h"

namespace lidarseg {
namespace {

Segment segmentFrom(const std::vector<Eigen::Vector2d>& pts, const SensorNoise& noise = {}) {
  Segment s;
  for (const auto& p : pts) s.moments.addPoint(p.x(), p.y());
  s.num_points = static_cast<std::uint32_t>(pts.size());
  s.first_point = pts.front();
  s.last_point = pts.back();
  fitSegment(s, noise);
  return s;
}

// Range along beam angle phi to the line x cos(theta) + y sin(theta) = rho.
double rangeToLine(double rho, double theta, double phi) { return rho / std::cos(phi - theta); }

TEST(Segment, ExactFitOfNoiselessPoints) {
  // Line y = 2 (theta = 90 deg, rho = 2) from x = -1 to x = 3.
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i <= 40; ++i) pts.emplace_back(-1.0 + 0.1 * i, 2.0);
  const Segment s = segmentFrom(pts);
  EXPECT_NEAR(s.rho_m, 2.0, 1e-12);
  EXPECT_NEAR(s.theta_rad, kPi / 2, 1e-12);
  EXPECT_NEAR(s.length_m, 4.0, 1e-12);
  EXPECT_NEAR(s.cog.x(), 1.0, 1e-12);
  EXPECT_NEAR(s.cog.y(), 2.0, 1e-12);
  EXPECT_NEAR(s.rms_residual_m, 0.0, 1e-9);
  EXPECT_NEAR(s.direction().x(), 1.0, 1e-12);
  EXPECT_NEAR(s.signedDistance({0.0, 2.5}), 0.5, 1e-12);
}

TEST(Segment, RhoIsNonNegativeAndThetaPointsToTheLine) {
  // Line x = -3: the normal from the sensor towards it is -x, so theta = pi, rho = 3.
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i <= 20; ++i) pts.emplace_back(-3.0, -1.0 + 0.1 * i);
  const Segment s = segmentFrom(pts);
  EXPECT_NEAR(s.rho_m, 3.0, 1e-12);
  EXPECT_NEAR(std::abs(s.theta_rad), kPi, 1e-12);
  EXPECT_GT(s.theta_rad, -kPi);
}

TEST(Segment, EndpointsAreProjectedOntoTheLine) {
  const Segment s = segmentFrom({{0, 1.0}, {1, 1.1}, {2, 0.9}, {3, 1.0}});
  EXPECT_NEAR(s.signedDistance(s.start), 0.0, 1e-12);
  EXPECT_NEAR(s.signedDistance(s.end), 0.0, 1e-12);
  EXPECT_NEAR((s.start - s.first_point).norm(), std::abs(s.signedDistance(s.first_point)), 1e-12);
}

TEST(Segment, FewerThanTwoDistinctPointsGiveInfiniteCovariance) {
  const Segment s = segmentFrom({{1, 1}, {1, 1}});
  EXPECT_TRUE(std::isinf(s.covariance(0, 0)));
  EXPECT_TRUE(std::isinf(s.covariance(1, 1)));
}

struct NoiseCase {
  const char* name;
  double rho, theta, phi_min_deg, phi_max_deg;
  double sigma_r, sigma_phi;
};

class SegmentCovariance : public ::testing::TestWithParam<NoiseCase> {};

// The propagated covariance must match the empirical covariance of fits of many noisy
// realisations of the same wall.
TEST_P(SegmentCovariance, MatchesMonteCarlo) {
  const NoiseCase c = GetParam();
  const SensorNoise noise{c.sigma_r, c.sigma_phi};
  const double step = 0.5 * kPi / 180.0;
  std::mt19937_64 rng(42);
  std::normal_distribution<double> unit(0.0, 1.0);

  std::vector<Eigen::Vector2d> samples;
  Eigen::Matrix2d model = Eigen::Matrix2d::Zero();
  const int trials = 4000;
  for (int t = 0; t < trials; ++t) {
    std::vector<Eigen::Vector2d> pts;
    for (double phi = c.phi_min_deg * kPi / 180; phi <= c.phi_max_deg * kPi / 180; phi += step) {
      // The beam really left at phi + dphi but is reported at phi.
      const double true_phi = phi + c.sigma_phi * unit(rng);
      const double r = rangeToLine(c.rho, c.theta, true_phi) + c.sigma_r * unit(rng);
      pts.emplace_back(r * std::cos(phi), r * std::sin(phi));
    }
    const Segment s = segmentFrom(pts, noise);
    samples.emplace_back(s.rho_m, std::remainder(s.theta_rad - c.theta, 2 * kPi));
    model += s.covariance / trials;
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& v : samples) mean += v / trials;
  Eigen::Matrix2d empirical = Eigen::Matrix2d::Zero();
  for (const auto& v : samples) empirical += (v - mean) * (v - mean).transpose() / (trials - 1);

  EXPECT_NEAR(mean.x(), c.rho, 4 * std::sqrt(empirical(0, 0) / trials) + 1e-4);
  EXPECT_NEAR(model(0, 0), empirical(0, 0), 0.10 * empirical(0, 0)) << c.name;
  EXPECT_NEAR(model(1, 1), empirical(1, 1), 0.10 * empirical(1, 1)) << c.name;
  const double corr_model = model(0, 1) / std::sqrt(model(0, 0) * model(1, 1));
  const double corr_emp = empirical(0, 1) / std::sqrt(empirical(0, 0) * empirical(1, 1));
  EXPECT_NEAR(corr_model, corr_emp, 0.05) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Walls, SegmentCovariance,
    ::testing::Values(NoiseCase{"facing", 3.0, 0.3, -10, 35, 0.012, 0.0},
                      NoiseCase{"oblique", 2.0, -1.2, -20, 40, 0.03, 0.0},
                      NoiseCase{"far_short", 8.0, 2.0, 105, 112, 0.012, 0.0},
                      NoiseCase{"with_bearing_noise", 3.0, 0.3, -10, 35, 0.01, 0.002}),
    [](const ::testing::TestParamInfo<NoiseCase>& p) { return std::string(p.param.name); });

TEST(LineMoments, AddingMomentsEqualsMomentsOfTheUnion) {
  LineMoments a, b, all;
  for (int i = 0; i < 10; ++i) {
    const double x = 0.3 * i, y = 1.0 + 0.01 * i * i;
    (i < 4 ? a : b).addPoint(x, y);
    all.addPoint(x, y);
  }
  a += b;
  EXPECT_DOUBLE_EQ(a.count, all.count);
  EXPECT_NEAR(a.sum_xy, all.sum_xy, 1e-12);
  EXPECT_NEAR(a.sum_wyy, all.sum_wyy, 1e-12);
}

}  // namespace
}  // namespace lidarseg
