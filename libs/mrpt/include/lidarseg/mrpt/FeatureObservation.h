#pragma once
/// @file FeatureObservation.h
/// Doors and corners as MRPT range-bearing landmarks, for MRPT's EKF SLAM
/// (`mrpt::slam::CRangeBearingKFSLAM2D`, the `kf-slam` app).

#include <string>
#include <vector>

#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/poses/CPose3D.h>

#include "lidarseg/core/Feature.h"

namespace lidarseg::mrpt_adapter {

/// One landmark per feature, measured from the laser: range (m) and yaw (rad) of its
/// position in the sensor frame, pitch 0, landmarkID -1 (no identity: the SLAM associates),
/// and each measurement's 3x3 (range, yaw, pitch) covariance propagated from the feature's
/// (x, y) covariance (validCovariances = true; the pitch variance is a tiny constant so the
/// matrix stays invertible). The sensor's pose on the robot is the laser's.
/// @param max_range_m,field_of_view_rad the laser's, for the observation's sensor fields.
mrpt::obs::CObservationBearingRange::Ptr makeBearingRangeObservation(
    const std::vector<Feature>& features, const mrpt::poses::CPose3D& sensor_pose, double max_range_m,
    double field_of_view_rad, const std::string& sensor_label = "LIDAR_FEATURES");

}  // namespace lidarseg::mrpt_adapter
