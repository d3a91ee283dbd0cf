#pragma once
/// @file RawlogWriter.h
/// lidarseg-odometry --write-rawlog: the input log written back as an MRPT rawlog with
/// lidarseg's motion as the robot's odometry action (decision 54: the MRPT observation
/// rides along in each record for this writer).

#include <string>
#include <vector>

#include "lidarseg/core/Feature.h"
#include "lidarseg/core/Pose2D.h"
#include "lidarseg/mrpt/GzipOutputStream.h"
#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/LaserOdometry.h"
#include "lidarseg/report/OutputFiles.h"

namespace lidarseg::pipeline {

/// Writes, per scan, an action collection (the robot's motion since the previous scan as a
/// `CActionRobotMovement2D` with its covariance, robot frame) then a sensory frame (the scan,
/// the observations that came with it except the log's own odometry, and optionally the
/// scan's doors and corners as a `CObservationBearingRange`). gzip level 1, as MRPT's own
/// tools write rawlogs, through `GzipOutputStream` (every write and the end of the stream
/// checked); under a temporary name that `outputs` puts in place.
class RawlogWriter {
 public:
  /// @param landmarks add each scan's features as landmarks (for MRPT's EKF SLAM).
  /// @throws std::runtime_error naming the temporary file when it cannot be written.
  RawlogWriter(const std::string& path, report::OutputSet& outputs, bool landmarks);

  /// One scan. `stamp_s`: the scan's repaired stamp (the TUM files'), strictly increasing;
  /// `features`: the scan's doors and corners (sensor frame), used with landmarks only.
  /// @throws std::runtime_error "cannot write the rawlog 'PATH': why" when the file cannot
  /// take it (disk full, file size limit).
  void write(const mrpt_adapter::LaserRecord& record, const mrpt_adapter::LaserOdometryStep& step,
             double stamp_s, const std::vector<Feature>& features);

  /// Ends the gzip stream (its last blocks and trailer), syncs and closes the file; call it
  /// before `outputs` commits.
  /// @throws std::runtime_error "cannot write the rawlog 'PATH': why" when the end of the
  /// file cannot be written (the disk fills, or the file size limit is reached, within its
  /// last kilobytes): the run then fails and the temporary file is removed, never published.
  void close();

 private:
  std::string path_;
  bool landmarks_;
  mrpt_adapter::GzipOutputStream out_;
  Pose2D last_pose_;  // robot pose of the previous scan, odometry frame
};

}  // namespace lidarseg::pipeline
