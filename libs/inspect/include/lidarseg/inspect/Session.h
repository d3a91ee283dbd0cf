#pragma once
/// @file Session.h
/// The model behind lidarseg-inspect: a laser log opened lazily, each scan segmented (every
/// cascade level), matched against its keyframe and searched for doors and corners when it
/// is asked for, never all at start. Parameters can change at any time; the current scan is
/// then processed again.

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "lidarseg/inspect/Drawing.h"
#include "lidarseg/core/Feature.h"
#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/core/SegmentOdometry.h"
#include "lidarseg/core/StampPolicy.h"
#include "lidarseg/eval/StampedTrajectory.h"
#include "lidarseg/vision/RegionsOfInterest.h"

namespace lidarseg::mrpt_adapter {
class LaserLogReader;
struct LaserRecord;
}  // namespace lidarseg::mrpt_adapter

namespace lidarseg::pipeline {
class OdometryRun;
}  // namespace lidarseg::pipeline

namespace lidarseg::inspect {

/// Everything the inspector's pipeline can be tuned with.
struct InspectorParams {
  OdometryParams odometry;
  /// How the log's stamps are repaired (the same run as lidarseg-odometry's).
  StampPolicyParams stamps;
  FeatureDetectorParams features;
  vision::RoiParams rois;
  std::optional<vision::CameraParams> camera;  ///< empty: the images' own calibration

  /// Reads [segmentation], [matcher], [refiner], [search], [odometry], [stamps], [features],
  /// [camera], [rois] (each optional; one LidarsegConfig). @throws as the loaders do (file:line [section] key).
  static InspectorParams fromFile(const std::string& path);
  /// Writes every section the other apps read.
  void saveIni(const std::string& path) const;
};

/// Which layers a picture shows.
struct Layers {
  bool raw_points = true;
  std::array<bool, kNumCascadeLevels> levels{false, true, false, true};
  bool indices = false;        ///< segment indices beside the segments
  bool predicted = true;       ///< keyframe segments moved by the prior
  bool matches = true;         ///< matched pairs
  bool features = true;        ///< doors (red), corners (green)
  bool trajectory = true;      ///< lidarseg, references, ground truth
  bool camera = true;          ///< camera image with ROI boxes
};

/// One processed scan.
struct Frame {
  std::size_t index = 0;
  double stamp_s = 0.0;
  std::string where;           ///< place in the log
  std::string error;           ///< non-empty: the scan could not be used
  Segmentation segmentation;   ///< every level, sensor frame
  std::vector<Feature> features;
  OdometryStep step;           ///< match against the keyframe, timings
  std::size_t keyframe_index = 0;
  /// The keyframe's segmentation (every level) the match used, in the keyframe's frame.
  std::shared_ptr<const Segmentation> keyframe_segments;
  double detect_us = 0.0;
  /// The camera image (with ROI boxes drawn) of the scan, when the log has one.
  cv::Mat camera;
  std::size_t rois = 0;
};

/// A trajectory shown beside lidarseg's (ground truth or another method's), TUM file.
struct Reference {
  std::string name;
  eval::StampedTrajectory poses;
};

class Session {
 public:
  /// Opens `log` (rawlog or CARMEN). Nothing is read beyond the first scan.
  /// @throws std::runtime_error naming the file when it cannot be opened.
  Session(const std::string& log, const std::string& sensor_label, InspectorParams params);
  ~Session();

  /// Scan `index`, processed on demand (the scans before it are matched first, once).
  /// @throws std::out_of_range past the end of the log.
  const Frame& frame(std::size_t index);
  /// Index of the scan nearest to `stamp_s` among those that exist (reads on if needed).
  std::size_t indexAtTime(double stamp_s);
  /// Number of scans read so far; `complete()` once the end of the log was met.
  std::size_t scansRead() const { return records_.size(); }
  bool complete() const { return complete_; }
  /// Reads the whole log (for the last index or the report).
  std::size_t countAll();

  const InspectorParams& params() const { return params_; }
  /// New parameters: cached results are dropped, frames are processed again on demand.
  /// @throws std::invalid_argument (the old parameters stay) when they are invalid.
  void setParams(const InspectorParams& params);

  void addReference(Reference reference) { references_.push_back(std::move(reference)); }
  const std::vector<Reference>& references() const { return references_; }
  /// lidarseg's sensor poses (odometry frame) of scans 0..index.
  std::vector<Pose2D> trajectory(std::size_t index);
  /// lidarseg's robot poses of scans 0..index, stamped: the same run, hence the same poses,
  /// as lidarseg-odometry's lidarseg.tum (constant-velocity prior). A scan that could not
  /// be used has none.
  eval::StampedTrajectory robotTrajectory(std::size_t index);

  /// The picture of scan `index` with these layers.
  Drawing draw(std::size_t index, const Layers& layers);

  const std::string& path() const { return path_; }
  /// The laser's mounting pose on the robot at the first scan (x, y, yaw).
  Pose2D mountOfFirstScan() const;

 private:
  bool readUpTo(std::size_t index);
  void matchUpTo(std::size_t index);
  // draw(): lidarseg's path and the references' up to `f`, in f's sensor frame.
  void drawTrajectories(const Frame& f, Drawing& d);

  std::string path_;
  InspectorParams params_;
  std::unique_ptr<mrpt_adapter::LaserLogReader> reader_;
  std::vector<std::shared_ptr<mrpt_adapter::LaserRecord>> records_;
  bool complete_ = false;
  // Odometry run so far (scan by scan, in order): the run every tool shares.
  std::unique_ptr<pipeline::OdometryRun> run_;
  struct Step {
    OdometryStep step;
    std::optional<eval::StampedPose> robot_pose;
    std::size_t keyframe_index = 0;
    std::shared_ptr<const Segmentation> keyframe_segments;
    std::string error;
  };
  std::vector<Step> steps_;
  std::size_t keyframe_index_ = 0;
  std::shared_ptr<const Segmentation> keyframe_segments_;
  std::optional<Frame> cached_;
  std::vector<Reference> references_;
};

}  // namespace lidarseg::inspect
