#include "lidarseg/core/SegmentMatcher.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "Validation.h"

namespace lidarseg {

namespace {

constexpr double kMaxWeight = std::numeric_limits<double>::infinity();

// A segment's line and shape, in some frame.
struct Line {
  double rho = 0.0, theta = 0.0;
  Eigen::Vector2d cog = Eigen::Vector2d::Zero();
  double length = 0.0;
  double var_rho = 0.0, var_theta = 0.0;
};

Line lineOf(const Segment& s, const MatcherParams& p) {
  Line l;
  l.rho = s.rho_m;
  l.theta = s.theta_rad;
  l.cog = s.cog;
  l.length = s.length_m;
  l.var_rho = std::max(s.covariance(0, 0), p.min_rho_sigma_m * p.min_rho_sigma_m);
  l.var_theta = std::max(s.covariance(1, 1), p.min_theta_sigma_rad * p.min_theta_sigma_rad);
  return l;
}

// The line of a previous-frame segment seen from the current frame (T_curr_prev).
Line transformed(const Line& l, const Pose2D& T) {
  Line out = l;
  out.theta = wrapAngle(l.theta + T.yaw);
  const Eigen::Vector2d n(std::cos(out.theta), std::sin(out.theta));
  out.rho = l.rho + n.dot(T.translation());
  if (out.rho < 0.0) {
    out.rho = -out.rho;
    out.theta = wrapAngle(out.theta + kPi);
  }
  out.cog = T * l.cog;
  return out;
}

// theta difference a - b for the same line possibly written with opposite normals;
// sets `flip` when b must be read as (-rho, theta + pi).
double alignedAngle(double theta_a, double theta_b, bool& flip) {
  double d = wrapAngle(theta_a - theta_b);
  flip = std::abs(d) > 0.5 * kPi;
  if (flip) d = wrapAngle(d - kPi);
  return d;
}

struct Workspace {
  std::vector<Line> prev, cur, predicted;
  std::vector<double> weights;  // n x m, row-major
  std::vector<double> bearings;
  std::vector<int> order;       // current segments sorted by bearing
  std::vector<int> prev_index, cur_index;  // considered segment -> index in the input
};

// The indices (ascending) of the `limit` longest segments, or of all of them.
void selectLongest(const std::vector<Segment>& segments, std::size_t limit, std::vector<int>& out) {
  out.resize(segments.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = static_cast<int>(i);
  if (segments.size() <= limit) return;
  std::nth_element(out.begin(), out.begin() + static_cast<long>(limit), out.end(), [&](int a, int b) {
    const double la = segments[a].length_m, lb = segments[b].length_m;
    return la > lb || (la == lb && a < b);
  });
  out.resize(limit);
  std::sort(out.begin(), out.end());
}

}  // namespace

const char* MatchRejections::dominant() const {
  const std::pair<const char*, std::size_t> all[] = {{"gated", gated},
                                                     {"over_threshold", over_threshold},
                                                     {"ambiguous", ambiguous},
                                                     {"not_mutual", not_mutual},
                                                     {"outliers", outliers}};
  const char* name = "none";
  std::size_t most = 0;
  for (const auto& [n, c] : all) {
    if (c > most) {
      most = c;
      name = n;
    }
  }
  return name;
}

const char* toString(MatchStatus s) {
  switch (s) {
    case MatchStatus::kOk:
      return "ok";
    case MatchStatus::kDegenerate:
      return "degenerate";
    case MatchStatus::kTooFewMatches:
      return "too_few_matches";
  }
  return "unknown";
}

void MatcherParams::validate() const {
  detail::requirePositive("cog_gate_m", cog_gate_m);
  detail::requireNonNegative("cog_gate_length_ratio", cog_gate_length_ratio);
  detail::requirePositive("rho_scale_m", rho_scale_m);
  detail::requirePositive("theta_scale_rad", theta_scale_rad);
  detail::requirePositive("cog_scale_m", cog_scale_m);
  detail::requireNonNegative("length_weight", length_weight);
  detail::requirePositive("max_weight", max_weight);
  detail::requireInRange("ambiguity_ratio", ambiguity_ratio, 1e-6, 1.0);
  if (min_matches < 2) detail::failKey("min_matches", ">= 2", static_cast<double>(min_matches));
  if (max_segments < 2) detail::failKey("max_segments", ">= 2", static_cast<double>(max_segments));
  detail::requirePositive("outlier_sigmas", outlier_sigmas);
  detail::requireInRange("degeneracy_ratio", degeneracy_ratio, 0.0, 1.0);
  detail::requirePositive("unconstrained_sigma_m", unconstrained_sigma_m);
  detail::requirePositive("min_rho_sigma_m", min_rho_sigma_m);
  detail::requirePositive("min_theta_sigma_rad", min_theta_sigma_rad);
}

SegmentMatcher::SegmentMatcher(const MatcherParams& params) : params_(params) { params_.validate(); }

MatchResult SegmentMatcher::match(const std::vector<Segment>& previous,
                                  const std::vector<Segment>& current, const Pose2D& prior) const {
  const MatcherParams& P = params_;
  MatchResult result;
  result.T_prev_curr = prior;
  const double u2 = P.unconstrained_sigma_m * P.unconstrained_sigma_m;
  result.covariance = Eigen::Vector3d(u2, u2, 0.1).asDiagonal();  // "nothing learnt"
  if (previous.empty() || current.empty()) return result;

  thread_local Workspace ws;
  selectLongest(previous, P.max_segments, ws.prev_index);
  selectLongest(current, P.max_segments, ws.cur_index);
  const std::size_t n = ws.prev_index.size(), m = ws.cur_index.size();
  result.segments_ignored = previous.size() - n + current.size() - m;
  ws.prev.resize(n);
  ws.cur.resize(m);
  ws.predicted.resize(n);
  for (std::size_t i = 0; i < n; ++i) ws.prev[i] = lineOf(previous[ws.prev_index[i]], P);
  for (std::size_t j = 0; j < m; ++j) ws.cur[j] = lineOf(current[ws.cur_index[j]], P);
  ws.bearings.resize(m);
  ws.order.resize(m);
  for (std::size_t j = 0; j < m; ++j) {
    ws.bearings[j] = std::atan2(ws.cur[j].cog.y(), ws.cur[j].cog.x());
    ws.order[j] = static_cast<int>(j);
  }
  std::sort(ws.order.begin(), ws.order.end(),
            [&](int a, int b) { return ws.bearings[a] < ws.bearings[b]; });

  Pose2D estimate = prior;
  std::vector<std::pair<int, int>> couples;
  // The last estimate that rested on at least 2 couples (re-association may lose some).
  bool have_good = false;
  std::vector<std::pair<int, int>> good_couples;
  for (std::size_t iter = 0; iter <= P.iterations; ++iter) {
    // (2) Previous segments predicted into the current frame.
    const Pose2D T_curr_prev = inverse(estimate);
    for (std::size_t i = 0; i < n; ++i) ws.predicted[i] = transformed(ws.prev[i], T_curr_prev);

    // (3) Weights on the focused band, (4) couples; the full matrix if the band is short.
    std::vector<std::pair<int, int>> found;
    for (int pass = 0; pass < 2; ++pass) {
      const bool full = pass == 1 || P.band_half_width == 0 || m <= 2 * P.band_half_width + 1;
      ws.weights.assign(n * m, kMaxWeight);
      for (std::size_t i = 0; i < n; ++i) {
        const Line& a = ws.predicted[i];
        const auto evaluate = [&](std::size_t j) {
          const Line& b = ws.cur[j];
          ++result.weights_computed;
          const double cog_dist = (a.cog - b.cog).norm();
          // Accelerated weight: far apart, maximal weight, nothing else computed.
          if (cog_dist > P.cog_gate_m + P.cog_gate_length_ratio * std::max(a.length, b.length)) {
            ++result.weights_gated;
            return;
          }
          bool flip = false;
          const double dtheta = alignedAngle(a.theta, b.theta, flip);
          const double drho = a.rho - (flip ? -b.rho : b.rho);
          const double dlen = std::abs(a.length - b.length) / std::max({a.length, b.length, 1e-9});
          ws.weights[i * m + j] = std::abs(drho) / P.rho_scale_m + std::abs(dtheta) / P.theta_scale_rad +
                                  cog_dist / P.cog_scale_m + P.length_weight * dlen;
        };
        if (full) {
          for (std::size_t j = 0; j < m; ++j) evaluate(j);
        } else {
          const double bearing = std::atan2(a.cog.y(), a.cog.x());
          const auto pos = static_cast<long>(
              std::lower_bound(ws.order.begin(), ws.order.end(), bearing,
                               [&](int j, double b) { return ws.bearings[j] < b; }) -
              ws.order.begin());
          const long w = static_cast<long>(P.band_half_width);
          for (long k = pos - w; k <= pos + w; ++k) {
            const long mm = static_cast<long>(m);
            evaluate(static_cast<std::size_t>(ws.order[static_cast<std::size_t>(((k % mm) + mm) % mm)]));
          }
        }
      }
      found.clear();
      result.rejections = {};
      for (std::size_t i = 0; i < n; ++i) {
        std::size_t best_j = 0;
        double best = kMaxWeight, second = kMaxWeight;
        for (std::size_t j = 0; j < m; ++j) {
          const double w = ws.weights[i * m + j];
          if (w < best) {
            second = best;
            best = w;
            best_j = j;
          } else if (w < second) {
            second = w;
          }
        }
        if (!(best < kMaxWeight)) {
          ++result.rejections.gated;
          continue;
        }
        if (!(best < P.max_weight)) {
          ++result.rejections.over_threshold;
          continue;
        }
        if (second < kMaxWeight && best > P.ambiguity_ratio * second) {
          ++result.rejections.ambiguous;
          continue;
        }
        // Mutual: i is also the best (and unambiguous) row of column best_j.
        double col_second = kMaxWeight;
        bool mutual = true;
        for (std::size_t k = 0; k < n; ++k) {
          if (k == i) continue;
          const double w = ws.weights[k * m + best_j];
          if (w <= best) mutual = false;
          col_second = std::min(col_second, w);
        }
        if (!mutual) {
          ++result.rejections.not_mutual;
          continue;
        }
        if (col_second < kMaxWeight && best > P.ambiguity_ratio * col_second) {
          ++result.rejections.ambiguous;
          continue;
        }
        found.emplace_back(static_cast<int>(i), static_cast<int>(best_j));
      }
      if (found.size() >= P.min_matches || full) {
        result.used_full_matrix = result.used_full_matrix || (full && pass == 1);
        break;
      }
    }
    if (found.size() < 2) break;
    couples = found;
    result.iterations = iter + 1;

    // (5) Rigid motion from the matched lines, with outlier rejection.
    std::vector<char> inlier(couples.size(), 1);
    for (int round = 0; round < 2; ++round) {
      double sw = 0.0, swd = 0.0;
      std::size_t used = 0;
      for (std::size_t k = 0; k < couples.size(); ++k) {
        if (!inlier[k]) continue;
        const Line& p = ws.prev[couples[k].first];
        const Line& c = ws.cur[couples[k].second];
        bool flip = false;
        const double d = alignedAngle(p.theta, c.theta + estimate.yaw, flip);
        const double w = 1.0 / (p.var_theta + c.var_theta);
        sw += w;
        swd += w * d;
        ++used;
      }
      if (used < 2) break;
      const double yaw = wrapAngle(estimate.yaw + swd / sw);
      const double var_yaw = 1.0 / sw;
      Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
      Eigen::Vector2d b = Eigen::Vector2d::Zero();
      for (std::size_t k = 0; k < couples.size(); ++k) {
        if (!inlier[k]) continue;
        const Line& p = ws.prev[couples[k].first];
        const Line& c = ws.cur[couples[k].second];
        bool flip = false;
        alignedAngle(p.theta, c.theta + yaw, flip);
        const double theta_c = flip ? c.theta + kPi : c.theta;
        const double rho_c = flip ? -c.rho : c.rho;
        const Eigen::Vector2d nrm(std::cos(theta_c + yaw), std::sin(theta_c + yaw));
        const double w = 1.0 / (p.var_rho + c.var_rho);
        A += w * nrm * nrm.transpose();
        b += w * nrm * (p.rho - rho_c);
      }
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(A);
      const Eigen::Vector2d lambda = eig.eigenvalues();  // ascending
      const Eigen::Matrix2d V = eig.eigenvectors();
      if (!(lambda(1) > 0.0)) break;
      Eigen::Vector2d t;
      Eigen::Matrix2d cov_t;
      const bool degenerate = lambda(0) < P.degeneracy_ratio * lambda(1);
      if (degenerate) {
        const Eigen::Vector2d strong = V.col(1), weak = V.col(0);
        t = strong * (strong.dot(b) / lambda(1)) + weak * weak.dot(estimate.translation());
        cov_t = strong * strong.transpose() / lambda(1) + weak * weak.transpose() * u2;
      } else {
        t = A.ldlt().solve(b);
        cov_t = A.inverse();
      }
      // Drop couples whose line residual is far beyond its standard deviation.
      bool dropped = false;
      for (std::size_t k = 0; k < couples.size(); ++k) {
        if (!inlier[k]) continue;
        const Line& p = ws.prev[couples[k].first];
        const Line& c = ws.cur[couples[k].second];
        bool flip = false;
        const double dth = alignedAngle(p.theta, c.theta + yaw, flip);
        const double theta_c = flip ? c.theta + kPi : c.theta;
        const double rho_c = flip ? -c.rho : c.rho;
        const Eigen::Vector2d nrm(std::cos(theta_c + yaw), std::sin(theta_c + yaw));
        const double r = p.rho - rho_c - nrm.dot(t);
        const double sigma = std::sqrt(p.var_rho + c.var_rho) + 0.01;
        const double sigma_th = std::sqrt(p.var_theta + c.var_theta) + 0.005;
        if (std::abs(r) > P.outlier_sigmas * sigma || std::abs(dth) > P.outlier_sigmas * sigma_th) {
          inlier[k] = 0;
          ++result.rejections.outliers;
          dropped = true;
        }
      }
      estimate = {t.x(), t.y(), yaw};
      result.covariance.setZero();
      result.covariance.topLeftCorner<2, 2>() = cov_t;
      result.covariance(2, 2) = var_yaw;
      result.status = degenerate ? MatchStatus::kDegenerate : MatchStatus::kOk;
      result.degenerate_direction = degenerate ? Eigen::Vector2d(V.col(0)) : Eigen::Vector2d::Zero();
      if (!dropped) break;
    }
    std::vector<std::pair<int, int>> kept;
    for (std::size_t k = 0; k < couples.size(); ++k) {
      if (inlier[k]) kept.push_back(couples[k]);
    }
    if (kept.size() < 2) break;
    have_good = true;
    good_couples = std::move(kept);
  }
  if (!have_good) {
    result.status = MatchStatus::kTooFewMatches;
    result.T_prev_curr = prior;
    result.covariance = Eigen::Vector3d(u2, u2, 0.1).asDiagonal();
    return result;
  }
  result.T_prev_curr = estimate;
  result.matches = std::move(good_couples);
  for (auto& [i, j] : result.matches) {  // back to the caller's indices
    i = ws.prev_index[static_cast<std::size_t>(i)];
    j = ws.cur_index[static_cast<std::size_t>(j)];
  }
  return result;
}

}  // namespace lidarseg
