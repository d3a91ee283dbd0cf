#pragma once
/// @file BeamLayout.h
/// Directions of the beams of a planar range sensor.

#include <cstddef>
#include <map>
#include <memory>
#include <tuple>
#include <vector>

namespace lidarseg {

/// The beam directions of a 2D range sensor, in the sensor frame (x forward, y left,
/// angles counter-clockwise from x, radians), with their cosines and sines precomputed
/// once so that converting a scan to points costs two multiplications per beam.
///
/// A layout is shared (read-only) by every scan of the same sensor.
class BeamLayout {
 public:
  BeamLayout() = default;

  /// Layout from explicit beam angles (rad), in scan order.
  /// @throws std::invalid_argument if an angle is not finite.
  explicit BeamLayout(std::vector<double> angles_rad);

  /// Evenly spaced beams: angle(i) = first_angle_rad + i * increment_rad.
  /// A negative increment describes a clockwise sensor.
  /// @throws std::invalid_argument if an argument is not finite.
  static BeamLayout uniform(std::size_t num_beams, double first_angle_rad, double increment_rad);

  /// Evenly spaced beams over a field of view centred on x:
  /// from -fov/2 to +fov/2 inclusive (the convention of MRPT and SICK data sheets).
  static BeamLayout centred(std::size_t num_beams, double field_of_view_rad);

  std::size_t size() const { return angles_.size(); }
  bool empty() const { return angles_.empty(); }
  double angle(std::size_t i) const { return angles_[i]; }
  double cosine(std::size_t i) const { return cos_[i]; }
  double sine(std::size_t i) const { return sin_[i]; }
  const std::vector<double>& angles() const { return angles_; }

  /// Mean absolute angle between consecutive beams (rad); 0 with fewer than 2 beams.
  double meanIncrement() const { return mean_increment_; }

  /// True when the last beam is followed by the first one, i.e. the beams cover a full
  /// turn (the gap from last to first is at most 1.5 mean increments). Segments may
  /// then continue across the wrap-around.
  bool wrapsAround() const { return wraps_; }

  /// Sums over beams [first, last] (inclusive) of cos^2, cos*sin and sin^2 of the beam
  /// angles. O(1) from prefix sums; used by the segments' noise model.
  void sumOuterProducts(std::size_t first, std::size_t last, double& cc, double& cs,
                        double& ss) const {
    cc = prefix_cc_[last + 1] - prefix_cc_[first];
    cs = prefix_cs_[last + 1] - prefix_cs_[first];
    ss = prefix_ss_[last + 1] - prefix_ss_[first];
  }

 private:
  void precompute();

  std::vector<double> angles_;
  std::vector<double> cos_;
  std::vector<double> sin_;
  std::vector<double> prefix_cc_, prefix_cs_, prefix_ss_;  // size() + 1 entries each
  double mean_increment_ = 0.0;
  bool wraps_ = false;
};

/// Layouts of sensors whose beams are evenly spaced over an aperture centred on the sensor's
/// x axis (MRPT's observations, CARMEN laser lines): beam i at -aperture/2 + i * step
/// counter-clockwise, or +aperture/2 - i * step clockwise, step = aperture / (beams - 1).
/// Cached per (beams, aperture, direction), so a sensor's cosines and sines are computed once
/// for a whole log; the cache holds at most kMaxLayouts (a log whose aperture varies scan by
/// scan does not grow it without bound). Not thread-safe: one per reader.
class CentredLayoutCache {
 public:
  static constexpr std::size_t kMaxLayouts = 16;
  /// @param num_beams at least 2
  /// @param aperture_rad finite and > 0 (the caller checks)
  std::shared_ptr<const BeamLayout> get(std::size_t num_beams, double aperture_rad, bool counter_clockwise);

 private:
  std::map<std::tuple<std::size_t, double, bool>, std::shared_ptr<const BeamLayout>> layouts_;
};

}  // namespace lidarseg
