#pragma once
/// @file ScanRefiner.h
/// Precise pose refinement after the segment match (beyond the paper): the current scan's
/// own points against the keyframe's low-level segments taken as finite lines.

#include <cstddef>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/core/Pose2D.h"
#include "lidarseg/core/Segmentation.h"

namespace lidarseg {

/// Parameters of the point-to-segment refinement.
struct RefinerParams {
  /// Whether the odometry refines its matches at all.
  bool enabled = true;
  /// Cascade level of the keyframe's segments the points are matched to. The low level
  /// keeps the short segments (door jambs, recesses, pillars) that constrain the motion
  /// along a corridor.
  CascadeLevel level = CascadeLevel::kWallDanielsson;
  /// Keyframe segments with fewer points than this are not used (their line is unknown).
  std::size_t min_segment_points = 3;
  /// Whether the keyframe points no usable segment holds (clutter, jambs, posts, wall
  /// ends) are used too: joined to a neighbour within max_distance_m as a two-point line
  /// (point to line, as PL-ICP); without one, a point on its two neighbours' line (within
  /// robust_scale_m: a surface seen at grazing incidence) as that line, any other as a lone
  /// point (point to point); a point next to an invalid beam is left out. Along a corridor
  /// they are what constrains the motion; a featureless corridor has none (its grazing wall
  /// samples pair along the walls only).
  bool unsegmented_points = true;
  /// Gauss-Newton iterations at most; each re-associates the points.
  std::size_t max_iterations = 10;
  /// The largest max_iterations accepted.
  static constexpr std::size_t kMaxIterations = 1000;
  /// A point is paired only with a segment whose line is closer than this (m).
  double max_distance_m = 0.3;
  /// Scale of the Cauchy loss on the point-to-line residuals (m): residuals well below it
  /// count fully, far beyond it hardly at all.
  double robust_scale_m = 0.05;
  /// Scale of the Cauchy loss in the first Gauss-Newton iteration of a refinement from a
  /// guessed start (refine's `guessed_start`) (m); it halves at each iteration down to
  /// robust_scale_m, and the refinement ends only at robust_scale_m. A start off by more than
  /// robust_scale_m along a corridor is pulled only by the few jamb or recess points, at
  /// residuals the final loss hardly counts: the wider first loss lets them pull (graduated
  /// robustness). Beyond max_distance_m, max_distance_m is used; 0 (or at most
  /// robust_scale_m): no schedule. When max_iterations run out before the scale reaches
  /// robust_scale_m (fewer iterations than halvings), the result's statistics are the last
  /// scale's.
  double initial_scale_m = 0.15;
  /// How far beyond a segment's end a point's projection may fall and still pair with it
  /// (m): the segment is finite, so a wall's points do not slide onto a jamb's extension.
  double endpoint_margin_m = 0.0;
  /// Keyframe beams searched on each side of a point's bearing for candidate segments.
  std::size_t bearing_window = 3;
  /// Standard deviation of one point across its line (m), floor of the estimate from the
  /// residuals (a noiseless simulation would otherwise give a zero covariance).
  double min_point_sigma_m = 0.005;
  /// Model error added to the covariance, per direction (m, m, rad): what the residuals
  /// cannot show (the keyframe's own distortion when it was deskewed with a wrong velocity,
  /// the segments' fits). Measured against ground truth: docs/results.md (NEES).
  double model_sigma_m = 0.005;
  double model_sigma_rad = 0.0005;
  /// Points per independent measurement: neighbouring points of one segment share the
  /// segment's modelling error (a wall is not a perfect line, the scan is deskewed with an
  /// estimated velocity), so the information of n points is counted as n / this.
  double correlation_length_points = 4.0;
  /// A refinement whose inlier ratio (points paired within 3 robust scales, out of those
  /// looking where the keyframe saw a segment) is below this is reported as failed: the
  /// initial pose was too far off, or the scans do not overlap.
  double min_inlier_ratio = 0.3;
  /// Points of the current scan used at most (evenly thinned beyond): bounds the cost of a
  /// dense scan.
  std::size_t max_points = 400;
  /// The largest max_points accepted (the log readers' beam cap).
  static constexpr std::size_t kMaxPoints = 100000;
  /// At least this many points must pair for any estimate.
  std::size_t min_points = 20;
  /// A direction of the information (yaw scaled by the points' RMS range) is unconstrained
  /// when it holds less than this many points' worth (a point counts 1 along its segment's
  /// normal, less with its robust weight): one door jamb's few points are enough, the
  /// grazing noise of a featureless corridor's walls is not...
  double min_constraint_points = 3.0;
  /// ...or less than this fraction of the strongest direction (numerical safety).
  double degeneracy_ratio = 1e-5;
  /// Standard deviation along an unconstrained direction, where the initial pose is kept (m).
  double unconstrained_sigma_m = 1.0;
  /// Stop when a step moves less than this (m, and the same in rad per metre of range).
  double convergence_m = 1e-3;
  /// After a step moving the points by less than this (m, the same measure), the next
  /// iteration keeps the points' pairings instead of searching them again (0 = always
  /// search, the default). 0.01 makes the real logs' median scan 1.4-1.6 times faster but
  /// moves two of them above ICP's median error (docs/performance.md): a speed setting.
  double reassociate_m = 0.0;

  /// @throws std::invalid_argument naming the key (as in the [refiner] section).
  void validate() const;
};

/// Why a refinement ended as it did.
enum class RefineStatus {
  kOk,          ///< every direction constrained
  kDegenerate,  ///< one direction unconstrained: the initial pose is kept along it
  kFailed,      ///< too few points paired, or a low inlier ratio: do not trust the pose
};
const char* toString(RefineStatus s);

/// Result of one refinement.
struct RefineResult {
  RefineStatus status = RefineStatus::kFailed;
  /// Pose of the current sensor frame in the keyframe's (T_key_curr).
  Pose2D T_key_curr;
  /// Covariance of (x, y, yaw) of T_key_curr from the final normal equations (m^2, rad^2).
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  /// Valid points of the current scan considered (after thinning to max_points).
  std::size_t points = 0;
  /// Points whose bearing (at the final pose) has a keyframe segment within about 2
  /// degrees: those that could pair at all (the rest look where the keyframe saw nothing).
  std::size_t covered = 0;
  /// Points paired within 3 robust scales at the final pose.
  std::size_t inliers = 0;
  /// inliers / covered.
  double inlier_ratio = 0.0;
  /// Root mean square of the inliers' residuals (m).
  double rms_m = 0.0;
  /// Root mean square range of the points used (m): the lever arm of a rotation.
  double rms_range_m = 0.0;
  std::size_t iterations = 0;
  /// The last Gauss-Newton step moved the points less than convergence_m (false: the
  /// iterations ran out while the pose was still moving, e.g. sliding along a corridor).
  bool converged = false;
  /// With status kDegenerate: the translation part of the least constrained direction of the
  /// information (x, y, yaw scaled by rms_range_m), normalised (keyframe frame); zero when that
  /// part is negligible. When the weak direction is mostly yaw this points where the
  /// translation is constrained: the covariance along it tells (unconstrained_sigma_m^2 when
  /// it is truly free).
  Eigen::Vector2d degenerate_direction = Eigen::Vector2d::Zero();
  /// With a SweepModel: the correction to the rotation rate the current scan was deskewed
  /// with (rad/s), estimated with the pose (0 without one).
  double sweep_rate_correction = 0.0;
};

/// The current scan's sweep as a fourth unknown of the refinement: each point was measured
/// time_offsets_s[beam] after the scan's stamp and deskewed with a rotation rate that may be
/// wrong by a correction c (rad/s); the point is turned by c t about the sensor and c is
/// estimated with the pose, under a zero-mean prior of standard deviation prior_sigma_rad_s,
/// within 3 of them.
/// A sweep as long as the period (a 360-degree scanner at 5 Hz) spans the motion to the next
/// scan, which no prior from the past knows at a turn's onset; the scan's own distortion does.
struct SweepModel {
  const std::vector<double>* time_offsets_s = nullptr;  ///< per beam of the current scan (s)
  double prior_sigma_rad_s = 1.0;
};

/// A keyframe prepared for refinement (ScanRefiner::prepare): its usable segments as finite
/// lines and the bearing index of its points. Build it once per keyframe and refine every
/// scan matched against that keyframe with it. Reuse one object: it keeps its buffers.
struct RefinementKeyframe {
  /// A segment as a finite line, keyframe sensor frame (m).
  struct Line {
    Eigen::Vector2d normal, start, direction;
    double rho = 0.0, length = 0.0;
  };
  std::vector<Line> lines;
  /// Line of each beam, -1 when none.
  std::vector<int> beam_line;
  /// Pseudo-bearing (monotonic in the bearing, [0, 4) over a turn) of every point that
  /// belongs to a line, sorted, and that line.
  std::vector<double> bearing;
  std::vector<int> line_of;
  /// bin_start[b]: the first sorted entry whose pseudo-bearing is >= b * 4 / (bins).
  std::vector<int> bin_start;
  /// Scans merged (a local map of several keyframes): the bearing window grows with them.
  std::size_t scans = 0;
  /// Sorted entries searched on each side of a point's place in `bearing`: the preparing
  /// refiner's bearing_window, doubled for a local map (at most the entries).
  std::size_t window = 0;
  /// The distinct lines of each place's window, in the order the window meets them:
  /// place k (0 <= k < entries; the first entry at or after a point's pseudo-bearing, the
  /// end wrapping to 0) holds window_lines[window_start[k] .. window_start[k + 1]).
  /// Made once per keyframe, so that a point's pairing visits each line once.
  std::vector<int> window_start;
  std::vector<int> window_lines;
  /// Preparation's scratch buffers.
  std::vector<int> seen;
  std::vector<std::pair<double, int>> scratch;
};

/// One scan of a local map: its segmentation and its pose in the reference keyframe's frame.
struct RefinementMapScan {
  const Segmentation* segmentation = nullptr;
  Pose2D T_key_scan;
};

/// Refines T_key_curr by robust Gauss-Newton on point-to-line distances: each valid point of
/// the current scan, moved into the keyframe's frame, is paired with the nearest finite
/// keyframe segment among those covering the keyframe beams around its bearing (no k-d
/// tree: the scans' bearing order is the index). Cauchy loss; the covariance is the inverse
/// of the final normal equations scaled by the residuals' variance and by the points'
/// correlation length. A degenerate direction (a featureless corridor) keeps the initial
/// value and gets RefinerParams::unconstrained_sigma_m.
/// Never throws on data (a non-finite initial pose: kFailed). O(iterations * points * (log
/// beams + bearing_window)).
/// Thread-safe: the scratch buffers are per thread.
class ScanRefiner {
 public:
  /// @throws std::invalid_argument for invalid parameters.
  explicit ScanRefiner(const RefinerParams& params = {});

  /// @param keyframe segmentation of the keyframe (its points and segments, sensor frame)
  /// @param current segmentation of the current scan (only its points are used)
  /// @param initial starting T_key_curr (the segment match, or a prior)
  RefineResult refine(const Segmentation& keyframe, const Segmentation& current,
                      const Pose2D& initial) const;
  /// The same against a prepared keyframe (no per-call preparation; its bearing window is
  /// that of the refiner that prepared it).
  RefineResult refine(const RefinementKeyframe& keyframe, const Segmentation& current,
                      const Pose2D& initial) const;
  /// The same with the sweep's rotation rate estimated too (see SweepModel; `sweep` null or
  /// without times: the overload above). `guessed_start`: `initial` is a guess whose error
  /// is not bounded by robust_scale_m (no motion measured yet): the loss starts at
  /// RefinerParams::initial_scale_m (decision 112).
  RefineResult refine(const RefinementKeyframe& keyframe, const Segmentation& current, const Pose2D& initial,
                      const SweepModel* sweep, bool guessed_start = false) const;

  /// Prepares `keyframe` for refinements: O(beams x bearing_window).
  void prepare(const Segmentation& keyframe, RefinementKeyframe& out) const;
  /// Prepares a local map: several scans' segments moved into the reference keyframe's
  /// frame (the points pair with the nearest line around their bearing, whichever scan it
  /// came from). O(total beams x (log + bearing_window)).
  void prepare(const std::vector<RefinementMapScan>& scans, RefinementKeyframe& out) const;

  const RefinerParams& params() const { return params_; }

 private:
  RefinerParams params_;
};

}  // namespace lidarseg
