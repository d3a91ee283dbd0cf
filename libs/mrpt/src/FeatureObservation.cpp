#include "lidarseg/mrpt/FeatureObservation.h"

#include <cmath>

namespace lidarseg::mrpt_adapter {

namespace {
constexpr double kPitchVariance = 1e-6;  // rad^2: 2D landmarks; keeps the matrix invertible
}  // namespace

mrpt::obs::CObservationBearingRange::Ptr makeBearingRangeObservation(const std::vector<Feature>& features,
                                                                     const mrpt::poses::CPose3D& sensor_pose,
                                                                     double max_range_m, double field_of_view_rad,
                                                                     const std::string& sensor_label) {
  auto obs = mrpt::obs::CObservationBearingRange::Create();
  obs->sensorLabel = sensor_label;
  obs->sensorLocationOnRobot = sensor_pose;
  obs->minSensorDistance = 0.0f;
  obs->maxSensorDistance = std::isfinite(max_range_m) ? static_cast<float>(max_range_m) : 0.0f;
  obs->fieldOfView_yaw = static_cast<float>(field_of_view_rad);
  obs->fieldOfView_pitch = 0.0f;
  obs->validCovariances = true;
  for (const Feature& f : features) {
    const double x = f.position.x(), y = f.position.y();
    const double r2 = x * x + y * y, r = std::sqrt(r2);
    if (!(r > 1e-6) || !std::isfinite(r)) continue;
    mrpt::obs::CObservationBearingRange::TMeasurement m;
    m.range = static_cast<float>(r);
    m.yaw = static_cast<float>(std::atan2(y, x));
    m.pitch = 0.0f;
    m.landmarkID = -1;
    Eigen::Matrix2d J;  // d(range, yaw) / d(x, y)
    J << x / r, y / r, -y / r2, x / r2;
    const Eigen::Matrix2d c = J * f.covariance.topLeftCorner<2, 2>() * J.transpose();
    m.covariance.setZero();
    m.covariance(0, 0) = c(0, 0);
    m.covariance(0, 1) = m.covariance(1, 0) = c(0, 1);
    m.covariance(1, 1) = c(1, 1);
    m.covariance(2, 2) = kPitchVariance;
    obs->sensedData.push_back(m);
  }
  return obs;
}

}  // namespace lidarseg::mrpt_adapter
