#pragma once
/// @file SegmentOdometry.h
/// Laser odometry from consecutive scans: segment each scan once, match it with the
/// previous one, integrate the motion.

#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/core/CorrelativeSearch.h"
#include "lidarseg/core/Pose2D.h"
#include "lidarseg/core/Scan.h"
#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/core/ScanRefiner.h"
#include "lidarseg/core/SegmentMatcher.h"

namespace lidarseg {

/// Parameters of the laser odometry.
struct OdometryParams {
  SegmentationParams segmentation;
  MatcherParams matcher;
  /// Point-to-segment refinement of every match (beyond the paper).
  RefinerParams refiner;
  /// Correlative search around the prior when neither the segment match nor the
  /// refinement from the prior holds (beyond the paper).
  SearchParams search;
  /// Whether the search runs at all; without it, such a scan is lost at once.
  bool recovery = true;
  /// A refinement is doubtful when its inlier ratio is below this fraction of the running
  /// mean of the last scans' ratios; it is then also refined from the prior and, if still
  /// doubtful, the search runs and the hypothesis pairing the most points wins. 0 = only
  /// failed refinements are doubtful.
  double doubtful_ratio = 0.9;
  /// When the segment match (or the search) and the prior lead to different poses, the
  /// prior's refinement is kept unless it is doubtful or the other pairs more than
  /// (1 + this) times as many points: a corridor's walls pair almost as well one door
  /// further, and the prior is what tells the two apart.
  double prior_preference = 0.15;
  /// A search hypothesis replaces the best refinement found from the prior and the segment
  /// match, when that one holds, only if it pairs more than (1 + this) times as many points
  /// (decision 81). 0 = any hypothesis that pairs more.
  double search_preference = 0.15;
  /// Whether a doubtful (not only a failed) refinement also runs the search.
  bool search_when_doubtful = true;
  /// Whether a keyframe whose sweep lies after its stamp (stamped at its first beam) is
  /// revised at the next scan: its sweep lies in the interval to that scan, whose rotation
  /// rate was unknown when it was deskewed (the rate of the interval before was used). When
  /// the rate measured over that interval differs by more than deskew_tolerance_rad over the
  /// sweep, the keyframe is segmented again with it and refined again against its own
  /// reference; when that pairs at least as many points with a lower inlier RMS (and is not
  /// degenerate where the first fit was constrained), and the current scan, refined again
  /// against it, holds, the keyframe's pose and segments are replaced (decision 114).
  bool revise_keyframe = true;
  /// Whether a deskewed scan's covariance includes the rolling-shutter correction's own error,
  /// which no residual shows: a scan deskewed with a motion off by d (m/s, rad/s) over a sweep
  /// of T seconds is bent by up to d T, and its fit moved by about half of that. d is the
  /// motion's recent change: the interval's measured motion against the one the scan was
  /// deskewed with and against the interval before (the larger of each); the keyframe's term
  /// is added too. Only the covariance changes, not the pose (decision 117).
  bool deskew_covariance = true;
  /// When the segment match and the refinements from the prior and from the first search
  /// all failed (the scan would be lost), a second search over a window this many times
  /// wider (translation and rotation; at most 20 m and pi) runs first: a prior wrong by more
  /// than the first window (wheel odometry slipping by 2 m or 50 deg). Its refinement must
  /// be constrained in every direction (not degenerate). 1 = no second search (decision 83).
  double wide_search_factor = 2.0;
  /// Whether the segment match's refinement is also refined from the prior when the two
  /// disagree by more than prior_gate_sigmas standard deviations of the prior's error (below)
  /// and of the refinement's own covariance along their difference, in translation or in
  /// yaw. A corridor's walls pair about as well one pillar face or door jamb further along,
  /// and the match may lock onto that; the prior's refinement is then the reference, as
  /// when the match moved beyond max_distance_m (decision 75). With wheel odometry it acts
  /// only when odometry_error_ratio is set (otherwise the prior's error is unbounded).
  bool check_match_against_prior = true;
  /// Whether a degenerate fit (free along one direction: a corridor's axis) takes its pose
  /// along that direction from the prior, refined again from there. The scan says nothing
  /// along it, and the value the fit kept is wherever its hypothesis started: a segment match
  /// or a search hypothesis one bay away, which the constant-velocity prior then carries on
  /// through the whole corridor (decision 98). With wheel odometry, the odometry's value.
  bool degenerate_along_prior = true;
  /// Whether a degenerate fit's motion along its free direction (a corridor's axis, where its
  /// position came from the prior or from wherever its hypothesis left it, not from the
  /// scan) is kept out of the constant-velocity estimate: the velocity along that direction
  /// stays what the steps before measured. Without it, one scan placed a bay off at a
  /// corridor's entrance set a velocity that every later degenerate step reproduced (the
  /// 181-beam SICK at 5 Hz with keyframes every 0.3 rad: 23 m off; decision 111).
  bool degenerate_keeps_velocity = true;
  /// How far the prior may plausibly be wrong, which bounds how far from it the correlative
  /// search's hypothesis may replace the prior's own refinement while that one holds:
  /// prior_gate_sigmas standard deviations of the prior's error, and never less than
  /// RefinerParams::max_distance_m and prior_gate_floor_rad. Without wheel odometry the error
  /// is that of a constant velocity under an unknown acceleration, 0.5 a dt^2
  /// (prior_accel_m_s2, prior_angular_accel_rad_s2); with it, odometry_error_ratio of the
  /// odometry's own step, 0 = no gate (the default: wheel odometry can be wrong by any
  /// amount; on the real logs a gate of even 1x the odometry's step cost accuracy). Beyond
  /// the gate the search's hypothesis replaces the prior's refinement only when that one
  /// failed: pairing more points one corridor bay further is not evidence enough against a
  /// prior that holds. The segment match is not gated (decision 64: stamp jitter makes a
  /// constant-velocity prior wrong by more than the acceleration says, and the match, which
  /// pairs whole segments, was right there); it is only checked against the prior
  /// (check_match_against_prior), which adds the prior's refinement as the reference.
  double prior_gate_sigmas = 3.0;
  double prior_accel_m_s2 = 2.0;
  double prior_angular_accel_rad_s2 = 4.0;
  double odometry_error_ratio = 0.0;
  double prior_gate_floor_rad = 0.15;
  /// The refinement pairs the points with the segments of this many keyframes (the current
  /// one and the previous ones, moved into its frame): a local map. 1 = the keyframe alone.
  /// 2 measured better than 1 on the real logs and the hospital, worse on the 5 Hz maze
  /// (decision 40), at about 1.5 times the cost.
  std::size_t local_map_keyframes = 2;
  /// Cascade level whose segments are matched (paper: the high level).
  CascadeLevel level = CascadeLevel::kFusedAgain;
  /// When the match at `level` is degenerate (a corridor), match again at this finer level
  /// (more, shorter segments: door recesses, jambs) and keep that match if it constrains
  /// every direction. Equal to `level` (or coarser) disables the fallback.
  CascadeLevel degenerate_fallback_level = CascadeLevel::kFused;
  /// Keyframes (beyond the paper): each scan is matched against the last keyframe, which
  /// is renewed once the sensor has moved this far (m) or turned this much (rad) from it,
  /// or when a match fails. Matching against a keyframe instead of the previous scan adds
  /// the noise of one match per keyframe, not per scan. Both 0: every scan is a keyframe
  /// (the paper's scan-to-scan matching).
  double keyframe_distance_m = 1.0;
  double keyframe_angle_rad = 0.2;
  /// Correct each scan for the motion during its sweep (rolling shutter), with the
  /// estimated velocity, when the scan has per-beam time offsets.
  bool deskew = true;
  /// The velocity (for the constant-velocity prior and the rolling-shutter correction) is
  /// the mean motion over this much past time (s): one step's translation is too noisy.
  double velocity_window_s = 0.2;
  /// The angular velocity reacts faster (a turn starts abruptly and rotation is what
  /// distorts a scan most), over this window (s).
  double angular_velocity_window_s = 0.1;
  /// When the rotation measured by the match differs from the one used to correct the
  /// scan by more than this over a sweep (rad), the scan is corrected again and re-matched.
  double deskew_tolerance_rad = 0.002;
  /// Estimate a full-turn sweep's rotation rate with its pose (ScanRefiner's SweepModel)
  /// when the rate may have changed since the last scan by enough to turn the sweep's last
  /// beam by more than deskew_tolerance_rad (prior_angular_accel_rad_s2 x dt x sweep): a
  /// 360-degree scanner at 5-10 Hz. Faster scanners and partial sweeps are not affected.
  bool estimate_sweep_rate = true;
  /// Rotation frequency of the scanner's mirror (Hz) for scans without per-beam times:
  /// beam i is then taken at i * (beam spacing) / (2 pi f) after the first, as a spinning
  /// scanner measures them (e.g. 50 for a SICK LMS100 at 50 Hz). 0 = the beams of such
  /// scans are taken as simultaneous (no rolling-shutter correction).
  double scanner_rotation_hz = 0.0;
  /// Which beam's instant the scans' stamps are (for scans given beam times from
  /// scanner_rotation_hz): the beam times are then relative to that beam.
  ScanStamp scan_stamp = ScanStamp::kFirst;

  void validate() const;
};

/// How a scan was tracked.
enum class TrackStatus {
  kFirst,       ///< the first scan: the origin
  kOk,          ///< matched (and refined); every direction constrained
  kDegenerate,  ///< matched, but one direction was unconstrained and kept from the prior
  kRecovered,   ///< the match and the refinement from the prior failed; the search found it
  kLost,        ///< every hypothesis failed: the prediction is kept, with a large covariance
};
const char* toString(TrackStatus s);

/// A keyframe revised at the next scan (decision 114).
struct KeyframeRevision {
  /// Its revised T_odom_sensor.
  Pose2D T_odom_sensor;
  /// Its segmentation again with the rotation rate measured over its sweep.
  std::shared_ptr<const Segmentation> segmentation;
};

/// One step of the odometry.
struct OdometryStep {
  std::size_t index = 0;
  double stamp_s = 0.0;
  /// Pose of the sensor in the odometry frame (the first scan's sensor frame).
  Pose2D T_odom_sensor;
  /// Motion since the previous scan, T_prev_curr, and the covariance (x, y, yaw) of the
  /// motion from the keyframe, T_keyframe_curr: the refinement's (or the segment match's),
  /// plus, for a deskewed scan, the rolling-shutter corrections' own error of the scan and
  /// of its keyframe (OdometryParams::deskew_covariance, decision 117).
  Pose2D increment;
  Eigen::Matrix3d increment_covariance = Eigen::Matrix3d::Zero();
  /// The predicted motion since the previous scan (constant velocity or wheel odometry).
  Pose2D prior;
  /// The prediction the matcher started from: T_keyframe_curr.
  Pose2D prior_from_keyframe;
  /// Cascade level of the segments `match` couples (the degenerate fallback's when kept).
  CascadeLevel matched_level = CascadeLevel::kFusedAgain;
  /// Matching details (status, couples, weights) against the keyframe; empty for the
  /// first scan. match.T_prev_curr is T_keyframe_curr.
  MatchResult match;
  /// The point-to-segment refinement that gave the pose (status kFailed when none held).
  RefineResult refine;
  /// The correlative search, when it ran (the wider one's, when that ran too).
  std::optional<SearchResult> search;
  /// Whether the wider second search ran (OdometryParams::wide_search_factor).
  bool wide_search = false;
  /// Whether the scan was segmented again for the rotation rate its refinement measured
  /// (tried whenever the rate it was deskewed with differed by more than
  /// deskew_tolerance_rad over the sweep; decision 90).
  bool deskewed_again = false;
  /// The motion (sensor frame) this scan's segments were deskewed with in the end: the
  /// prediction, none (the match held only without motion), the rate a match or the
  /// refinement measured, or the sweep's estimated rate (zero without beam times).
  Twist2D deskewed_with;
  /// How this scan was tracked; the pose is T_keyframe_curr of `refine` unless kLost.
  TrackStatus status = TrackStatus::kFirst;
  /// When the previous scan, the keyframe, was revised with the rotation rate measured over
  /// its sweep (OdometryParams::revise_keyframe; decision 114): its revised pose and
  /// segments. `match`, `prior_from_keyframe` and `search` refer to the keyframe before its
  /// revision; `refine` to the revised one. The pose reported for that scan is not changed (each step's output is
  /// causal); this scan's pose was refined against the revised keyframe, and `increment`
  /// (from the pose reported for the previous scan) includes the revision's correction while
  /// `increment_covariance` is that of the refinement against the revised keyframe.
  std::optional<KeyframeRevision> keyframe_revision;
  /// Whether this scan became the keyframe.
  bool keyframe = false;
  bool first = false;
  /// Wall-clock time of each stage (microseconds).
  double wall_danielsson_us = 0.0;
  double cascade_us = 0.0;
  double matching_us = 0.0;
  /// Refinement and (when it ran) search; part of the matching time above.
  double refinement_us = 0.0;
  /// Indexing this scan as the new keyframe (and local map) for the next scans' refinements,
  /// when it became one; part of the matching time above, so that a scan's time is all the
  /// work done for it.
  double keyframe_us = 0.0;
};

/// Laser odometry with the segment matcher. Each scan is segmented once; the keyframe's
/// segments are kept for the next scans. The prior is the constant-velocity prediction (the previous
/// increment scaled to the time elapsed), or, when given, the wheel-odometry increment.
/// Each segment match (paper §III.A) is refined with the scan's points against the local
/// map's segments (ScanRefiner); when neither it nor a refinement from the prior holds, a
/// correlative search around the prior (CorrelativeSearch) is refined instead. When all of
/// them fail the scan is lost: the prior is kept and the step's covariance says so
/// (OdometryStep::status; docs/architecture.md, "Matching a scan").
class SegmentOdometry {
 public:
  /// @throws std::invalid_argument for invalid parameters.
  explicit SegmentOdometry(const OdometryParams& params = {});

  /// Processes the next scan.
  /// @param odometry_increment wheel odometry T_prev_curr of the sensor since the
  ///        previous scan, used as the prior instead of constant velocity.
  /// @throws std::invalid_argument for an inconsistent scan (see Scan::validate()), a
  ///         non-finite stamp, or an odometry_increment not finite or beyond +-1e7
  ///         (kMaxRelativeCoordinate); the odometry's state is then unchanged.
  OdometryStep process(const Scan& scan, const std::optional<Pose2D>& odometry_increment = {});

  /// The segmentation of the last scan processed.
  const Segmentation& lastSegmentation() const { return segmentation_[current_]; }
  const Pose2D& pose() const { return pose_; }
  /// Current velocity estimate, in the sensor frame.
  const Twist2D& velocity() const { return velocity_; }
  void reset();

 private:
  /// Records the pose at `stamp` and updates the constant-velocity estimate; `free_odom`
  /// (odometry frame, unit, or zero): a direction the step did not measure, along which the
  /// velocity keeps its earlier value (decision 111).
  void remember(double stamp, const Eigen::Vector2d& free_odom = Eigen::Vector2d::Zero());
  /// Segments `scan` deskewed with `motion` into the slot and records the motion (slot_motion_).
  void segmentInto(const Scan& scan, int slot, const Twist2D& motion, OdometryStep& step);
  /// Wall-Danielsson segmentation and the cascade into `out`, their times added to `step`.
  void segment(const Scan& scan, const Twist2D& motion, Segmentation& out, OdometryStep& step) const;
  MatchResult matchWithKeyframe(int slot, const Pose2D& prior, OdometryStep& step) const;
  /// The gate of the prior (translation m, rotation rad): see OdometryParams::prior_gate_sigmas.
  struct PriorGate {
    double translation_m = 0.0, rotation_rad = 0.0;
    /// Standard deviation of the prior's error (m, rad): infinite when unknown.
    double sigma_m = 0.0, sigma_rad = 0.0;
    /// The prior is wheel odometry (independent of the poses estimated so far), not the
    /// constant velocity of the last estimates.
    bool wheel_odometry = false;
  };
  PriorGate priorGate(double dt, const std::optional<Pose2D>& odometry_increment) const;
  /// A refinement is doubtful when it failed, or pairs clearly fewer points than the last
  /// scans did (its inlier ratio below doubtful_ratio times their running mean).
  bool doubtful(const RefineResult& r) const;
  /// T_key_curr lies within the prior's gate around `prior` (both keyframe frame).
  static bool withinGate(const Pose2D& T_key_curr, const Pose2D& prior, const PriorGate& gate);
  /// Refines the match (or recovers from a failed one) into step.refine and step.status;
  /// returns T_keyframe_curr. `sweep`: the scan's sweep model when its rotation rate is
  /// estimated with the pose (decision 95), else nullptr.
  Pose2D refineWithKeyframe(int slot, const Pose2D& prior, const PriorGate& gate, const SweepModel* sweep,
                            OdometryStep& step);
  /// Segments the scan again with the rotation rate of T_key_curr when it differs from the
  /// rate `used` by more than deskew_tolerance_rad over the sweep, and refines again from
  /// T_key_curr; returns the pose kept.
  Pose2D deskewWithRefinedMotion(const Scan& scan, int slot, double dt, const Twist2D& used, const Pose2D& T_key_curr,
                                 OdometryStep& step);
  /// The direction (keyframe frame, unit) along which a degenerate fit is truly free: its
  /// translation variance there is at least half the unconstrained one's (a yaw-mostly weak
  /// direction whose translation part the points constrain is not). Nullopt otherwise, and
  /// for a fit that is not degenerate (decisions 98 and 111).
  std::optional<Eigen::Vector2d> freeDirection(const RefineResult& fit) const;
  /// The revision of the keyframe at the next scan (OdometryParams::revise_keyframe);
  /// returns the current scan's T_key_curr against the (possibly revised) keyframe.
  Pose2D reviseKeyframe(double dt, const Pose2D& T_key_curr, OdometryStep& step);
  /// Prepares `keyframe` at `keyframe_pose` with the local map's scans for the refinements.
  void prepareIndex(const Segmentation& keyframe, const Pose2D& keyframe_pose, RefinementKeyframe& index);
  /// Prepares the keyframe (and the local map) for the refinements.
  void prepareKeyframe(OdometryStep& step);
  Twist2D meanVelocity(double stamp, double window) const;
  const Scan& withBeamTimes(const Scan& scan);

  OdometryParams params_;
  ScanSegmenter segmenter_;
  SegmentMatcher matcher_;
  ScanRefiner refiner_;
  RefinementKeyframe refine_keyframe_;  // the keyframe (and local map) prepared for refinements
  struct MapKeyframe {
    Segmentation segmentation;
    Pose2D T_odom_sensor;
  };
  std::vector<MapKeyframe> map_;  // ring of the previous keyframes of the local map
  std::size_t map_next_ = 0;      // the slot the next one goes to
  std::size_t map_size_ = 0;      // how many slots hold a keyframe
  std::vector<RefinementMapScan> map_scans_;
  CorrelativeSearch search_;
  CorrelativeSearch wide_search_;  // search_ over a window wide_search_factor times wider
  SearchGrid search_grid_;  // the keyframe rasterised for the search, made when first needed
  Segmentation segmentation_[2];  // the keyframe's and the current scan's
  Twist2D slot_motion_[2];        // the motion each slot's segmentation was deskewed with
  /// What the keyframe's revision needs (decision 114): its scan, the reference it was refined
  /// against (prepared), that reference's pose, and the refinement's pose and counts.
  struct KeyframeOrigin {
    bool revisable = false;
    std::size_t index = 0;  // the keyframe's scan index
    Pose2D parent_pose;     // T_odom_sensor of the keyframe it was refined against
    Pose2D T_parent_key;
    std::size_t inliers = 0;
    double rms_m = 0.0;
    RefineStatus status = RefineStatus::kFailed;
  };
  KeyframeOrigin key_origin_;
  Scan key_scan_;
  RefinementKeyframe parent_index_;
  RefinementKeyframe revised_index_;  // the revised keyframe prepared, until it is kept
  Segmentation revised_;
  int keyframe_ = 0;
  int current_ = 0;
  std::size_t count_ = 0;
  /// A step has measured the motion (a refinement constrained in every direction): until
  /// then the constant-velocity prior is a guess, refined from a wider loss (decision 112).
  bool motion_measured_ = false;
  double typical_inlier_ratio_ = 0.0;  // running mean of the refinements' inlier ratios
  double last_stamp_ = 0.0;
  /// Recent (stamp, pose): a ring buffer for the velocity estimate.
  static constexpr std::size_t kHistory = 64;
  double history_stamp_[kHistory] = {};
  Pose2D history_pose_[kHistory];
  std::size_t history_size_ = 0;
  Twist2D velocity_;
  /// The rate the last scan's sweep was estimated at, when it was (the next scan is
  /// deskewed with it).
  std::optional<double> sweep_omega_;
  // The motion measured over the last interval (sensor frame), and the covariance of the
  // keyframe's rolling-shutter correction (its frame; OdometryParams::deskew_covariance).
  std::optional<Twist2D> interval_;
  Eigen::Matrix3d key_bend_ = Eigen::Matrix3d::Zero();
  Pose2D pose_;           // T_odom_sensor of the last scan
  Pose2D keyframe_pose_;  // T_odom_sensor of the keyframe
  Scan timed_;            // a scan given beam times from scanner_rotation_hz
  std::shared_ptr<const BeamLayout> timed_layout_;
  ScanStamp timed_stamp_ = ScanStamp::kFirst;
  std::vector<double> beam_times_;
};

}  // namespace lidarseg
