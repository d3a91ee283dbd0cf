#pragma once
/// @file SegmentMatcher.h
/// Segment-based scan matching (paper §III.A): the rigid motion between two scans from
/// their high-level segments.

#include <cstddef>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/core/Pose2D.h"
#include "lidarseg/core/Segment.h"

namespace lidarseg {

/// Parameters of the segment matcher. Weights are sums of normalised differences; the
/// scales say what difference counts as "one unit".
struct MatcherParams {
  /// Accelerated weight (paper): when the predicted COG distance exceeds
  /// cog_gate_m + cog_gate_length_ratio * (the longer segment's length), the pair gets
  /// the maximum weight without computing the rest. The length term allows for the COG of
  /// a partly seen wall moving as more or less of it is visible.
  double cog_gate_m = 1.0;
  double cog_gate_length_ratio = 0.5;
  /// Normalising scales of the weight's terms.
  double rho_scale_m = 0.15;
  double theta_scale_rad = 0.1;
  double cog_scale_m = 0.75;
  /// Weight of the relative length difference (partial views change lengths).
  double length_weight = 0.5;
  /// A couple is accepted only with a weight below this.
  double max_weight = 3.0;
  /// Ambiguity: a couple is rejected when its weight is more than this fraction of the
  /// second best weight of its row or column (0..1]; 1 disables the test.
  double ambiguity_ratio = 0.9;
  /// Focused band: each previous segment is compared with the current segments whose
  /// bearing order is within this many places of its predicted bearing (paper: the
  /// diagonal, shifted by the predicted rotation). 0 = full matrix always.
  std::size_t band_half_width = 2;
  /// Fall back to the full matrix when the band yields fewer couples than this.
  std::size_t min_matches = 3;
  /// Re-association iterations after the first estimate (<= kMaxIterations).
  std::size_t iterations = 2;
  static constexpr std::size_t kMaxIterations = 1000;
  /// Latency bound: at most this many segments of each scan are considered, the longest
  /// ones (a cluttered or pathological scan can hold thousands). With it, one match costs
  /// at most 2 x (iterations + 1) x max_segments^2 weights, whatever the scan. In
  /// [2, kMaxSegments].
  std::size_t max_segments = 128;
  static constexpr std::size_t kMaxSegments = 10000;
  /// Couples whose line residual exceeds this many standard deviations are dropped.
  double outlier_sigmas = 4.0;
  /// Degenerate when the translation's information along its weakest direction is below
  /// this fraction of the strongest one (a corridor of parallel walls).
  double degeneracy_ratio = 1e-3;
  /// Standard deviation given to the translation along an unconstrained direction, where
  /// the prediction is kept (m).
  double unconstrained_sigma_m = 1.0;
  /// Floor on each line's (rho, theta) standard deviations, for numerically well-posed
  /// weights with noiseless data (m, rad).
  double min_rho_sigma_m = 0.002;
  double min_theta_sigma_rad = 0.0005;

  /// @throws std::invalid_argument naming the key ("matcher_..." style without prefix).
  void validate() const;
};

/// Why a match ended as it did.
enum class MatchStatus {
  kOk,              ///< the motion is constrained in every direction
  kDegenerate,      ///< translation unconstrained along `degenerate_direction`: kept the prediction there
  kTooFewMatches,   ///< fewer than 2 couples (or no constraint at all): the prediction is returned
};
const char* toString(MatchStatus s);

/// Why rows of the weight matrix (previous segments) gave no couple, in the last
/// association of a match: the reasons a match fails, counted (issue: failures on real data).
struct MatchRejections {
  std::size_t gated = 0;           ///< every candidate beyond the COG gate (or outside the band)
  std::size_t over_threshold = 0;  ///< best weight not below max_weight
  std::size_t ambiguous = 0;       ///< best weight too close to the row's or column's second best
  std::size_t not_mutual = 0;      ///< the column's best is another row
  std::size_t outliers = 0;        ///< couples dropped by the residual test
  /// The most frequent reason ("gated", "over_threshold", "ambiguous", "not_mutual",
  /// "outliers"), or "none".
  const char* dominant() const;
};

/// Result of matching two scans. status, T_prev_curr, covariance, degenerate_direction and
/// matches all come from one iteration: the last whose outlier test kept at least 2 couples
/// (an iteration left with fewer is discarded whole); with none, the prior and kTooFewMatches.
struct MatchResult {
  MatchStatus status = MatchStatus::kTooFewMatches;
  /// Pose of the current sensor frame in the previous one (T_prev_curr).
  Pose2D T_prev_curr;
  /// Covariance of (x, y, yaw) of T_prev_curr (m^2, rad^2).
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  /// Couples (previous index, current index) of the final estimate's iteration that passed
  /// its last outlier test; empty with kTooFewMatches.
  std::vector<std::pair<int, int>> matches;
  /// Unit direction (previous frame) along which the translation is unconstrained.
  Eigen::Vector2d degenerate_direction = Eigen::Vector2d::Zero();
  /// Weights evaluated and how many of them the COG gate short-cut, over all iterations.
  std::size_t weights_computed = 0;
  std::size_t weights_gated = 0;
  /// Segments left out by MatcherParams::max_segments (previous + current).
  std::size_t segments_ignored = 0;
  /// Whether the focused band had to fall back to the full matrix.
  bool used_full_matrix = false;
  /// Iterations that reached the pose solve, a discarded last one included.
  std::size_t iterations = 0;
  /// Why previous segments found no couple (last association).
  MatchRejections rejections;
};

/// Matches the high-level segments of two consecutive scans (paper §III.A, five steps):
/// (1) take the segments, (2) predict the previous ones into the current frame with the
/// motion prior, (3) weight the couples on the focused band of the weight matrix with the
/// accelerated (gated) weight, (4) keep mutual minima below a threshold that are not
/// ambiguous, (5) solve the rigid motion from the matched lines: rotation from their
/// directions, translation by weighted least squares on rho with the segments'
/// covariances, dropping outlier couples; then re-associate a few times about the estimate.
/// Never throws on data: a failure is a status (a non-finite prior: kTooFewMatches). O(n *
/// band) weights per iteration.
class SegmentMatcher {
 public:
  /// @throws std::invalid_argument for invalid parameters.
  explicit SegmentMatcher(const MatcherParams& params = {});

  /// @param previous segments of the previous scan (its sensor frame)
  /// @param current segments of the current scan (its sensor frame)
  /// @param prior predicted T_prev_curr (constant velocity or odometry)
  MatchResult match(const std::vector<Segment>& previous, const std::vector<Segment>& current,
                    const Pose2D& prior) const;

  const MatcherParams& params() const { return params_; }

 private:
  MatcherParams params_;
};

}  // namespace lidarseg
