#include "lidarseg/core/StampPolicy.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "Validation.h"

namespace lidarseg {

void StampPolicyParams::validate() const {
  detail::requirePositive("max_time_gap_s", max_time_gap_s);
  detail::requirePositive("max_speed_mps", max_speed_mps);
  detail::requirePositive("max_turn_rate_radps", max_turn_rate_radps);
  detail::requirePositive("unusable_step_span_s", unusable_step_span_s);
  detail::requireNonNegative("min_span_s", min_span_s);
  detail::requireNonNegative("jump_margin", jump_margin);
  // A nudge below a microsecond vanishes in a stamp's rounding (1e9 s + 1e-12 is 1e9 s);
  // beyond a second it moves stamps by more than any gap the policy accepts (issue 16).
  detail::requireInRange("output_nudge_s", output_nudge_s, 1e-6, 1.0);
}

StampPolicy::StampPolicy(const StampPolicyParams& params) : params_(params) { params_.validate(); }

StampStep StampPolicy::next(double log_stamp_s) const {
  StampStep s;
  s.log_stamp_s = log_stamp_s;
  s.model_stamp_s = log_stamp_s;
  s.output_stamp_s = log_stamp_s;
  if (have_previous_) {
    s.first = false;
    s.log_step_s = log_stamp_s - last_log_;
    double step = s.log_step_s;
    if (s.log_step_s < -params_.max_time_gap_s) {
      s.clock_jump = true;
      s.gap = true;
      step = last_dt_;
    } else if (!(s.log_step_s > 0.0)) {
      s.non_increasing = true;
      step = last_dt_;
    } else if (s.log_step_s > params_.max_time_gap_s) {
      s.gap = true;
    }
    s.model_stamp_s = last_model_ + step;
    s.dt_s = step;
    if (!(s.output_stamp_s > last_output_)) {
      // At least the next representable stamp: the written stamps always increase.
      s.output_stamp_s = std::max(last_output_ + params_.output_nudge_s,
                                  std::nextafter(last_output_, std::numeric_limits<double>::infinity()));
    }
  }
  return s;
}

void StampPolicy::accept(const StampStep& s) {
  if (!s.first && !s.non_increasing && !s.gap) last_dt_ = s.log_step_s;
  have_previous_ = true;
  last_log_ = s.log_stamp_s;
  last_model_ = s.model_stamp_s;
  last_output_ = s.output_stamp_s;
}

bool StampPolicy::plausible(const Pose2D& increment, const StampStep& step) const {
  const double span = (step.non_increasing || step.clock_jump) ? params_.unusable_step_span_s : std::max(step.dt_s, params_.min_span_s);
  const double limit_t = params_.max_speed_mps * span + params_.jump_margin;
  const double limit_r = params_.max_turn_rate_radps * span + params_.jump_margin;
  return std::hypot(increment.x, increment.y) <= limit_t && std::abs(increment.yaw) <= limit_r;
}

}  // namespace lidarseg
