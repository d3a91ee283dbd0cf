#include "lidarseg/core/BeamLayout.h"
#include "lidarseg/core/Angles.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace lidarseg {

namespace {
constexpr double kTwoPi = 2.0 * kPi;
// Last-to-first gap (in mean increments) still counted as one step of a full turn.
constexpr double kWrapTolerance = 0.5;
}  // namespace

BeamLayout::BeamLayout(std::vector<double> angles_rad) : angles_(std::move(angles_rad)) {
  for (std::size_t i = 0; i < angles_.size(); ++i) {
    if (!std::isfinite(angles_[i])) {
      throw std::invalid_argument("BeamLayout: angle of beam " + std::to_string(i) +
                                  " is not finite");
    }
  }
  precompute();
}

BeamLayout BeamLayout::uniform(std::size_t num_beams, double first_angle_rad,
                               double increment_rad) {
  if (!std::isfinite(first_angle_rad) || !std::isfinite(increment_rad)) {
    throw std::invalid_argument("BeamLayout::uniform: first angle and increment must be finite");
  }
  std::vector<double> angles(num_beams);
  for (std::size_t i = 0; i < num_beams; ++i) {
    angles[i] = first_angle_rad + static_cast<double>(i) * increment_rad;
  }
  return BeamLayout(std::move(angles));
}

BeamLayout BeamLayout::centred(std::size_t num_beams, double field_of_view_rad) {
  if (num_beams < 2) return uniform(num_beams, 0.0, 0.0);
  return uniform(num_beams, -0.5 * field_of_view_rad,
                 field_of_view_rad / static_cast<double>(num_beams - 1));
}

void BeamLayout::precompute() {
  const std::size_t n = angles_.size();
  cos_.resize(n);
  sin_.resize(n);
  prefix_cc_.assign(n + 1, 0.0);
  prefix_cs_.assign(n + 1, 0.0);
  prefix_ss_.assign(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    cos_[i] = std::cos(angles_[i]);
    sin_[i] = std::sin(angles_[i]);
    prefix_cc_[i + 1] = prefix_cc_[i] + cos_[i] * cos_[i];
    prefix_cs_[i + 1] = prefix_cs_[i] + cos_[i] * sin_[i];
    prefix_ss_[i + 1] = prefix_ss_[i] + sin_[i] * sin_[i];
  }
  mean_increment_ = 0.0;
  wraps_ = false;
  if (n >= 2) {
    mean_increment_ = std::abs(angles_.back() - angles_.front()) / static_cast<double>(n - 1);
    // A full turn either ends one increment short of the first beam (360 beams at 1 deg
    // from -180) or ends on the first beam's direction again (MRPT's 360-degree scans:
    // -pi..+pi inclusive).
    const double covered = std::abs(angles_.back() - angles_.front());
    const double tol = kWrapTolerance * mean_increment_;
    wraps_ = mean_increment_ > 0.0 && (std::abs(covered + mean_increment_ - kTwoPi) <= tol ||
                                       std::abs(covered - kTwoPi) <= tol);
  }
}

std::shared_ptr<const BeamLayout> CentredLayoutCache::get(std::size_t num_beams, double aperture_rad,
                                                          bool counter_clockwise) {
  const auto key = std::make_tuple(num_beams, aperture_rad, counter_clockwise);
  const auto it = layouts_.find(key);
  if (it != layouts_.end()) return it->second;
  if (layouts_.size() >= kMaxLayouts) layouts_.clear();
  const double step = aperture_rad / static_cast<double>(num_beams - 1);
  auto layout = std::make_shared<const BeamLayout>(
      counter_clockwise ? BeamLayout::uniform(num_beams, -0.5 * aperture_rad, step)
                        : BeamLayout::uniform(num_beams, 0.5 * aperture_rad, -step));
  layouts_.emplace(key, layout);
  return layout;
}

}  // namespace lidarseg
