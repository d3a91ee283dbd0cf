#pragma once
/// @file StampedTrajectory.h
/// Timestamped planar trajectories and the TUM trajectory format.

#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "lidarseg/core/Pose2D.h"

namespace lidarseg::eval {

/// A pose with its time (s, the log's clock).
struct StampedPose {
  double stamp_s = 0.0;
  Pose2D pose;
};

/// Poses in increasing time order.
using StampedTrajectory = std::vector<StampedPose>;

/// Reads a TUM trajectory file: `timestamp x y z qx qy qz qw` per line, `#` comments;
/// the yaw is taken from the quaternion (rotation about z), z is ignored.
/// @throws std::runtime_error naming the file and line for an unreadable file, a line
/// without 8 numbers, a non-finite value, a time going backwards or a quaternion whose norm
/// is outside [0.9, 1.1] (one within is normalised; decision 108).
StampedTrajectory readTum(const std::string& path);

/// Writes one TUM line per pose (nanosecond-resolution stamps, z = 0).
void writeTum(std::ostream& os, const StampedTrajectory& trajectory, const std::string& header = {});

/// Index of the pose whose stamp is nearest to `stamp_s`, if within `tolerance_s`.
/// O(log n).
std::optional<std::size_t> nearestIndex(const StampedTrajectory& trajectory, double stamp_s,
                                        double tolerance_s);

/// Path length (sum of the distances between consecutive positions, m).
double pathLength(const StampedTrajectory& trajectory);

}  // namespace lidarseg::eval
