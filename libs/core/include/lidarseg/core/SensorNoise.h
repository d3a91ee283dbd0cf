#pragma once
/// @file SensorNoise.h
/// Gaussian measurement noise of a range sensor.

namespace lidarseg {

/// Gaussian, independent noise on each beam's range and bearing. The segment fitter
/// propagates it to the (rho, theta) covariance of every segment (paper II.A: "the model
/// of the noise, Gaussian distributed, can be transmitted to the equation of the
/// extracted segment").
struct SensorNoise {
  /// Standard deviation of a range measurement (m). SICK LMS100 data sheet: 0.012 m.
  double range_sigma_m = 0.012;
  /// Standard deviation of a beam's bearing (rad); 0 for most scanners.
  double bearing_sigma_rad = 0.0;

  /// @throws std::invalid_argument naming the key when a value is negative or not finite.
  void validate() const;
};

}  // namespace lidarseg
