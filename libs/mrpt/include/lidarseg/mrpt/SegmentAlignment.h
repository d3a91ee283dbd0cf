#pragma once
/// @file SegmentAlignment.h
/// lidarseg's segment matcher as an MRPT map-alignment algorithm, a drop-in alternative
/// to mrpt::slam::CICP for 2D scans of structured buildings.

#include <cstddef>
#include <string>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/slam/CMetricMapsAlignmentAlgorithm.h>

#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/core/SegmentMatcher.h"

namespace lidarseg::mrpt_adapter {

/// Aligns two point maps built from 2D scans by matching their segments (paper §III.A),
/// where mrpt::slam::CICP would match points.
///
/// The maps must hold the points of one scan each, in scan order (as
/// `CSimplePointsMap::insertObservation` or `loadFromRangeScan` leave them), both in the
/// same robot-fixed convention; `AlignPDF(m1, m2, prior)` returns the pose of m2's frame in
/// m1's as a `CPosePDFGaussian` whose covariance comes from the line least squares (large
/// along an unconstrained direction: see TReturnInfo::status).
class SegmentAlignment : public mrpt::slam::CMetricMapsAlignmentAlgorithm {
 public:
  /// Parameters, loadable like CICP::TConfigParams: one section holding the
  /// [segmentation] keys, the [matcher] keys and `level` (cascade level 0..3).
  struct TConfigParams : public mrpt::config::CLoadableOptions {
    SegmentationParams segmentation;
    MatcherParams matcher;
    CascadeLevel level = CascadeLevel::kFusedAgain;
    /// @throws std::invalid_argument naming the section and key for an unknown key, a
    /// value that is not a number or one out of range.
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
    void validate() const;
  };

  /// Extra results of an alignment.
  struct TReturnInfo : public mrpt::slam::TMetricMapAlignmentResult {
    MatchStatus status = MatchStatus::kTooFewMatches;
    std::size_t matches = 0;
    std::size_t segments_m1 = 0;
    std::size_t segments_m2 = 0;
  };

  SegmentAlignment() = default;
  /// @throws std::invalid_argument for invalid parameters.
  explicit SegmentAlignment(const TConfigParams& params);

  TConfigParams options;

  /// @throws std::invalid_argument when a map is not a point map.
  mrpt::poses::CPosePDF::Ptr AlignPDF(
      const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
      const mrpt::poses::CPosePDFGaussian& initialEstimationPDF,
      mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> outInfo = std::nullopt) override;

  /// The planar case of a 3D alignment: the initial estimate must have z, pitch and roll
  /// of 0 (within 1e-6); z, pitch and roll of the result are 0 with a tiny variance.
  /// @throws std::invalid_argument otherwise (segment matching is planar).
  mrpt::poses::CPose3DPDF::Ptr Align3DPDF(
      const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
      const mrpt::poses::CPose3DPDFGaussian& initialEstimationPDF,
      mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> outInfo = std::nullopt) override;
};

}  // namespace lidarseg::mrpt_adapter
