#include "lidarseg/eval/TrajectoryMetrics.h"
#include "lidarseg/core/NumberText.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

namespace lidarseg::eval {

Pose2D alignPositions(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b) {
  if (a.size() != b.size() || a.empty()) {
    throw std::invalid_argument("alignPositions: need two equally long, non-empty sets");
  }
  Eigen::Vector2d ma = Eigen::Vector2d::Zero(), mb = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < a.size(); ++i) {
    ma += a[i];
    mb += b[i];
  }
  ma /= static_cast<double>(a.size());
  mb /= static_cast<double>(b.size());
  double s_cos = 0.0, s_sin = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector2d p = a[i] - ma, q = b[i] - mb;
    s_cos += p.dot(q);
    s_sin += p.x() * q.y() - p.y() * q.x();
  }
  const double yaw = (s_cos == 0.0 && s_sin == 0.0) ? 0.0 : std::atan2(s_sin, s_cos);
  const Eigen::Rotation2Dd R(yaw);
  const Eigen::Vector2d t = mb - R * ma;
  return {t.x(), t.y(), yaw};
}

NeesSummary evaluateNees(const std::vector<KeyframeMotion>& motions, const StampedTrajectory& ground_truth,
                         double tolerance_s) {
  constexpr double kChi2Of3At95 = 7.815;
  NeesSummary out;
  std::vector<double> values;
  for (const KeyframeMotion& m : motions) {
    const auto k = nearestIndex(ground_truth, m.keyframe_stamp_s, tolerance_s);
    const auto c = nearestIndex(ground_truth, m.stamp_s, tolerance_s);
    if (!k || !c) continue;
    const Pose2D truth = relative(ground_truth[*c].pose, ground_truth[*k].pose);
    const Eigen::Vector3d e(m.T_key_curr.x - truth.x, m.T_key_curr.y - truth.y, wrapAngle(m.T_key_curr.yaw - truth.yaw));
    const Eigen::LLT<Eigen::Matrix3d> llt(m.covariance);
    const double nees = llt.info() == Eigen::Success ? e.dot(llt.solve(e)) : -1.0;
    if (!(nees >= 0.0) || !std::isfinite(nees) || !m.covariance.allFinite()) {
      ++out.singular;
      continue;
    }
    values.push_back(nees);
  }
  out.evaluated = values.size();
  if (values.empty()) return out;
  const auto within = std::count_if(values.begin(), values.end(), [](double v) { return v <= kChi2Of3At95; });
  out.share_within_95 = static_cast<double>(within) / static_cast<double>(values.size());
  const Summary s = summarize(std::move(values));
  out.mean = s.mean;
  out.median = s.median;
  return out;
}

TrajectoryErrors evaluateTrajectory(const StampedTrajectory& estimate,
                                    const StampedTrajectory& ground_truth, double tolerance_s) {
  std::vector<Pose2D> est, gt;
  for (const auto& p : estimate) {
    const auto k = nearestIndex(ground_truth, p.stamp_s, tolerance_s);
    if (!k) continue;
    est.push_back(p.pose);
    gt.push_back(ground_truth[*k].pose);
  }
  if (est.size() < 2) {
    throw std::invalid_argument("trajectory evaluation: only " + std::to_string(est.size()) +
                                " estimated pose(s) have a ground-truth pose within " +
                                numberText(tolerance_s) + " s");
  }
  TrajectoryErrors out;
  out.associated = est.size();
  for (std::size_t k = 1; k < gt.size(); ++k) {
    out.path_length_m += std::hypot(gt[k].x - gt[k - 1].x, gt[k].y - gt[k - 1].y);
  }

  // Final error: the estimate expressed so that its first pose is the true first pose.
  const Pose2D anchor = compose(gt.front(), inverse(est.front()));
  const Pose2D last = compose(anchor, est.back());
  out.final_position_error_m = std::hypot(last.x - gt.back().x, last.y - gt.back().y);
  out.final_yaw_error_rad = std::abs(wrapAngle(last.yaw - gt.back().yaw));

  // ATE after the best rigid alignment.
  std::vector<Eigen::Vector2d> a(est.size()), b(gt.size());
  for (std::size_t k = 0; k < est.size(); ++k) {
    a[k] = est[k].translation();
    b[k] = gt[k].translation();
  }
  const Pose2D T = alignPositions(a, b);
  double sum_sq = 0.0, sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const double e = (T * a[k] - b[k]).norm();
    sum_sq += e * e;
    sum += e;
    out.ate_max_m = std::max(out.ate_max_m, e);
  }
  out.ate_rmse_m = std::sqrt(sum_sq / static_cast<double>(a.size()));
  out.ate_mean_m = sum / static_cast<double>(a.size());

  // Table I: per-step motion errors.
  std::vector<double> ex, ey, eth;
  ex.reserve(est.size());
  ey.reserve(est.size());
  eth.reserve(est.size());
  for (std::size_t k = 1; k < est.size(); ++k) {
    const Pose2D de = relative(est[k], est[k - 1]);
    const Pose2D dg = relative(gt[k], gt[k - 1]);
    ex.push_back(std::abs(de.x - dg.x));
    ey.push_back(std::abs(de.y - dg.y));
    eth.push_back(std::abs(wrapAngle(de.yaw - dg.yaw)));
  }
  out.motion.dx_m = summarize(std::move(ex));
  out.motion.dy_m = summarize(std::move(ey));
  out.motion.dtheta_rad = summarize(std::move(eth));
  return out;
}

}  // namespace lidarseg::eval
