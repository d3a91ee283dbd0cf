#pragma once
/// @file SegmentAlignment.h
/// lidarseg's segment matcher as an MRPT map-alignment algorithm, a drop-in alternative
/// to mrpt::slam::CICP for 2D scans of structured buildings.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/slam/CMetricMapsAlignmentAlgorithm.h>

#include "lidarseg/core/CorrelativeSearch.h"
#include "lidarseg/core/ScanRefiner.h"
#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/core/SegmentMatcher.h"
#include "lidarseg/core/SegmentOdometry.h"
#include "lidarseg/mrpt/LaserOdometry.h"

namespace lidarseg::mrpt_adapter {

/// Aligns two point maps built from 2D scans by matching their segments (paper §III.A),
/// where mrpt::slam::CICP would match points.
///
/// The maps must hold the points of one scan each, in scan order (as
/// `CSimplePointsMap::insertObservation` or `loadFromRangeScan` leave them), both in the
/// same robot-fixed convention; `AlignPDF(m1, m2, prior)` returns the pose of m2's frame in
/// m1's (T_m1_m2, m and rad) as a `CPosePDFGaussian` whose covariance comes from the line
/// least squares (large along an unconstrained direction: see TReturnInfo::status).
///
/// Used like CICP: options from a config section (TConfigParams), results of a call in a
/// TReturnInfo with CICP's `nIterations` and `goodness`. It runs lidarseg-odometry's own
/// step on the pair (SegmentOdometry with m1 as the keyframe and the initial estimate as
/// the prior): the segment match (paper §III.A), then the point-to-segment refinement and,
/// when both fail, the correlative recovery search, so an MRPT program gets what the
/// tools compute. O(beams) for the segmentation and the refinement plus the matcher's
/// O(segments x band) per iteration.
///
/// For a sequence of scans it also tracks, as the lidarseg tools do (they all run this
/// class): track() gives each scan's robot pose in the odometry frame against a keyframe
/// and a local map kept between calls, with the velocity for the constant-velocity prior
/// and the rolling-shutter correction. The pairwise AlignPDF() and the tracking are
/// independent: each has its own options (`options`, `trackingOptions`) and its own state.
class SegmentAlignment : public mrpt::slam::CMetricMapsAlignmentAlgorithm {
 public:
  /// Parameters, loadable like CICP::TConfigParams: one section holding the
  /// [segmentation] keys, the [matcher] keys and `level` (cascade level 0..3), with the
  /// names and units of config/default.ini (see its comments).
  struct TConfigParams : public mrpt::config::CLoadableOptions {
    /// How each map's points are cut into segments (the [segmentation] keys).
    SegmentationParams segmentation;
    /// How the two maps' segments are matched (the [matcher] keys).
    MatcherParams matcher;
    /// Cascade level whose segments are matched (key `level`, by name or 0..3).
    CascadeLevel level = CascadeLevel::kFusedAgain;
    /// Point-to-segment refinement after the match (the [refiner] keys, prefixed
    /// `refine_`: `refine_enabled = 0` keeps the segment-only estimate).
    RefinerParams refiner;
    /// Correlative search when the match and the refinement fail (the [search] keys,
    /// prefixed `search_`); only with `recovery`.
    SearchParams search;
    /// Search for the pose when the match and the refinement from the prior fail (key
    /// `recovery`, 0 or 1).
    bool recovery = true;

    /// Reads the keys present in `section`; a key that is absent keeps its current value.
    /// A missing section is not an error: every field keeps its value (the defaults, for
    /// a default-constructed object), as CICP::TConfigParams::loadFromConfigFile does, so a
    /// misspelt section name also gives the defaults. Works for INI and YAML sources
    /// (`CConfigFileMemory::setContentFromYAML`). The fields only change when the whole
    /// section is valid.
    /// @throws std::invalid_argument naming the section and key for an unknown key in the
    /// section, a value that is not a number, or one out of range.
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    /// Writes every key to `section`, full precision (loading it back gives equal fields).
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
    /// @throws std::invalid_argument naming the first key out of range.
    void validate() const;
  };

  /// Results of one alignment, the analogue of CICP::TReturnInfo. Every field is written
  /// on every AlignPDF() / Align3DPDF() call that is given one, whatever the outcome.
  /// `nIterations` and `goodness` keep CICP's names so that code reading them compiles
  /// with either algorithm.
  struct TReturnInfo : public mrpt::slam::TMetricMapAlignmentResult {
    /// How the segment match ended: kOk, kDegenerate (translation unconstrained along one
    /// direction, where the initial estimate is kept) or kTooFewMatches (the initial
    /// estimate is returned unchanged).
    MatchStatus status = MatchStatus::kTooFewMatches;
    /// How the whole step ended, as lidarseg-odometry reports each scan: kOk, kDegenerate
    /// (one direction kept from the initial estimate), kRecovered (found by the search) or
    /// kLost (the initial estimate is returned, with a large covariance).
    TrackStatus track = TrackStatus::kLost;
    /// Segment couples (m1, m2) the final estimate rests on (0 for kTooFewMatches).
    std::size_t matches = 0;
    /// Segments of m1 at the cascade level used (before MatcherParams::max_segments).
    std::size_t segments_m1 = 0;
    /// Segments of m2 at the cascade level used (before MatcherParams::max_segments).
    std::size_t segments_m2 = 0;
    /// Iterations of the point refinement when it ran, else the association-and-solve
    /// rounds of the segment matcher (MatchResult::iterations; 0 with kTooFewMatches).
    /// Like CICP's nIterations a measure of the work done (a few here where CICP takes
    /// tens).
    unsigned int nIterations = 0;
    /// Quality of the alignment in [0, 1]. After a refinement: the fraction of m2's points
    /// (those it used) within reach of m1's lines (RefineResult::inlier_ratio), the
    /// analogue of CICP's fraction of m2's points with a correspondence. Without one: the
    /// fraction of m2's points that belong to a segment of the final couples (0 for
    /// kTooFewMatches or an empty m2).
    double goodness = 0.0;
  };

  /// Parameters of the tracking (track()): the laser odometry's, lidarseg::OdometryParams
  /// (segmentation, matcher, refiner, search, keyframes, deskew, priors), loadable from one
  /// section like TConfigParams.
  struct TTrackingParams : public OdometryParams, public mrpt::config::CLoadableOptions {
    /// The defaults of OdometryParams.
    TTrackingParams() = default;
    /// The given odometry parameters (not validated here: track() and the constructor do).
    explicit TTrackingParams(const OdometryParams& params) : OdometryParams(params) {}

    /// Reads the keys present in `section`: the [odometry] keys of config/default.ini
    /// under their own names, and TConfigParams' keys (the [segmentation] and [matcher]
    /// keys, `refine_`- and `search_`-prefixed [refiner] and [search] keys); `level` and
    /// `recovery` are the odometry's. So the [odometry] section of a tool's file loads as
    /// it is. Absent keys and an absent section keep the current values (CICP's contract);
    /// the fields only change when the whole section is valid.
    /// @throws std::invalid_argument naming the section and key for an unknown key, a
    /// value that is not a number, or one out of range.
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    /// Writes every key to `section`, full precision (loading it back gives equal fields).
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
  };

  /// One tracked scan: the core step (sensor frame, matching details, stage timings in
  /// µs), the robot pose in the odometry frame (the robot frame at the first scan since
  /// the last reset, m and rad) with its accumulated covariance, and the robot's motion
  /// since the previous scan (robot frame) with its covariance.
  using TTrackResult = LaserOdometryStep;

  /// Default parameters (the defaults of SegmentationParams and MatcherParams).
  SegmentAlignment() = default;
  /// @throws std::invalid_argument for invalid parameters.
  explicit SegmentAlignment(const TConfigParams& params);
  /// Pairwise and tracking parameters.
  /// @throws std::invalid_argument for invalid parameters of either.
  SegmentAlignment(const TConfigParams& params, const OdometryParams& tracking);

  /// Parameters used by the next call; validated at every call.
  TConfigParams options;

  /// Parameters of the tracking. Read (and validated) by the first track() after
  /// construction or resetTracking(); changes made while tracking take effect at the next
  /// resetTracking().
  TTrackingParams trackingOptions;

  /// Tracks the next scan of a sequence: its pose against the current keyframe and local
  /// map, from the prior, then the keyframe renewed when the robot moved far enough.
  /// @param scan the laser's scan in the sensor frame; `scan.stamp_s` (s) is the motion
  ///        model's clock (velocity, deskew).
  /// @param T_robot_sensor the laser's pose on the robot (m, rad).
  /// @param robot_odometry_increment the robot's motion since the previous scan (robot
  ///        frame, m and rad), e.g. wheel odometry, used as the prior; empty: constant
  ///        velocity.
  /// Never throws on a scan that matches badly: its status says so (TrackStatus).
  /// @throws std::invalid_argument for invalid trackingOptions (first call after a reset)
  ///         or a scan that cannot be used (fewer than 2 beams); the tracking state is then
  ///         unchanged.
  TTrackResult track(const Scan& scan, const Pose2D& T_robot_sensor,
                     const std::optional<Pose2D>& robot_odometry_increment = {});
  /// The same for an MRPT observation: the laser's pose on the robot from its
  /// `sensorPose`, the stamp from `stamp_s` (s) when given, else its timestamp.
  TTrackResult track(const mrpt::obs::CObservation2DRangeScan& scan,
                     const std::optional<mrpt::poses::CPose2D>& robot_odometry_increment = {},
                     std::optional<double> stamp_s = {});
  /// Forgets the tracked scans: the next track() starts a new odometry frame, with the
  /// trackingOptions it then holds.
  void resetTracking();
  /// The core odometry behind track() (the last scan's segmentation, the keyframe, the
  /// velocity), sensor frame.
  /// @throws std::logic_error when no scan was tracked since the last reset.
  const SegmentOdometry& trackingCore() const;

  /// Pose of m2's frame in m1's (T_m1_m2), starting from the mean of
  /// `initialEstimationPDF` (its covariance is not used). Never throws on data: a failed
  /// match returns the initial estimate with a large covariance and says so in `outInfo`
  /// (a TReturnInfo, or a plain TMetricMapAlignmentResult for the execution time only).
  /// A map's point with a non-finite coordinate is a beam without return.
  /// @throws std::invalid_argument when a map is not a point map, for invalid options, or
  ///         for a non-finite initial estimate.
  mrpt::poses::CPosePDF::Ptr AlignPDF(
      const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
      const mrpt::poses::CPosePDFGaussian& initialEstimationPDF,
      mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> outInfo = std::nullopt) override;

  /// The planar case of a 3D alignment: the initial estimate must have z, pitch and roll
  /// of 0 (within 1e-6); z, pitch and roll of the result are 0 with a tiny variance.
  /// `outInfo` is filled as by AlignPDF().
  /// @throws std::invalid_argument otherwise (segment matching is planar).
  mrpt::poses::CPose3DPDF::Ptr Align3DPDF(
      const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
      const mrpt::poses::CPose3DPDFGaussian& initialEstimationPDF,
      mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> outInfo = std::nullopt) override;

 private:
  /// The odometry that aligns each pair, kept while `options` stay the same (key values).
  std::optional<SegmentOdometry> odometry_;
  std::vector<double> odometry_key_;
  /// The tracking odometry, made from trackingOptions at the first track() after a reset.
  std::optional<LaserOdometry> tracker_;
};

}  // namespace lidarseg::mrpt_adapter
