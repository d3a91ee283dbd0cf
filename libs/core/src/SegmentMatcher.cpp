#include "lidarseg/core/SegmentMatcher.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "Validation.h"
#include "lidarseg/core/Angles.h"

namespace lidarseg {

namespace {

// Weight of a couple that is no candidate: beyond the COG gate or outside the focused band.
constexpr double kMaxWeight = std::numeric_limits<double>::infinity();
// Yaw variance of the "nothing learnt" covariance returned with the prior (rad^2: a standard
// deviation of 0.32 rad, 18 deg); its translation variances are unconstrained_sigma_m^2.
constexpr double kUninformedYawVarianceRad2 = 0.1;
// Fewest couples an estimate may rest on (and the fewest inliers a solve may use): two
// non-parallel lines fix a planar pose.
constexpr std::size_t kMinCouples = 2;
// Floor of the relative length difference's denominator (m), for two zero-length segments.
constexpr double kMinLengthM = 1e-9;
// Added to a couple's propagated rho (m) and theta (rad) standard deviations in the outlier
// test, so that the couples of long, nearly noiseless lines, whose propagated deviations are
// far below 1 cm and 0.3 deg, are not dropped for errors the line model leaves out.
constexpr double kOutlierSlackRhoM = 0.01;
constexpr double kOutlierSlackThetaRad = 0.005;
// Solves per iteration: on all couples, then once more without the outliers the first found.
constexpr int kSolveRounds = 2;

using Couples = std::vector<std::pair<int, int>>;

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

// A current line c turned by yaw into the previous frame and written with the normal of the
// previous line p: that normal, c's rho read with it, and the angle residual p - c (rad).
struct AlignedCouple {
  Eigen::Vector2d normal;
  double rho_c = 0.0;
  double dtheta = 0.0;
};

AlignedCouple aligned(const Line& p, const Line& c, double yaw) {
  bool flip = false;
  AlignedCouple a;
  a.dtheta = alignedAngle(p.theta, c.theta + yaw, flip);
  const double theta_c = flip ? c.theta + kPi : c.theta;
  a.rho_c = flip ? -c.rho : c.rho;
  a.normal = Eigen::Vector2d(std::cos(theta_c + yaw), std::sin(theta_c + yaw));
  return a;
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

// Step (1): the lines of the segments considered (max_segments), and the current ones'
// order by bearing, which the focused band searches.
void prepareLines(const std::vector<Segment>& previous, const std::vector<Segment>& current,
                  const MatcherParams& P, Workspace& ws) {
  selectLongest(previous, P.max_segments, ws.prev_index);
  selectLongest(current, P.max_segments, ws.cur_index);
  const std::size_t n = ws.prev_index.size(), m = ws.cur_index.size();
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
}

// Step (2): the previous lines predicted into the current frame by the estimate T_prev_curr.
void predictPrevious(const Pose2D& T_prev_curr, Workspace& ws) {
  const Pose2D T_curr_prev = inverse(T_prev_curr);
  for (std::size_t i = 0; i < ws.prev.size(); ++i) {
    ws.predicted[i] = transformed(ws.prev[i], T_curr_prev);
  }
}

// Step (3), one couple: predicted previous line a, current line b. The accelerated weight:
// far apart, kMaxWeight and nothing else computed. Counts the weight in `result`.
double coupleWeight(const Line& a, const Line& b, const MatcherParams& P, MatchResult& result) {
  ++result.weights_computed;
  const double cog_dist = (a.cog - b.cog).norm();
  if (cog_dist > P.cog_gate_m + P.cog_gate_length_ratio * std::max(a.length, b.length)) {
    ++result.weights_gated;
    return kMaxWeight;
  }
  bool flip = false;
  const double dtheta = alignedAngle(a.theta, b.theta, flip);
  const double drho = a.rho - (flip ? -b.rho : b.rho);
  const double dlen = std::abs(a.length - b.length) / std::max({a.length, b.length, kMinLengthM});
  return std::abs(drho) / P.rho_scale_m + std::abs(dtheta) / P.theta_scale_rad +
         cog_dist / P.cog_scale_m + P.length_weight * dlen;
}

// Where a predicted line's COG bearing falls in the current lines' bearing order.
long bandCentre(const Workspace& ws, const Line& a) {
  const double bearing = std::atan2(a.cog.y(), a.cog.x());
  const auto first = std::lower_bound(ws.order.begin(), ws.order.end(), bearing,
                                      [&](int j, double b) { return ws.bearings[j] < b; });
  return static_cast<long>(first - ws.order.begin());
}

// Step (3): the weight matrix, on the focused band (band_half_width places either side of
// each row's predicted bearing, wrapping around) or in `full`; the rest stays kMaxWeight.
void weighCouples(bool full, const MatcherParams& P, Workspace& ws, MatchResult& result) {
  const std::size_t n = ws.predicted.size(), m = ws.cur.size();
  ws.weights.assign(n * m, kMaxWeight);
  const long mm = static_cast<long>(m), w = static_cast<long>(P.band_half_width);
  for (std::size_t i = 0; i < n; ++i) {
    const Line& a = ws.predicted[i];
    double* row = ws.weights.data() + i * m;
    if (full) {
      for (std::size_t j = 0; j < m; ++j) row[j] = coupleWeight(a, ws.cur[j], P, result);
      continue;
    }
    const long pos = bandCentre(ws, a);
    for (long k = pos - w; k <= pos + w; ++k) {
      const auto j =
          static_cast<std::size_t>(ws.order[static_cast<std::size_t>(((k % mm) + mm) % mm)]);
      row[j] = coupleWeight(a, ws.cur[j], P, result);
    }
  }
}

// A row's lowest and second lowest weights, and the column of the lowest.
struct RowBest {
  std::size_t j = 0;
  double best = kMaxWeight, second = kMaxWeight;
};

RowBest rowBest(const Workspace& ws, std::size_t i) {
  const std::size_t m = ws.cur.size();
  RowBest r;
  for (std::size_t j = 0; j < m; ++j) {
    const double w = ws.weights[i * m + j];
    if (w < r.best) {
      r.second = r.best;
      r.best = w;
      r.j = j;
    } else if (w < r.second) {
      r.second = w;
    }
  }
  return r;
}

// Whether every other row of column j weighs more than `best` (row i is the column's strict
// minimum); `second` gets the lowest weight of those other rows.
bool isColumnMinimum(const Workspace& ws, std::size_t i, std::size_t j, double best,
                     double& second) {
  const std::size_t n = ws.prev.size(), m = ws.cur.size();
  second = kMaxWeight;
  bool minimum = true;
  for (std::size_t k = 0; k < n; ++k) {
    if (k == i) continue;
    const double w = ws.weights[k * m + j];
    if (w <= best) minimum = false;
    second = std::min(second, w);
  }
  return minimum;
}

// Step (4): the couples that are their row's and column's minimum, below max_weight and not
// ambiguous in their row or column; `rejections` counts why each other row gave none.
void associateCouples(const Workspace& ws, const MatcherParams& P, Couples& found,
                      MatchRejections& rejections) {
  found.clear();
  rejections = {};
  for (std::size_t i = 0; i < ws.prev.size(); ++i) {
    const RowBest r = rowBest(ws, i);
    double col_second = kMaxWeight;
    if (!(r.best < kMaxWeight)) {
      ++rejections.gated;
    } else if (!(r.best < P.max_weight)) {
      ++rejections.over_threshold;
    } else if (r.second < kMaxWeight && r.best > P.ambiguity_ratio * r.second) {
      ++rejections.ambiguous;
    } else if (!isColumnMinimum(ws, i, r.j, r.best, col_second)) {
      ++rejections.not_mutual;
    } else if (col_second < kMaxWeight && r.best > P.ambiguity_ratio * col_second) {
      ++rejections.ambiguous;
    } else {
      found.emplace_back(static_cast<int>(i), static_cast<int>(r.j));
    }
  }
}

// Steps (3) and (4) on the focused band, then on the full matrix if the band gave fewer than
// min_matches couples (or at once when the band would cover every column).
void weighAndAssociate(const MatcherParams& P, Workspace& ws, Couples& found, MatchResult& result) {
  const bool banded = P.band_half_width != 0 && ws.cur.size() > 2 * P.band_half_width + 1;
  weighCouples(!banded, P, ws, result);
  associateCouples(ws, P, found, result.rejections);
  if (!banded || found.size() >= P.min_matches) return;
  weighCouples(true, P, ws, result);
  associateCouples(ws, P, found, result.rejections);
  result.used_full_matrix = true;
}

// A pose solved from couples, with what match() returns about it.
struct PoseSolution {
  Pose2D T_prev_curr;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // (x, y, yaw): m^2, rad^2
  MatchStatus status = MatchStatus::kTooFewMatches;
  Eigen::Vector2d degenerate_direction = Eigen::Vector2d::Zero();
};

// Step (5), rotation: yaw (rad) and its variance (rad^2) as the inverse-variance weighted
// mean of the inlier couples' angle differences, linearised about around_yaw.
bool solveYaw(const Workspace& ws, const Couples& couples, const std::vector<char>& inlier,
              double around_yaw, double& yaw, double& var_yaw) {
  double sw = 0.0, swd = 0.0;
  std::size_t used = 0;
  for (std::size_t k = 0; k < couples.size(); ++k) {
    if (!inlier[k]) continue;
    const Line& p = ws.prev[couples[k].first];
    const Line& c = ws.cur[couples[k].second];
    bool flip = false;
    const double d = alignedAngle(p.theta, c.theta + around_yaw, flip);
    const double w = 1.0 / (p.var_theta + c.var_theta);
    sw += w;
    swd += w * d;
    ++used;
  }
  if (used < kMinCouples) return false;
  yaw = wrapAngle(around_yaw + swd / sw);
  var_yaw = 1.0 / sw;
  return true;
}

// Step (5): the rotation, then the translation by weighted least squares on rho. Along a
// direction with too little information (degeneracy_ratio) the translation of `around` is
// kept, with variance unconstrained_sigma_m^2. False when there is no solution.
bool solvePose(const Workspace& ws, const MatcherParams& P, const Couples& couples,
               const std::vector<char>& inlier, const Pose2D& around, PoseSolution& out) {
  double yaw = 0.0, var_yaw = 0.0;
  if (!solveYaw(ws, couples, inlier, around.yaw, yaw, var_yaw)) return false;
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < couples.size(); ++k) {
    if (!inlier[k]) continue;
    const Line& p = ws.prev[couples[k].first];
    const Line& c = ws.cur[couples[k].second];
    const AlignedCouple a = aligned(p, c, yaw);
    const double w = 1.0 / (p.var_rho + c.var_rho);
    A += w * a.normal * a.normal.transpose();
    b += w * a.normal * (p.rho - a.rho_c);
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(A);
  const Eigen::Vector2d lambda = eig.eigenvalues();  // ascending
  const Eigen::Matrix2d V = eig.eigenvectors();
  if (!(lambda(1) > 0.0)) return false;
  Eigen::Vector2d t;
  Eigen::Matrix2d cov_t;
  const bool degenerate = lambda(0) < P.degeneracy_ratio * lambda(1);
  if (degenerate) {
    const double u2 = P.unconstrained_sigma_m * P.unconstrained_sigma_m;
    const Eigen::Vector2d strong = V.col(1), weak = V.col(0);
    t = strong * (strong.dot(b) / lambda(1)) + weak * weak.dot(around.translation());
    cov_t = strong * strong.transpose() / lambda(1) + weak * weak.transpose() * u2;
  } else {
    t = A.ldlt().solve(b);
    cov_t = A.inverse();
  }
  out.T_prev_curr = {t.x(), t.y(), yaw};
  out.covariance.setZero();
  out.covariance.topLeftCorner<2, 2>() = cov_t;
  out.covariance(2, 2) = var_yaw;
  out.status = degenerate ? MatchStatus::kDegenerate : MatchStatus::kOk;
  out.degenerate_direction = degenerate ? Eigen::Vector2d(V.col(0)) : Eigen::Vector2d::Zero();
  return true;
}

// Outlier rejection: marks as outliers the inlier couples whose rho or theta residual under
// T_prev_curr exceeds outlier_sigmas standard deviations. Returns how many it marked.
std::size_t rejectOutliers(const Workspace& ws, const MatcherParams& P, const Couples& couples,
                           const Pose2D& T_prev_curr, std::vector<char>& inlier) {
  const Eigen::Vector2d t = T_prev_curr.translation();
  std::size_t dropped = 0;
  for (std::size_t k = 0; k < couples.size(); ++k) {
    if (!inlier[k]) continue;
    const Line& p = ws.prev[couples[k].first];
    const Line& c = ws.cur[couples[k].second];
    const AlignedCouple a = aligned(p, c, T_prev_curr.yaw);
    const double r = p.rho - a.rho_c - a.normal.dot(t);
    const double sigma = std::sqrt(p.var_rho + c.var_rho) + kOutlierSlackRhoM;
    const double sigma_th = std::sqrt(p.var_theta + c.var_theta) + kOutlierSlackThetaRad;
    if (std::abs(r) > P.outlier_sigmas * sigma ||
        std::abs(a.dtheta) > P.outlier_sigmas * sigma_th) {
      inlier[k] = 0;
      ++dropped;
    }
  }
  return dropped;
}

// Step (5) with outlier rejection, up to kSolveRounds solves, each about the last one's pose
// (the first about `estimate`). `kept` gets the couples that passed the last outlier test
// and `outliers` counts the others. False when not even the first solve succeeded.
bool solveWithoutOutliers(const Workspace& ws, const MatcherParams& P, const Couples& couples,
                          const Pose2D& estimate, PoseSolution& solution, Couples& kept,
                          std::size_t& outliers) {
  std::vector<char> inlier(couples.size(), 1);
  bool solved = false;
  for (int round = 0; round < kSolveRounds; ++round) {
    PoseSolution s;
    if (!solvePose(ws, P, couples, inlier, solved ? solution.T_prev_curr : estimate, s)) break;
    const std::size_t dropped = rejectOutliers(ws, P, couples, s.T_prev_curr, inlier);
    outliers += dropped;
    solution = s;
    solved = true;
    if (dropped == 0) break;
  }
  kept.clear();
  for (std::size_t k = 0; k < couples.size(); ++k) {
    if (inlier[k]) kept.push_back(couples[k]);
  }
  return solved;
}

// The covariance returned with the prior when nothing was learnt.
Eigen::Matrix3d uninformedCovariance(const MatcherParams& P) {
  const double u2 = P.unconstrained_sigma_m * P.unconstrained_sigma_m;
  return Eigen::Vector3d(u2, u2, kUninformedYawVarianceRad2).asDiagonal();
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
  // Counts that drive the work of one match are bounded (issue 16): a match costs at most
  // 2 x (iterations + 1) x max_segments^2 weights.
  if (iterations > kMaxIterations) detail::failKey("iterations", "<= 1000", static_cast<double>(iterations));
  if (max_segments < 2 || max_segments > kMaxSegments) {
    detail::failKey("max_segments", "in [2, 10000]", static_cast<double>(max_segments));
  }
  detail::requirePositive("outlier_sigmas", outlier_sigmas);
  detail::requireInRange("degeneracy_ratio", degeneracy_ratio, 0.0, 1.0);
  detail::requireSigmaM("unconstrained_sigma_m", unconstrained_sigma_m, false);
  detail::requireSigmaM("min_rho_sigma_m", min_rho_sigma_m, false);
  detail::requireSigmaRad("min_theta_sigma_rad", min_theta_sigma_rad, false);
}

SegmentMatcher::SegmentMatcher(const MatcherParams& params) : params_(params) { params_.validate(); }

MatchResult SegmentMatcher::match(const std::vector<Segment>& previous,
                                  const std::vector<Segment>& current, const Pose2D& prior) const {
  const MatcherParams& P = params_;
  MatchResult result;
  result.T_prev_curr = prior;
  result.covariance = uninformedCovariance(P);
  if (previous.empty() || current.empty()) return result;
  if (!(std::isfinite(prior.x) && std::isfinite(prior.y) && std::isfinite(prior.yaw))) return result;  // no prediction

  thread_local Workspace ws;
  prepareLines(previous, current, P, ws);
  result.segments_ignored = previous.size() - ws.prev.size() + current.size() - ws.cur.size();

  // Each iteration re-associates about the last estimate. One that gives no pose, or whose
  // outlier test leaves fewer than kMinCouples couples, is discarded whole, so that the pose,
  // covariance, status and matches returned all come from one iteration: the last good one.
  Pose2D estimate = prior;
  bool have_good = false;
  Couples found, kept;
  for (std::size_t iter = 0; iter <= P.iterations; ++iter) {
    predictPrevious(estimate, ws);
    weighAndAssociate(P, ws, found, result);
    if (found.size() < kMinCouples) break;
    result.iterations = iter + 1;
    PoseSolution s;
    if (!solveWithoutOutliers(ws, P, found, estimate, s, kept, result.rejections.outliers)) break;
    if (kept.size() < kMinCouples) break;
    estimate = s.T_prev_curr;
    result.T_prev_curr = s.T_prev_curr;
    result.covariance = s.covariance;
    result.status = s.status;
    result.degenerate_direction = s.degenerate_direction;
    result.matches.swap(kept);
    have_good = true;
  }
  if (!have_good) return result;  // still the prior, kTooFewMatches
  for (auto& [i, j] : result.matches) {  // back to the caller's indices
    i = ws.prev_index[static_cast<std::size_t>(i)];
    j = ws.cur_index[static_cast<std::size_t>(j)];
  }
  return result;
}

}  // namespace lidarseg
