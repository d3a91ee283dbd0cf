#pragma once
/// @file StampPolicy.h
/// How a run turns a log's scan stamps into the motion model's clock, and when a wheel
/// odometry increment is plausible (beyond the paper: real logs repeat stamps, go
/// backwards, pause, and their odometry jumps).

#include <cstddef>
#include <optional>

#include "lidarseg/core/Pose2D.h"

namespace lidarseg {

/// The largest |stamp| (s) a log's scan may carry: 1e10 s is the year 2286 in Unix time. A
/// larger stamp is no clock reading (a corrupt field), and beyond it the output's 1 ms nudge
/// of a non-increasing stamp is lost to rounding; the readers skip such a record with its
/// place (issue 16).
constexpr double kMaxLogStampS = 1e10;

/// The knobs of the stamp repair, each a key of the `[stamps]` configuration section.
struct StampPolicyParams {
  /// A step between two scans longer than this (s) is a gap: the motion prior restarts
  /// from rest instead of extrapolating over it.
  double max_time_gap_s = 1.0;
  /// A wheel odometry increment faster than this (m/s, rad/s) is a jump, not a prior.
  double max_speed_mps = 10.0;
  double max_turn_rate_radps = 10.0;
  /// The span an odometry increment is judged over when the scan's own step is unusable
  /// (a repeated or backwards stamp, a clock jump), s.
  double unusable_step_span_s = 0.5;
  /// The shortest span an increment is judged over (a 1 ms step would reject any motion), s.
  double min_span_s = 0.05;
  /// Added to both speed limits' products (m, rad): the odometry's own quantisation.
  double jump_margin = 0.1;
  /// An output stamp that does not increase is written this long after the previous one
  /// (s), so that every trajectory file is strictly increasing.
  double output_nudge_s = 1e-3;
  /// @throws std::invalid_argument naming the key of the first invalid field.
  void validate() const;
};

/// What the stamp policy made of one scan's stamp.
struct StampStep {
  /// The motion model's clock (s): the log's steps, the last good step standing in for a
  /// non-increasing one.
  double model_stamp_s = 0.0;
  /// The stamp written to the outputs (s): the log's, nudged when it does not increase.
  double output_stamp_s = 0.0;
  /// Model time since the previous scan (s); 0 for the first scan.
  double dt_s = 0.0;
  /// The log's step did not increase (by at most max_time_gap_s back): dt_s is the last good step.
  bool non_increasing = false;
  /// The log's step exceeded max_time_gap_s, or the clock jumped back by more than that:
  /// the prior restarts from rest.
  bool gap = false;
  /// The clock jumped backwards by more than max_time_gap_s (a discontinuity, not a repeated
  /// stamp): also a gap; dt_s is the last good step.
  bool clock_jump = false;
  /// The log's own stamp and step since the previous accepted scan (s).
  double log_stamp_s = 0.0;
  double log_step_s = 0.0;
  bool first = true;
};

/// What a run's stamp policy met, counted over the scans it used: the counts every tool
/// reading a log reports alike (lidarseg-odometry, -features, -segment).
struct StampCounts {
  /// Scans whose time did not increase (processed with a synthetic time step).
  std::size_t non_increasing_stamps = 0;
  /// Time gaps beyond max_time_gap_s (the prior restarted from rest).
  std::size_t time_gaps = 0;
  /// Clock jumps backwards by more than max_time_gap_s (the prior restarted from rest).
  std::size_t clock_jumps = 0;
};

/// Repairs a log's stamps scan by scan (repeated, backwards, gapped) and judges wheel
/// odometry increments. Pure state machine: the same stamps give the same steps.
class StampPolicy {
 public:
  /// @throws std::invalid_argument for invalid parameters.
  explicit StampPolicy(const StampPolicyParams& params = {});
  /// What the next scan's stamp (the log's clock, s) becomes; nothing changes until
  /// accept(): a scan that cannot be processed leaves the clock as it was. Non-finite
  /// stamps are the caller's to reject (the log readers do).
  StampStep next(double log_stamp_s) const;
  /// The scan of `step` was processed: the next step is measured from it.
  void accept(const StampStep& step);
  /// Whether `increment` (robot frame, since the previous scan) is a plausible motion over
  /// `step`.
  bool plausible(const Pose2D& increment, const StampStep& step) const;
  const StampPolicyParams& params() const { return params_; }

  /// The time step (s) assumed before two stamps have given one: 10 Hz, the commonest
  /// scanning rate; replaced by the log's own step from its second scan on.
  static constexpr double kStartStepS = 0.1;

 private:
  StampPolicyParams params_;
  bool have_previous_ = false;
  double last_log_ = 0.0, last_output_ = 0.0, last_model_ = 0.0, last_dt_ = kStartStepS;
};

}  // namespace lidarseg
