#include "lidarseg/core/Segment.h"
#include "lidarseg/core/Angles.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lidarseg {

namespace {
// Kurtosis of a uniform distribution: sum(u^4) = 9/5 * N * var^2 for points spread evenly
// along the segment (used by the bearing-noise term only).
constexpr double kUniformKurtosis = 1.8;
}  // namespace

Eigen::Vector2d Segment::direction() const {
  if (length_m > 0.0) return (end - start) / length_m;
  return {-std::sin(theta_rad), std::cos(theta_rad)};
}

double Segment::signedDistance(const Eigen::Vector2d& p) const { return normal.dot(p) - rho_m; }

double residualSumOfSquares(const LineMoments& m) {
  if (m.count <= 0.0) return 0.0;
  const double cx = m.sum_x / m.count, cy = m.sum_y / m.count;
  const double mxx = m.sum_xx - m.sum_x * cx;
  const double mxy = m.sum_xy - m.sum_x * cy;
  const double myy = m.sum_yy - m.sum_y * cy;
  const double half_diff = 0.5 * (mxx - myy);
  const double ss = 0.5 * (mxx + myy) - std::sqrt(half_diff * half_diff + mxy * mxy);
  return ss > 0.0 ? ss : (ss == ss ? 0.0 : ss);  // clamp rounding below 0, keep NaN
}

void fitSegment(Segment& s, const SensorNoise& noise) {
  const LineMoments& m = s.moments;
  const double n_pts = m.count;
  if (n_pts <= 0.0) {
    s = Segment{};
    return;
  }
  const double cx = m.sum_x / n_pts;
  const double cy = m.sum_y / n_pts;
  // Scatter matrix of the points about their centroid.
  const double mxx = m.sum_xx - m.sum_x * cx;
  const double mxy = m.sum_xy - m.sum_x * cy;
  const double myy = m.sum_yy - m.sum_y * cy;

  // Total least squares: the line runs along the scatter's major axis, at angle alpha with
  // (cos 2alpha, sin 2alpha) = (mxx - myy, 2 mxy) / h. Half-angle formulas avoid cos/sin.
  // Plain sqrt rather than std::hypot: the moments are far from overflow, and this runs
  // for every segment of every scan.
  const double h = std::sqrt((mxx - myy) * (mxx - myy) + 4.0 * mxy * mxy);
  const double cos2 = h > 0.0 ? (mxx - myy) / h : 1.0;
  const double cos_a = std::sqrt(std::max(0.0, 0.5 * (1.0 + cos2)));
  const double sin_a = std::copysign(std::sqrt(std::max(0.0, 0.5 * (1.0 - cos2))), mxy);
  double nx = -sin_a, ny = cos_a;  // normal = direction rotated by +90 degrees
  double rho = cx * nx + cy * ny;
  if (rho < 0.0) {
    rho = -rho;
    nx = -nx;
    ny = -ny;
  }
  double theta = std::atan2(ny, nx);
  if (theta <= -kPi) theta = kPi;  // atan2(-0, -1): keep theta in (-pi, pi]
  const double dx = -ny, dy = nx;  // line direction, normal rotated by +90 degrees

  const double spread = std::max(0.0, dx * dx * mxx + 2.0 * dx * dy * mxy + dy * dy * myy);
  const double residual = std::max(0.0, nx * nx * mxx + 2.0 * nx * ny * mxy + ny * ny * myy);

  s.rho_m = rho;
  s.theta_rad = theta;
  s.normal = {nx, ny};
  s.centroid = {cx, cy};
  s.residual_ss_m2 = residual;
  s.rms_residual_m = std::sqrt(residual / n_pts);
  const Eigen::Vector2d& n = s.normal;
  s.start = s.first_point - (n.dot(s.first_point) - rho) * n;
  s.end = s.last_point - (n.dot(s.last_point) - rho) * n;
  s.cog = 0.5 * (s.start + s.end);
  s.length_m = (s.end - s.start).norm();

  // Noise model (paper II.A). Perpendicular error of point i: e_i = (n.b_i) dr_i - s_i dphi_i,
  // variance v_i. With u_i = s_i - s_mean, TLS gives to first order
  //   d(offset at centroid) = mean(e_i),  d(theta) = -sum(e_i u_i) / sum(u_i^2),
  // and rho = n(theta) . centroid adds s_mean * d(theta).
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Degenerate: fewer than 2 points, or all at one place (relative to their distance from
  // the sensor, so that rounding noise does not pass for a spread).
  if (n_pts < 2.0 || !(spread > 1e-12 * (m.sum_xx + m.sum_yy))) {
    s.covariance << kInf, 0.0, 0.0, kInf;
    return;
  }
  const double s_mean = dx * cx + dy * cy;

  // Range term: v_i = sigma_r^2 rho^2 / r_i^2, i.e. weights w_i = 1 / r_i^2.
  const double a = noise.range_sigma_m * noise.range_sigma_m * rho * rho;
  const double w0 = m.sum_w;
  const double w1 = dx * m.sum_wx + dy * m.sum_wy;
  const double w2 = dx * dx * m.sum_wxx + 2.0 * dx * dy * m.sum_wxy + dy * dy * m.sum_wyy;
  double v_sum = a * w0;                                                      // sum v_i
  double vu_sum = a * (w1 - s_mean * w0);                                     // sum v_i u_i
  double vuu_sum = a * std::max(0.0, w2 - 2.0 * s_mean * w1 + s_mean * s_mean * w0);  // sum v_i u_i^2

  // Bearing term: v_i = sigma_phi^2 s_i^2, with sum(u^3) ~ 0 and sum(u^4) ~ 1.8 spread^2 / N.
  const double b = noise.bearing_sigma_rad * noise.bearing_sigma_rad;
  if (b > 0.0) {
    v_sum += b * (spread + n_pts * s_mean * s_mean);
    vu_sum += b * 2.0 * s_mean * spread;
    vuu_sum += b * (kUniformKurtosis * spread * spread / n_pts + s_mean * s_mean * spread);
  }

  const double var_offset = v_sum / (n_pts * n_pts);
  const double var_theta = vuu_sum / (spread * spread);
  const double cov_offset_theta = -vu_sum / (n_pts * spread);
  const double var_rho = var_offset + 2.0 * s_mean * cov_offset_theta + s_mean * s_mean * var_theta;
  const double cov_rho_theta = cov_offset_theta + s_mean * var_theta;
  s.covariance << var_rho, cov_rho_theta, cov_rho_theta, var_theta;
}

}  // namespace lidarseg
