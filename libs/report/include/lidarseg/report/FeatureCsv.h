#pragma once
/// @file FeatureCsv.h
/// The features CSV that lidarseg-features and lidarseg-odometry --features-out write
/// (docs/decisions.md 22): doors and corners per scan in the robot frame (m, rad).

#include <cstddef>
#include <ostream>
#include <vector>

#include "lidarseg/core/Feature.h"
#include "lidarseg/core/Pose2D.h"

namespace lidarseg::report {

/// The header line: t,type,x,y,theta,width,confidence,scan,var_x,var_y,cov_xy,var_theta,var_width
void writeFeatureCsvHeader(std::ostream& os);

/// One line per feature, moved from the sensor frame to the robot frame (T_robot_sensor;
/// covariance rotated).
void writeFeatureCsvRows(std::ostream& os, double stamp_s, std::size_t scan, const Pose2D& T_robot_sensor,
                         const std::vector<Feature>& features);

}  // namespace lidarseg::report
