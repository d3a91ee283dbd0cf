#pragma once
/// @file FeatureEvaluation.h
/// Recall and precision of detected doors and corners against ground truth, per type.

#include <array>
#include <cstddef>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/core/Feature.h"

namespace lidarseg::eval {

/// A true feature of one scan (sensor frame), as the simulator writes it
/// (`<prefix>.features.csv`).
struct TrueFeature {
  FeatureType type = FeatureType::kCornerConcave;
  /// What the scan can show it as (a door ajar with its leaf out of sight: door_open).
  FeatureType seen_as = FeatureType::kCornerConcave;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  /// Counted for recall only when resolvable; any true feature can make a detection right.
  bool resolvable = true;
  /// As the simulator writes them: a door's wall normal pointing away from the sensor, a
  /// corner's bisector (rad); a door's width (m, 0 for corners); the index of the door in
  /// the world or of the corner in the oracle's list.
  double theta_rad = 0.0;
  double width_m = 0.0;
  std::size_t id = 0;
  /// The stamp of the scan the truth was written for (s, column t): how a run tells the
  /// truth of its own log from another's.
  double stamp_s = 0.0;
};

/// Reads a simulator feature file: a header line, then
/// `scan,t,type,x,y,theta,width,id[,resolvable[,seen_as]]` per line; grouped by scan.
/// @throws std::runtime_error naming file:line and the column for a bad line or an
/// unreadable file.
std::map<std::size_t, std::vector<TrueFeature>> readTrueFeatures(const std::string& path);

/// Counts for one type (or one family: doors, corners).
struct DetectionCounts {
  std::size_t truths = 0;            ///< resolvable true features
  std::size_t truths_found = 0;      ///< of them, matched by a detection of the right type
  std::size_t detections = 0;        ///< detections reported
  std::size_t detections_right = 0;  ///< matched to a true feature of the right type
  std::size_t visible = 0;           ///< every true feature in view, resolvable or not
  std::size_t visible_found = 0;     ///< of them, matched by a detection of the right type
  double recall() const;     ///< truths_found / truths; NaN without truths
  double precision() const;  ///< detections_right / detections; NaN without detections
  double visibleRecall() const;  ///< visible_found / visible: includes the unresolvable
};

/// Accumulates recall and precision over scans. A detection and a true feature match when
/// both are doors or both are corners and they lie within `gate_m` of each other, each used
/// once (nearest pairs first). A match is of the right type when the detection's type is
/// the true one or the one it is seen as.
class FeatureEvaluation {
 public:
  explicit FeatureEvaluation(double gate_m = 0.2);

  /// Adds one scan; returns the position errors (m) of its matched pairs.
  std::vector<double> add(const std::vector<TrueFeature>& truth, const std::vector<Feature>& detected);

  /// Per type, indexed by FeatureType (the true type seen_as for truths).
  const std::array<DetectionCounts, kNumFeatureTypes>& byType() const { return by_type_; }
  /// Doors of any type (right type = any door), and corners of either type.
  const DetectionCounts& doors() const { return doors_; }
  const DetectionCounts& corners() const { return corners_; }
  /// confusion()[true seen_as][detected type]: matched pairs.
  const std::array<std::array<std::size_t, kNumFeatureTypes>, kNumFeatureTypes>& confusion() const {
    return confusion_;
  }
  std::size_t scans() const { return scans_; }
  /// Of the last scan added: for each true feature, the index of the detection matched to
  /// it (-1: none); for each detection, the index of its true feature (-1: none).
  const std::vector<int>& lastTruthMatches() const { return truth_match_; }
  const std::vector<int>& lastDetectionMatches() const { return det_match_; }
  /// Position errors of every matched pair so far (m).
  const std::vector<double>& errors() const { return errors_; }
  double gate() const { return gate_m_; }

 private:
  double gate_m_;
  std::array<DetectionCounts, kNumFeatureTypes> by_type_{};
  DetectionCounts doors_{}, corners_{};
  std::array<std::array<std::size_t, kNumFeatureTypes>, kNumFeatureTypes> confusion_{};
  std::vector<double> errors_;
  std::vector<int> truth_match_, det_match_;
  std::size_t scans_ = 0;
};

/// The header of the matches CSV (lidarseg-features --matches-out, scored by bins in
/// tests/benchmarks/buildings.py): `scan,role,type,seen_as,x,y,theta,width,id,resolvable,match`.
void writeMatchesCsvHeader(std::ostream& os);

/// The matches CSV rows of the scan last added to `evaluation`: each true feature (role
/// truth, match = the detected type or none) and each detection (role detection, id = the
/// matched truth's id or -1, match = its seen_as or none); sensor frame, m and rad.
/// `truth` and `detected` are what was passed to FeatureEvaluation::add().
void writeMatchesCsvRows(std::ostream& os, std::size_t scan, const std::vector<TrueFeature>& truth,
                         const std::vector<Feature>& detected, const FeatureEvaluation& evaluation);

}  // namespace lidarseg::eval
