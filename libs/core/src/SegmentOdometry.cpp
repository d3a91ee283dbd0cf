#include "lidarseg/core/SegmentOdometry.h"

#include <Eigen/Geometry>

#include "lidarseg/core/Angles.h"
#include "lidarseg/core/NumberText.h"
#include "lidarseg/core/ScanRecord.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "Validation.h"

namespace lidarseg {

namespace {
double microsecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
}

// The search's parameters over a window `factor` times wider, within what the search accepts
// (20 m and 399 whole cells of translation, pi of rotation), never narrower than the first.
SearchParams widened(SearchParams p, double factor) {
  if (!(factor >= 1.0)) factor = 1.0;  // validate() names the key; this only keeps the search valid
  const double cells_cap = 399.0 * p.resolution_m;  // whole cells: no rounding above 400
  p.linear_window_m = std::max(p.linear_window_m, std::min({p.linear_window_m * factor, 20.0, cells_cap}));
  p.angular_window_rad = std::max(p.angular_window_rad, std::min(p.angular_window_rad * factor, kPi));
  return p;
}

}  // namespace

const char* toString(TrackStatus s) {
  switch (s) {
    case TrackStatus::kFirst:
      return "first";
    case TrackStatus::kOk:
      return "ok";
    case TrackStatus::kDegenerate:
      return "degenerate";
    case TrackStatus::kRecovered:
      return "recovered";
    case TrackStatus::kLost:
      return "lost";
  }
  return "unknown";
}

void OdometryParams::validate() const {
  segmentation.validate();
  matcher.validate();
  refiner.validate();
  search.validate();
  if (static_cast<std::size_t>(level) >= kNumCascadeLevels) {
    detail::failKey("level", "a cascade level 0..3", static_cast<double>(static_cast<std::size_t>(level)));
  }
  detail::requireNonNegative("keyframe_distance_m", keyframe_distance_m);
  detail::requireNonNegative("keyframe_angle_rad", keyframe_angle_rad);
  detail::requirePositive("velocity_window_s", velocity_window_s);
  detail::requirePositive("angular_velocity_window_s", angular_velocity_window_s);
  detail::requirePositive("deskew_tolerance_rad", deskew_tolerance_rad);
  detail::requireNonNegative("scanner_rotation_hz", scanner_rotation_hz);
  detail::requireInRange("doubtful_ratio", doubtful_ratio, 0.0, 1.0);
  detail::requireInRange("prior_preference", prior_preference, 0.0, 10.0);
  detail::requireInRange("search_preference", search_preference, 0.0, 10.0);
  detail::requireInRange("wide_search_factor", wide_search_factor, 1.0, 10.0);
  try {  // the wider search's own parameters: a failure names this key, not one never written
    widened(search, wide_search_factor).validate();
  } catch (const std::invalid_argument& e) {
    detail::failKey("wide_search_factor", std::string("a window the search accepts (") + e.what() + ")",
                    wide_search_factor);
  }
  detail::requirePositive("prior_gate_sigmas", prior_gate_sigmas);
  detail::requireNonNegative("prior_accel_m_s2", prior_accel_m_s2);
  detail::requireNonNegative("prior_angular_accel_rad_s2", prior_angular_accel_rad_s2);
  detail::requireNonNegative("odometry_error_ratio", odometry_error_ratio);
  detail::requireNonNegative("prior_gate_floor_rad", prior_gate_floor_rad);
  if (local_map_keyframes < 1 || local_map_keyframes > 16) {
    detail::failKey("local_map_keyframes", "in [1, 16]", static_cast<double>(local_map_keyframes));
  }
  if (static_cast<std::size_t>(scan_stamp) > 2) {
    detail::failKey("scan_stamp", "0 (first beam), 1 (middle) or 2 (last beam)",
                    static_cast<double>(static_cast<std::size_t>(scan_stamp)));
  }
  if (static_cast<std::size_t>(degenerate_fallback_level) >= kNumCascadeLevels) {
    detail::failKey("degenerate_fallback_level", "a cascade level 0..3",
                    static_cast<double>(static_cast<std::size_t>(degenerate_fallback_level)));
  }
}

SegmentOdometry::SegmentOdometry(const OdometryParams& params)
    : params_((params.validate(), params)),
      segmenter_(params.segmentation),
      matcher_(params.matcher),
      refiner_(params.refiner),
      search_(params.search),
      wide_search_(widened(params.search, params.wide_search_factor)) {}

void SegmentOdometry::reset() {
  count_ = 0;
  motion_measured_ = false;
  typical_inlier_ratio_ = 0.0;
  pose_ = {};
  keyframe_pose_ = {};
  history_size_ = 0;
  velocity_ = {};
  sweep_omega_.reset();
  interval_.reset();
  key_bend_.setZero();
  map_size_ = 0;
  search_grid_.ready = false;
  key_origin_ = {};
}

void SegmentOdometry::segmentInto(const Scan& scan, int slot, const Twist2D& motion, OdometryStep& step) {
  slot_motion_[slot] = motion;
  segment(scan, motion, segmentation_[slot], step);
}

void SegmentOdometry::segment(const Scan& scan, const Twist2D& motion, Segmentation& out, OdometryStep& step) const {
  auto t0 = std::chrono::steady_clock::now();
  segmenter_.wallDanielsson().segment(scan, out, motion);
  step.wall_danielsson_us += microsecondsSince(t0);
  t0 = std::chrono::steady_clock::now();
  segmenter_.cascade().apply(out);
  step.cascade_us += microsecondsSince(t0);
}

MatchResult SegmentOdometry::matchWithKeyframe(int slot, const Pose2D& prior, OdometryStep& step) const {
  const auto t0 = std::chrono::steady_clock::now();
  MatchResult m = matcher_.match(segmentation_[keyframe_].level(params_.level).segments,
                                 segmentation_[slot].level(params_.level).segments, prior);
  step.matched_level = params_.level;
  step.prior_from_keyframe = prior;
  // A degenerate match (a corridor: only its two walls matched) leaves the motion along
  // the walls to the prediction. The finer fallback level keeps the short segments (door
  // recesses, jambs, pillars) that the cascade removed; they may constrain it.
  if (m.status == MatchStatus::kDegenerate && params_.degenerate_fallback_level < params_.level) {
    MatchResult finer = matcher_.match(segmentation_[keyframe_].level(params_.degenerate_fallback_level).segments,
                                       segmentation_[slot].level(params_.degenerate_fallback_level).segments, m.T_prev_curr);
    if (finer.status == MatchStatus::kOk) {
      m = std::move(finer);
      step.matched_level = params_.degenerate_fallback_level;
    }
  }
  step.matching_us += microsecondsSince(t0);
  return m;
}

namespace {
// The better of two refinements: one that holds over one that failed, then more paired
// points (a wrong along-corridor solution loses the jambs' and recesses' points).
bool better(const RefineResult& a, const RefineResult& b) {
  const bool a_ok = a.status != RefineStatus::kFailed, b_ok = b.status != RefineStatus::kFailed;
  if (a_ok != b_ok) return a_ok;
  return a.inliers > b.inliers;
}
}  // namespace

namespace {
constexpr double kUnbounded = std::numeric_limits<double>::infinity();
}  // namespace

SegmentOdometry::PriorGate SegmentOdometry::priorGate(double dt, const std::optional<Pose2D>& odometry_increment) const {
  double sigma_m = 0.0, sigma_rad = 0.0;
  if (odometry_increment) {
    // Wheel odometry can be wrong by any amount (slip, a bad calibration): no gate unless set.
    if (!(params_.odometry_error_ratio > 0.0)) return {kUnbounded, kUnbounded, kUnbounded, kUnbounded, true};
    sigma_m = params_.odometry_error_ratio * std::hypot(odometry_increment->x, odometry_increment->y);
    sigma_rad = params_.odometry_error_ratio * std::abs(odometry_increment->yaw);
  } else {
    const double t2 = std::isfinite(dt) && dt > 0.0 ? 0.5 * dt * dt : 0.0;
    sigma_m = params_.prior_accel_m_s2 * t2;
    sigma_rad = params_.prior_angular_accel_rad_s2 * t2;
  }
  return {std::max(params_.refiner.max_distance_m, params_.prior_gate_sigmas * sigma_m),
          std::max(params_.prior_gate_floor_rad, params_.prior_gate_sigmas * sigma_rad), sigma_m, sigma_rad,
          odometry_increment.has_value()};
}

bool SegmentOdometry::doubtful(const RefineResult& r) const {
  // A local optimum (a corridor's walls pair at any shift along them; only the jambs' and
  // recesses' points tell) pairs clearly fewer points than the last scans did.
  return r.status == RefineStatus::kFailed ||
         (typical_inlier_ratio_ > 0.0 && r.inlier_ratio < params_.doubtful_ratio * typical_inlier_ratio_);
}

bool SegmentOdometry::withinGate(const Pose2D& T_key_curr, const Pose2D& prior, const PriorGate& gate) {
  const Pose2D d = relative(T_key_curr, prior);
  return std::hypot(d.x, d.y) <= gate.translation_m && std::abs(d.yaw) <= gate.rotation_rad;
}

Pose2D SegmentOdometry::refineWithKeyframe(int slot, const Pose2D& prior, const PriorGate& gate,
                                          const SweepModel* sweep, OdometryStep& step) {
  const Segmentation& key = segmentation_[keyframe_];
  const Segmentation& cur = segmentation_[slot];
  const MatchResult& m = step.match;
  const bool matched = m.status != MatchStatus::kTooFewMatches;
  // Before any step has measured the motion, the constant-velocity prior is a guess (the
  // robot may already move at any speed): the refinements start from a wider loss, so that
  // a start off by more than the final loss's scale along a corridor still feels the jambs
  // (decision 112). Wheel odometry is a measurement.
  const bool guessed = !gate.wheel_odometry && !motion_measured_;
  // 1. From the segment match.
  RefineResult best;
  if (matched) best = refiner_.refine(refine_keyframe_, cur, m.T_prev_curr, sweep, guessed);
  // 2. From the prior, when the match failed, moved far from the prior (it may have locked
  // onto a wrong couple: a repeated door, a corridor), its refinement is doubtful, or that
  // refinement was still moving when its iterations ran out (a start off along a corridor
  // whose only cue is a jamb or a pillar: the pose crawls towards it by a centimetre or two
  // per iteration, so where it stopped depends on where it started).
  const Pose2D shift = relative(best.T_key_curr, prior);
  const bool far = std::hypot(shift.x, shift.y) > params_.refiner.max_distance_m ||
                   std::abs(shift.yaw) > params_.refiner.max_distance_m / std::max(1.0, best.rms_range_m);
  // The prior's hypothesis is the reference (as ICP, which only looks near the prior): another
  // replaces it only when it holds and pairs clearly more points, or the prior's failed.
  // Beyond the prior's gate, only when the prior's refinement failed.
  std::optional<RefineResult> reference;
  // The gate stands for the prior's assumed error (bounded accelerations) and guards a
  // prior whose refinement explains the scan as the last scans were explained. A doubtful
  // one (it pairs clearly fewer points) is no such reference: the prior was wrong by more
  // than assumed (a turn that starts within one scan of a slow scanner), and a hypothesis
  // beyond the gate is judged by the rules below alone (decision 90).
  const auto gateHolds = [&]() { return !doubtful(*reference); };
  const auto replaces = [&](const RefineResult& r, bool gated) {
    if (!reference || reference->status == RefineStatus::kFailed) return better(r, best);
    if (r.status == RefineStatus::kFailed || (gated && gateHolds() && !withinGate(r.T_key_curr, prior, gate))) return false;
    // A degenerate hypothesis is free along its weak direction (a corridor's axis): the
    // points it pairs there say nothing about the position, so it does not replace a
    // reference that is constrained (decision 76).
    if (r.status == RefineStatus::kDegenerate && reference->status == RefineStatus::kOk) return false;
    // A constant-velocity prior comes from the last estimates: a reference refined from it
    // whose iterations ran out while it still moved does not hold against one that came to
    // rest (it was sliding away along a corridor, and the next prior would start from there:
    // the error feeds itself). Wheel odometry does not depend on the estimates. It must pair
    // at least as many points: a reference creeping along a corridor still explains the scan
    // better than a match that converged one bay away with fewer points (decision 96).
    if (!gate.wheel_odometry && !reference->converged && r.converged && r.inliers >= reference->inliers) return true;
    return static_cast<double>(r.inliers) > (1.0 + params_.prior_preference) * static_cast<double>(reference->inliers);
  };
  // The match's refinement and the prior disagree beyond both their uncertainties (a
  // corridor whose walls pair as well one pillar face further, with a prior known to a few
  // millimetres): the prior's refinement is the reference then too.
  const auto disagrees = [&](const RefineResult& r) {
    if (!params_.check_match_against_prior || r.status == RefineStatus::kFailed) return false;
    const double k2 = params_.prior_gate_sigmas * params_.prior_gate_sigmas;
    const Eigen::Vector2d d(r.T_key_curr.x - prior.x, r.T_key_curr.y - prior.y);
    const double dist = d.norm();
    const double along = dist > 0.0 ? (d / dist).dot(r.covariance.topLeftCorner<2, 2>() * (d / dist)) : 0.0;
    const double dyaw = wrapAngle(r.T_key_curr.yaw - prior.yaw);
    return dist * dist > k2 * (gate.sigma_m * gate.sigma_m + along) ||
           dyaw * dyaw > k2 * (gate.sigma_rad * gate.sigma_rad + r.covariance(2, 2));
  };
  if (!matched || far || doubtful(best) || !best.converged || disagrees(best)) {
    reference = refiner_.refine(refine_keyframe_, cur, prior, sweep, guessed);
    if (!matched || !replaces(best, false)) best = *reference;
  }
  bool recovered = false;
  // 3. A bounded correlative search around the prior, then the refinement from its best.
  if (params_.recovery && (best.status == RefineStatus::kFailed || (params_.search_when_doubtful && doubtful(best)))) {
    if (!search_grid_.ready) search_.prepare(key.points, search_grid_);
    step.search = search_.search(search_grid_, cur.points, prior);
    if (step.search->found) {
      RefineResult r = refiner_.refine(refine_keyframe_, cur, step.search->T_key_curr, sweep);
      // It must also clearly beat the hypothesis it would replace, when that one holds: the
      // best of the prior's and the match's refinements is rarely wrong by a small margin,
      // and a corridor pairs almost as many points one bay further (decision 81).
      const bool clearly_better =
          best.status == RefineStatus::kFailed ||
          static_cast<double>(r.inliers) > (1.0 + params_.search_preference) * static_cast<double>(best.inliers);
      if (replaces(r, true) && better(r, best) && clearly_better) {
        best = std::move(r);
        recovered = true;
      }
    }
    // 4. Nothing holds, the segment match failed too: the scan would be lost. The prior may
    // be wrong by more than the window (wheel odometry that slipped by metres): a wider
    // search, then the refinement from its best, which must be constrained in every direction
    // (over a window this wide, a fit free along a corridor holds almost anywhere along it).
    // Not run for a doubtful fit: on the real logs that tripled the mean time (decision 83).
    if (!matched && best.status == RefineStatus::kFailed && params_.wide_search_factor > 1.0) {
      // Only a pose scoring above the first search's best can change anything (the first
      // window is part of this one, on the same lattice): the branch and bound starts there.
      const double first_score = step.search->found ? step.search->score : 0.0;
      const SearchResult wide = wide_search_.search(search_grid_, cur.points, prior, first_score);
      step.wide_search = true;
      if (wide.found) {
        step.search = wide;
        RefineResult r = refiner_.refine(refine_keyframe_, cur, wide.T_key_curr, sweep);
        if (r.status == RefineStatus::kOk) {
          best = std::move(r);
          recovered = true;
        }
      }
    }
  }
  // 4b. A degenerate fit is free along its weak direction (a corridor's axis): it kept there
  // the value its hypothesis started from (a segment match or a search one bay away), which
  // the scan does not support more than any other. The prior's value there is the only
  // information (the motion model, or wheel odometry): the fit is refined again from it, at
  // most the prior's gate away, and that is kept when it pairs at least as many points or is
  // constrained in every direction (decision 98). Only a direction the fit leaves truly free
  // counts (its variance there is the unconstrained one's, not a yaw-mostly weak direction
  // whose translation part the points do constrain).
  const std::optional<Eigen::Vector2d> free = freeDirection(best);
  if (params_.degenerate_along_prior && free) {
    const Eigen::Vector2d& u = *free;
    const double off = std::clamp(u.x() * (prior.x - best.T_key_curr.x) + u.y() * (prior.y - best.T_key_curr.y),
                                  -gate.translation_m, gate.translation_m);
    if (std::abs(off) > params_.refiner.robust_scale_m) {
      Pose2D start = best.T_key_curr;
      start.x += off * u.x();
      start.y += off * u.y();
      RefineResult along = refiner_.refine(refine_keyframe_, cur, start, sweep);
      if (along.status == RefineStatus::kOk || (along.status == RefineStatus::kDegenerate && along.inliers >= best.inliers)) {
        best = std::move(along);
      }
    }
  }
  step.refine = best;
  if (best.status != RefineStatus::kFailed) {
    // The running mean of the inlier ratio (about the last 10 scans).
    typical_inlier_ratio_ = typical_inlier_ratio_ > 0.0 ? 0.9 * typical_inlier_ratio_ + 0.1 * best.inlier_ratio
                                                        : best.inlier_ratio;
    step.status = best.status == RefineStatus::kDegenerate ? TrackStatus::kDegenerate
                  : recovered                              ? TrackStatus::kRecovered
                                                           : TrackStatus::kOk;
    return best.T_key_curr;
  }
  // 5. Nothing refined: the segment match alone if it held, else the prediction.
  if (matched) {
    step.status = m.status == MatchStatus::kOk ? TrackStatus::kOk : TrackStatus::kDegenerate;
    return m.T_prev_curr;
  }
  step.status = TrackStatus::kLost;
  return prior;
}

Pose2D SegmentOdometry::deskewWithRefinedMotion(const Scan& scan, int slot, double dt, const Twist2D& used,
                                                const Pose2D& T_key_curr, OdometryStep& step) {
  // The rotation rate the refinement measured, against the one the scan was deskewed with:
  // at the start or the end of a turn they differ (the prediction lags), and with a slow
  // scanner by much (a 5 Hz sweep of 180 degrees at 1.7 rad/s turns 0.17 rad). The scan is
  // segmented again with the measured rate and refined from where it came to rest; the
  // result is kept when it pairs at least as many points (decision 90).
  const double sweep = scan.time_offsets_s.back() - scan.time_offsets_s.front();
  const Pose2D measured = relative(compose(keyframe_pose_, T_key_curr), pose_);
  Twist2D refined = used;
  refined.omega = measured.yaw / dt;
  if (!(std::abs(refined.omega - used.omega) * sweep > params_.deskew_tolerance_rad)) return T_key_curr;
  segmentInto(scan, slot, refined, step);
  RefineResult again = refiner_.refine(refine_keyframe_, segmentation_[slot], T_key_curr);
  step.deskewed_again = true;
  if (again.status == RefineStatus::kFailed || again.inliers < step.refine.inliers) {
    segmentInto(scan, slot, used, step);  // keep the segments the estimate came from
    return T_key_curr;
  }
  if (again.status == RefineStatus::kDegenerate) step.status = TrackStatus::kDegenerate;
  else if (step.status == TrackStatus::kDegenerate) step.status = TrackStatus::kOk;
  step.refine = std::move(again);
  return step.refine.T_key_curr;
}

Pose2D SegmentOdometry::reviseKeyframe(double dt, const Pose2D& T_key_curr, OdometryStep& step) {
  // The keyframe is the previous scan, stamped at its first beam: its sweep lies in the
  // interval to this scan, and was deskewed with the rate of the interval before (the only
  // one known then). At a turn's onset or end the two differ: the keyframe's walls are bent
  // by the difference times the sweep, its pose took part of that bend, and every scan
  // matched against it inherits both (decision 114).
  KeyframeOrigin& origin = key_origin_;
  if (!origin.revisable || origin.index + 1 != step.index) return T_key_curr;
  origin.revisable = false;  // once
  const double sweep_s = key_scan_.time_offsets_s.back() - key_scan_.time_offsets_s.front();
  const Twist2D used = slot_motion_[keyframe_];
  Twist2D measured = used;
  measured.omega = T_key_curr.yaw / dt;
  if (!(std::abs(measured.omega - used.omega) * sweep_s > params_.deskew_tolerance_rad)) return T_key_curr;
  segment(key_scan_, measured, revised_, step);
  // Against the reference it was refined against, from where that refinement came to rest.
  // The interval's mean rate is not the sweep's when the turn starts or ends within the
  // interval: the revision must explain the keyframe better (as many points, a lower RMS)
  // and not be degenerate where the first fit was constrained.
  const RefineResult again = refiner_.refine(parent_index_, revised_, origin.T_parent_key);
  if (again.status == RefineStatus::kFailed || again.inliers < origin.inliers || !(again.rms_m < origin.rms_m) ||
      (again.status == RefineStatus::kDegenerate && origin.status == RefineStatus::kOk)) {
    return T_key_curr;
  }
  // The current scan against the revised keyframe (and local map), from the pose it had;
  // the revision is kept only when that holds too (not failed, not degenerate where the fit
  // against the unrevised keyframe was constrained).
  const Pose2D revised_pose = compose(origin.parent_pose, again.T_key_curr);
  prepareIndex(revised_, revised_pose, revised_index_);
  const Pose2D start = relative(compose(keyframe_pose_, T_key_curr), revised_pose);
  RefineResult current = refiner_.refine(revised_index_, segmentation_[current_], start);
  if (current.status == RefineStatus::kFailed ||
      (current.status == RefineStatus::kDegenerate && step.refine.status == RefineStatus::kOk)) {
    return T_key_curr;
  }
  std::swap(segmentation_[keyframe_], revised_);
  std::swap(refine_keyframe_, revised_index_);
  slot_motion_[keyframe_] = measured;
  keyframe_pose_ = revised_pose;
  history_pose_[(history_size_ - 1) % kHistory] = revised_pose;  // the velocity is measured from it
  search_grid_.ready = false;  // made again from the revised keyframe when a search needs it
  step.keyframe_revision = KeyframeRevision{revised_pose, std::make_shared<const Segmentation>(segmentation_[keyframe_])};
  if (current.status == RefineStatus::kDegenerate) step.status = TrackStatus::kDegenerate;
  else if (step.status == TrackStatus::kDegenerate) step.status = TrackStatus::kOk;
  step.refine = std::move(current);
  return step.refine.T_key_curr;
}

const Scan& SegmentOdometry::withBeamTimes(const Scan& scan) {
  if (!scan.time_offsets_s.empty() || !(params_.scanner_rotation_hz > 0.0) || !scan.layout) return scan;
  if (scan.layout != timed_layout_ || params_.scan_stamp != timed_stamp_) {
    timed_stamp_ = params_.scan_stamp;
    const BeamLayout& layout = *scan.layout;
    beam_times_.assign(layout.size(), 0.0);
    const double period = 1.0 / (2.0 * kPi * params_.scanner_rotation_hz);
    for (std::size_t i = 1; i < layout.size(); ++i) {
      beam_times_[i] = beam_times_[i - 1] + std::abs(layout.angle(i) - layout.angle(i - 1)) * period;
    }
    // Relative to the stamped beam's instant.
    const double sweep = beam_times_.empty() ? 0.0 : beam_times_.back();
    const double shift = params_.scan_stamp == ScanStamp::kMiddle ? 0.5 * sweep
                         : params_.scan_stamp == ScanStamp::kLast ? sweep
                                                                  : 0.0;
    for (double& t : beam_times_) t -= shift;
    timed_layout_ = scan.layout;
  }
  timed_.layout = scan.layout;
  timed_.ranges_m = scan.ranges_m;
  timed_.valid = scan.valid;
  timed_.time_offsets_s = beam_times_;
  timed_.stamp_s = scan.stamp_s;
  timed_.min_range_m = scan.min_range_m;
  timed_.max_range_m = scan.max_range_m;
  return timed_;
}

OdometryStep SegmentOdometry::process(const Scan& input, const std::optional<Pose2D>& odometry_increment) {
  // Before any state changes: a non-finite prior would reach the search's grid indices, a
  // non-finite stamp every later velocity, and a motion beyond the logs' coordinate bound
  // (kMaxRelativeCoordinate) is no robot's.
  const auto usable = [](double v) { return std::isfinite(v) && std::abs(v) <= kMaxRelativeCoordinate; };
  if (odometry_increment && !(usable(odometry_increment->x) && usable(odometry_increment->y) &&
                              usable(odometry_increment->yaw))) {
    throw std::invalid_argument("SegmentOdometry::process: the odometry increment (" + numberText(odometry_increment->x) +
                                ", " + numberText(odometry_increment->y) + ", " + numberText(odometry_increment->yaw) +
                                ") is not finite or beyond +-1e7 (m, rad)");
  }
  if (!std::isfinite(input.stamp_s)) {
    throw std::invalid_argument("SegmentOdometry::process: the scan's stamp " + numberText(input.stamp_s) + " is not finite");
  }
  input.validate();  // a malformed scan throws here, not half-way through the state's update
  const Scan& scan = withBeamTimes(input);
  OdometryStep step;
  step.index = count_;
  step.stamp_s = scan.stamp_s;
  // The current scan goes in the slot that is not the keyframe's.
  const int slot = count_ == 0 ? 0 : 1 - keyframe_;
  const bool deskew = params_.deskew && !scan.time_offsets_s.empty();
  Twist2D motion = deskew ? velocity_ : Twist2D{};
  // The last scan's sweep, when its rate was estimated, is the latest measure of the rate
  // (with first-beam stamps it spans the interval to this scan).
  if (deskew && sweep_omega_) motion.omega = *sweep_omega_;
  sweep_omega_.reset();  // set again below only when this scan's rate is estimated
  segmentInto(scan, slot, motion, step);  // slot_motion_[slot]: the motion it was deskewed with
  current_ = slot;

  if (count_ == 0) {
    step.deskewed_with = motion;
    step.first = true;
    step.keyframe = true;
    keyframe_ = slot;
    keyframe_pose_ = pose_;
    map_size_ = 0;
    key_origin_.revisable = false;
    prepareKeyframe(step);
    last_stamp_ = scan.stamp_s;
    ++count_;
    step.T_odom_sensor = pose_;
    remember(scan.stamp_s);
    return step;
  }
  const double dt = scan.stamp_s - last_stamp_;
  const Pose2D increment_prior = odometry_increment ? *odometry_increment : velocity_.integrate(dt);
  step.prior = increment_prior;
  // The matcher works from the keyframe: T_key_curr = T_key_last (+) predicted increment.
  const Pose2D prior_from_key = compose(relative(pose_, keyframe_pose_), increment_prior);
  step.match = matchWithKeyframe(slot, prior_from_key, step);

  if (deskew && dt > 0.0) {
    // The rolling-shutter correction used the predicted rotation rate. Where the match
    // says otherwise (a turn starts or ends) or failed, segment again with the measured
    // rate (or none) and keep that when it matches.
    const double sweep = scan.time_offsets_s.back() - scan.time_offsets_s.front();
    Twist2D corrected = motion;
    if (step.match.status == MatchStatus::kTooFewMatches) {
      corrected = Twist2D{};
    } else {
      const Pose2D measured = relative(compose(keyframe_pose_, step.match.T_prev_curr), pose_);
      corrected.omega = measured.yaw / dt;
    }
    if (std::abs(corrected.omega - motion.omega) * sweep > params_.deskew_tolerance_rad ||
        (step.match.status == MatchStatus::kTooFewMatches && (motion.omega != 0.0 || motion.vx != 0.0))) {
      segmentInto(scan, slot, corrected, step);
      MatchResult again = matchWithKeyframe(slot, prior_from_key, step);
      // Kept when it matches; when neither matches, the prediction's segments stay: a failed
      // match says nothing against the predicted rate (decision 115).
      if (again.status != MatchStatus::kTooFewMatches) {
        step.match = std::move(again);
      } else {
        segmentInto(scan, slot, motion, step);  // keep the segments the prediction gave
      }
    }
  }

  Pose2D T_key_curr = step.match.T_prev_curr;
  // A sweep whose rate the prior knows too poorly (the rate may have changed by the angular
  // acceleration's bound times dt, which turns the sweep's last beam by more than
  // deskew_tolerance_rad) has its rate estimated with the pose, when the scan is a full turn:
  // its first and last beams see the same walls a sweep apart, which fixes the rate; a
  // partial sweep bends a corridor's walls about as well at any rate near the truth, and
  // the estimate then runs off (decision 95).
  const double sweep_s = deskew ? std::abs(scan.time_offsets_s.back() - scan.time_offsets_s.front()) : 0.0;
  const double rate_sigma = params_.prior_angular_accel_rad_s2 * (std::isfinite(dt) && dt > 0.0 ? dt : 0.0);
  SweepModel sweep_model;
  const SweepModel* sweep = nullptr;
  if (params_.refiner.enabled && deskew && params_.estimate_sweep_rate && scan.layout && scan.layout->wrapsAround() &&
      rate_sigma * sweep_s > params_.deskew_tolerance_rad) {
    sweep_model.time_offsets_s = &scan.time_offsets_s;
    sweep_model.prior_sigma_rad_s = rate_sigma;
    sweep = &sweep_model;
  }
  if (params_.refiner.enabled) {
    const auto t0 = std::chrono::steady_clock::now();
    const PriorGate gate = priorGate(dt, odometry_increment);
    T_key_curr = refineWithKeyframe(slot, prior_from_key, gate, sweep, step);
    if (sweep != nullptr && step.refine.status != RefineStatus::kFailed) {
      // The scan segmented again with the rate found, as the next keyframe will be seen.
      const Twist2D deskewed_with = slot_motion_[slot];
      Twist2D swept = deskewed_with;
      swept.omega += step.refine.sweep_rate_correction;
      if (swept.omega != deskewed_with.omega) segmentInto(scan, slot, swept, step);
      sweep_omega_ = swept.omega;
    } else if (deskew && dt > 0.0 && step.refine.status != RefineStatus::kFailed) {
      const Twist2D deskewed_with = slot_motion_[slot];  // a copy: the call segments the slot again
      T_key_curr = deskewWithRefinedMotion(scan, slot, dt, deskewed_with, T_key_curr, step);
    }
    // Not when this scan's rate was estimated with its pose: its segments and the rate carried
    // to the next scan come from that fit, which a refinement against a revised keyframe
    // would leave behind.
    if (params_.revise_keyframe && deskew && dt > 0.0 && sweep == nullptr &&
        step.refine.status != RefineStatus::kFailed) {
      T_key_curr = reviseKeyframe(dt, T_key_curr, step);
    }
    step.refinement_us = microsecondsSince(t0);
    step.matching_us += step.refinement_us;
  } else {
    step.status = step.match.status == MatchStatus::kOk           ? TrackStatus::kOk
                  : step.match.status == MatchStatus::kDegenerate ? TrackStatus::kDegenerate
                                                                  : TrackStatus::kLost;
  }
  const bool refined = step.refine.status != RefineStatus::kFailed;
  step.deskewed_with = slot_motion_[slot];

  const Pose2D new_pose = compose(keyframe_pose_, T_key_curr);
  // From the pose reported for the previous scan (a revision of that keyframe does not move
  // it: the increments chain into the reported poses).
  step.increment = relative(new_pose, pose_);
  // The increment's uncertainty: that of the keyframe match, seen from the last pose.
  step.increment_covariance = refined ? step.refine.covariance : step.match.covariance;
  // And that of the rolling-shutter corrections of this scan and of its keyframe (decision
  // 117): the motion over this scan's sweep is known to within its recent change, and a
  // sweep deskewed with a motion off by d over T seconds is bent by up to d T, its fit moved
  // by about half of that. The keyframe's term is in its own frame, this scan's turned into it.
  Eigen::Matrix3d bend = Eigen::Matrix3d::Zero();  // this scan's, in its own frame
  if (deskew && dt > 0.0 && sweep_s > 0.0) {
    // The interval's motion: the increment, or after a revision of the keyframe (the previous
    // scan) the motion from its revised pose, without the revision's correction. Over at
    // least a sweep: a stamp a millisecond after the last would turn the increment's noise
    // into metres per second.
    const Pose2D& moved = step.keyframe_revision ? T_key_curr : step.increment;
    const double span = std::max(dt, sweep_s);
    const Twist2D measured{moved.x / span, moved.y / span, moved.yaw / span};
    const Twist2D& used = slot_motion_[slot];
    const auto change = [](const Twist2D& a, const Twist2D& b) {
      return Eigen::Vector3d(a.vx - b.vx, a.vy - b.vy, a.omega - b.omega);
    };
    const Eigen::Vector3d off = change(measured, used);
    Eigen::Vector3d doubt = off.cwiseAbs();
    Eigen::Vector2d dv = off.head<2>();
    if (interval_) {
      const Eigen::Vector3d since = change(measured, *interval_);
      doubt(2) = std::max(doubt(2), std::abs(since(2)));
      if (since.head<2>().norm() > dv.norm()) dv = since.head<2>();
    }
    const double half = 0.5 * sweep_s;
    bend.topLeftCorner<2, 2>() = half * half * dv * dv.transpose();
    bend(2, 2) = half * half * doubt(2) * doubt(2);
    interval_ = measured;
  }
  if (params_.deskew_covariance) {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    R.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(T_key_curr.yaw).toRotationMatrix();
    // The keyframe's turn error also moves this scan's position in its frame (lever arm).
    Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
    A(0, 2) = -T_key_curr.y;
    A(1, 2) = T_key_curr.x;
    step.increment_covariance += R * bend * R.transpose() + A * key_bend_ * A.transpose();
  }
  pose_ = new_pose;
  step.T_odom_sensor = pose_;
  last_stamp_ = scan.stamp_s;
  ++count_;
  // A fit free along a corridor's axis took its position there from the prior (or from
  // wherever its hypothesis left it): its motion along that axis is no measurement, and the
  // velocity keeps what the constrained steps before it measured (decision 111).
  Eigen::Vector2d free_odom = Eigen::Vector2d::Zero();
  if (params_.degenerate_keeps_velocity && refined) {
    if (const std::optional<Eigen::Vector2d> u = freeDirection(step.refine)) {
      const double c = std::cos(keyframe_pose_.yaw), s = std::sin(keyframe_pose_.yaw);
      free_odom = Eigen::Vector2d(c * u->x() - s * u->y(), s * u->x() + c * u->y());
    }
  }
  remember(scan.stamp_s, free_odom);
  if (step.refine.status == RefineStatus::kOk) motion_measured_ = true;

  const Pose2D& from_key = T_key_curr;
  const bool moved = std::hypot(from_key.x, from_key.y) >= params_.keyframe_distance_m ||
                     std::abs(from_key.yaw) >= params_.keyframe_angle_rad;
  if (moved || step.status != TrackStatus::kOk) {
    // The keyframe being replaced joins the local map (when there is one), unless it was
    // matched badly itself.
    if (params_.local_map_keyframes > 1 && step.status != TrackStatus::kLost) {
      // A ring of the previous keyframes; copy-assignment reuses each slot's buffers.
      const std::size_t capacity = params_.local_map_keyframes - 1;
      if (map_.size() < capacity) map_.resize(capacity);
      MapKeyframe& slot_k = map_[map_next_];
      slot_k.segmentation = segmentation_[keyframe_];
      slot_k.T_odom_sensor = keyframe_pose_;
      map_next_ = (map_next_ + 1) % capacity;
      map_size_ = std::min(map_size_ + 1, capacity);
    }
    if (step.status == TrackStatus::kLost) map_size_ = 0;
    // What a revision at the next scan needs: the scan's sweep lies after its stamp, the
    // rate was not estimated with the pose, and a refinement held (decision 114).
    key_origin_.revisable = params_.revise_keyframe && params_.refiner.enabled && deskew && sweep == nullptr &&
                            refined && step.status != TrackStatus::kLost && scan.time_offsets_s.front() >= 0.0 &&
                            scan.time_offsets_s.back() > scan.time_offsets_s.front();
    if (key_origin_.revisable) {
      key_origin_.index = step.index;
      key_origin_.parent_pose = keyframe_pose_;
      key_origin_.T_parent_key = T_key_curr;
      key_origin_.inliers = step.refine.inliers;
      key_origin_.rms_m = step.refine.rms_m;
      key_origin_.status = step.refine.status;
      key_scan_ = scan;
      std::swap(parent_index_, refine_keyframe_);  // the reference it was refined against
    }
    keyframe_ = slot;
    keyframe_pose_ = pose_;
    key_bend_ = bend;
    prepareKeyframe(step);
    step.keyframe = true;
  }
  return step;
}

std::optional<Eigen::Vector2d> SegmentOdometry::freeDirection(const RefineResult& fit) const {
  if (fit.status != RefineStatus::kDegenerate) return std::nullopt;
  const Eigen::Vector2d& u = fit.degenerate_direction;
  const double u2 = params_.refiner.unconstrained_sigma_m * params_.refiner.unconstrained_sigma_m;
  if (!(u.squaredNorm() > 0.5) || !(u.dot(fit.covariance.topLeftCorner<2, 2>() * u) > 0.5 * u2)) return std::nullopt;
  return u;
}

void SegmentOdometry::prepareIndex(const Segmentation& keyframe, const Pose2D& keyframe_pose,
                                   RefinementKeyframe& index) {
  map_scans_.clear();
  map_scans_.push_back({&keyframe, Pose2D{}});
  for (std::size_t i = 0; i < map_size_; ++i) {
    const MapKeyframe& k = map_[(map_next_ + map_.size() - 1 - i) % map_.size()];  // newest first
    map_scans_.push_back({&k.segmentation, relative(k.T_odom_sensor, keyframe_pose)});
  }
  refiner_.prepare(map_scans_, index);
}

void SegmentOdometry::prepareKeyframe(OdometryStep& step) {
  search_grid_.ready = false;  // made again, for the new keyframe, when a search needs it
  if (!params_.refiner.enabled) return;
  const auto t0 = std::chrono::steady_clock::now();
  prepareIndex(segmentation_[keyframe_], keyframe_pose_, refine_keyframe_);
  step.keyframe_us = microsecondsSince(t0);
  step.matching_us += step.keyframe_us;
}

void SegmentOdometry::remember(double stamp, const Eigen::Vector2d& free_odom) {
  history_stamp_[history_size_ % kHistory] = stamp;
  history_pose_[history_size_ % kHistory] = pose_;
  ++history_size_;
  Twist2D linear = meanVelocity(stamp, params_.velocity_window_s);
  if (free_odom.squaredNorm() > 0.0) {
    // The free direction in the sensor frame the velocities are given in (the body's, to
    // within the window's small turn): the new estimate's component along it is the old one's.
    const double c = std::cos(pose_.yaw), s = std::sin(pose_.yaw);
    const Eigen::Vector2d u(c * free_odom.x() + s * free_odom.y(), -s * free_odom.x() + c * free_odom.y());
    const Eigen::Vector2d v_new(linear.vx, linear.vy), v_old(velocity_.vx, velocity_.vy);
    const Eigen::Vector2d v = v_new + u * (u.dot(v_old) - u.dot(v_new));
    linear.vx = v.x();
    linear.vy = v.y();
  }
  const Twist2D angular = meanVelocity(stamp, params_.angular_velocity_window_s);
  velocity_ = {linear.vx, linear.vy, angular.omega};
}

Twist2D SegmentOdometry::meanVelocity(double stamp, double window) const {
  // The oldest remembered pose within the window, and the mean motion since.
  const std::size_t available = std::min(history_size_, kHistory);
  std::size_t oldest = history_size_ - 1;
  for (std::size_t k = 1; k < available; ++k) {
    const std::size_t idx = (history_size_ - 1 - k) % kHistory;
    oldest = history_size_ - 1 - k;
    if (stamp - history_stamp_[idx] >= window - 1e-9) break;
  }
  const std::size_t o = oldest % kHistory;
  const double span = stamp - history_stamp_[o];
  if (!(span > 0.0)) return {};
  const Pose2D motion = relative(pose_, history_pose_[o]);
  return {motion.x / span, motion.y / span, motion.yaw / span};
}

}  // namespace lidarseg
