#pragma once
/// @file CarmenScan.h
/// A CARMEN laser line as the core's scan and sensor mounting, with no MRPT in between.

#include <stdexcept>

#include "lidarseg/core/BeamLayout.h"
#include "lidarseg/core/Pose2D.h"
#include "lidarseg/core/Scan.h"
#include "lidarseg/logs/CarmenLogReader.h"

namespace lidarseg::logs {

/// The scan of a laser line, sensor frame: x along the middle of the line's aperture (the
/// frame MRPT gives a range scan; carmenSensorOnRobot() is where that frame sits on the
/// robot). Beams evenly spaced from start_angle_rad by angular_resolution_rad (counter-clockwise
/// when positive). A beam is valid when its range is finite, > 0 and < max_range_m; the
/// valid ranges are the line's own values (double); invalid beams hold the maximum range.
/// The aperture and the maximum range are taken at float precision, as MRPT's
/// CObservation2DRangeScan stores them, so that the ICP baseline, which reads the line
/// through such an observation, sees the same beam directions.
/// @param layouts the reader's cache of layouts (one per beam count, aperture, direction)
/// @throws std::invalid_argument for fewer than 2 beams, a zero resolution, or an aperture
/// that is not a finite positive float.
Scan carmenScan(const CarmenLaser& laser, CentredLayoutCache& layouts);

/// Pose of the scan's frame (carmenScan()) on the robot, T_robot_sensor (m, rad): the line's
/// laser mounting turned to the middle of its aperture.
Pose2D carmenSensorOnRobot(const CarmenLaser& laser);

}  // namespace lidarseg::logs
