#pragma once
/// @file
/// lidarseg::report: the baselines a run can compare lidarseg with, by name: what their
/// outputs are called and how the pictures draw them. MRPT-free (the methods themselves
/// are in OdometryMethods.h). A new baseline is one OdometryMethod class and one entry here.

#include <string>
#include <string_view>
#include <vector>

#include "lidarseg/report/Palette.h"

namespace lidarseg::report {

/// One baseline the runs know.
struct BaselineKind {
  std::string name;         ///< `--baseline` value, `NAME.tum`, `NAME_total_us` (with '_' for '-')
  std::string description;  ///< the TUM file's header: "DESCRIPTION robot poses, odometry frame"
  std::string label;        ///< the pictures' legend
  Rgb colour;               ///< the pictures' colour
};

/// The baselines, in the order a run reports them: "icp" (MRPT ICP with lidarseg's
/// keyframe policy), then "icp-s2s" (MRPT ICP scan to scan).
const std::vector<BaselineKind>& baselineKinds();

/// The baseline named `name`, or nullptr when no baseline has that name.
const BaselineKind* baselineKind(std::string_view name);

/// The baseline the speed-up is measured against (keyframed MRPT ICP).
inline constexpr std::string_view kSpeedupBaseline = "icp";

}  // namespace lidarseg::report
