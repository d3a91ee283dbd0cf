#pragma once
/// @file Segment.h
/// A line segment extracted from a scan, with its line fit and noise model.

#include <cstdint>

#include <Eigen/Core>

#include "lidarseg/core/SensorNoise.h"

namespace lidarseg {

/// Sufficient statistics of a set of scan points (sensor frame, m) for a total-least-squares
/// line fit and for the first-order propagation of range noise to that fit.
///
/// Moments add: the moments of the union of two point sets are the sum of their moments,
/// so fusing segments (paper II.B) re-fits "from the union of the points" in O(1).
struct LineMoments {
  double count = 0.0;
  double sum_x = 0.0, sum_y = 0.0;
  double sum_xx = 0.0, sum_xy = 0.0, sum_yy = 0.0;
  /// Sums weighted by 1/r^2 (r: range of the point), for the range-noise model.
  /// sum_wxx, sum_wxy, sum_wyy are sums of the beam directions' outer products
  /// (x^2/r^2 = cos^2 phi, ...), so they depend on the bearings only.
  double sum_w = 0.0;
  double sum_wx = 0.0, sum_wy = 0.0;
  double sum_wxx = 0.0, sum_wxy = 0.0, sum_wyy = 0.0;

  /// Adds one point (x, y) in the sensor frame (m); the sensor is at the origin.
  void addPoint(double x, double y) {
    const double xx = x * x, xy = x * y, yy = y * y;
    const double w = 1.0 / (xx + yy);
    count += 1.0;
    sum_x += x;
    sum_y += y;
    sum_xx += xx;
    sum_xy += xy;
    sum_yy += yy;
    sum_w += w;
    sum_wx += w * x;
    sum_wy += w * y;
    sum_wxx += w * xx;
    sum_wxy += w * xy;
    sum_wyy += w * yy;
  }

  LineMoments& operator+=(const LineMoments& o) {
    count += o.count;
    sum_x += o.sum_x;
    sum_y += o.sum_y;
    sum_xx += o.sum_xx;
    sum_xy += o.sum_xy;
    sum_yy += o.sum_yy;
    sum_w += o.sum_w;
    sum_wx += o.sum_wx;
    sum_wy += o.sum_wy;
    sum_wxx += o.sum_wxx;
    sum_wxy += o.sum_wxy;
    sum_wyy += o.sum_wyy;
    return *this;
  }
};

/// Sum of the squared orthogonal distances of the points to their total-least-squares line
/// (m^2): the smaller eigenvalue of their scatter matrix. O(1).
double residualSumOfSquares(const LineMoments& m);

/// A line segment of a scan, in the sensor frame.
///
/// The line is x cos(theta) + y sin(theta) = rho with rho >= 0 (Hessian normal form,
/// paper III.A's (rho, theta) representation); theta in (-pi, pi].
struct Segment {
  /// First and last beam covered (inclusive), in scan order. first_beam > last_beam only
  /// for a segment that continues across the wrap-around of a 360-degree scan.
  std::uint32_t first_beam = 0;
  std::uint32_t last_beam = 0;
  /// Number of scan points in the segment.
  std::uint32_t num_points = 0;
  /// The level-0 (Wall-Danielsson) segments that make up this one: indices
  /// parts[parts_begin .. parts_end) of its SegmentLevel::parts.
  std::uint32_t parts_begin = 0;
  std::uint32_t parts_end = 0;

  /// Measured first and last points, in scan order (m).
  Eigen::Vector2d first_point = Eigen::Vector2d::Zero();
  Eigen::Vector2d last_point = Eigen::Vector2d::Zero();

  /// Distance from the sensor to the line (m), >= 0.
  double rho_m = 0.0;
  /// Direction of the line's normal, from the sensor towards the line (rad).
  double theta_rad = 0.0;
  /// The unit normal (cos theta, sin theta).
  Eigen::Vector2d normal = Eigen::Vector2d::UnitX();
  /// first_point and last_point projected onto the line (m).
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  Eigen::Vector2d end = Eigen::Vector2d::Zero();
  /// The middle of [start, end]: the paper's "COG" (m).
  Eigen::Vector2d cog = Eigen::Vector2d::Zero();
  /// Mean of the points (m).
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  /// |end - start| (m).
  double length_m = 0.0;
  /// Root mean square of the points' orthogonal distances to the line (m).
  double rms_residual_m = 0.0;
  /// Sum of the squared orthogonal distances (m^2): residualSumOfSquares(moments).
  double residual_ss_m2 = 0.0;
  /// Covariance of (rho, theta) propagated from the sensor noise: units m^2, m*rad, rad^2.
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  /// The points' moments, from which the fit above was computed.
  LineMoments moments;

  /// Unit direction of the line, pointing from start to end (scan order).
  Eigen::Vector2d direction() const;
  /// Signed distance of p (m, sensor frame) from the line; positive beyond it.
  double signedDistance(const Eigen::Vector2d& p) const;
};

/// Fits the line of `segment` from its moments and first/last points, and fills every
/// derived field (rho, theta, endpoints, COG, centroid, length, residual, covariance).
///
/// Total least squares (orthogonal regression) on the points. The covariance is the
/// first-order propagation of independent Gaussian range and bearing noise (paper II.A):
/// a beam's error moves its point across the line by
///   e_i = (n . b_i) dr_i - s_i dphi_i,
/// with n the line normal, b_i the beam direction and s_i the point's coordinate along
/// the line; n . b_i is taken as rho / r_i. The range term is exact to first order; the
/// bearing term assumes the points are spread symmetrically about their centroid.
/// O(1). Needs moments.count >= 2 for a finite covariance; with fewer points, or all
/// points at one place, the covariance is set to +infinity on the diagonal.
void fitSegment(Segment& segment, const SensorNoise& noise);

}  // namespace lidarseg
