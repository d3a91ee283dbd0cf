#pragma once
/// @file
/// lidarseg::report: the one palette of every picture of every tool (the odometry and
/// batch plots, the inspector's window, renderings and report): a colour per method, and
/// the rule that colours a reference trajectory drawn beside them.

#include <string>
#include <vector>

namespace lidarseg::report {

/// sRGB colour, 0..255.
struct Rgb {
  unsigned char r = 0, g = 0, b = 0;
};

inline constexpr Rgb kLidarsegColour{0, 80, 200};    ///< blue: lidarseg
inline constexpr Rgb kIcpColour{220, 0, 0};          ///< red: MRPT ICP keyframed
inline constexpr Rgb kIcpS2sColour{160, 0, 160};     ///< purple: MRPT ICP scan to scan
inline constexpr Rgb kTruthColour{0, 0, 0};          ///< black: ground truth, log poses
inline constexpr Rgb kWheelColour{140, 140, 140};    ///< grey: the log's wheel odometry
inline constexpr Rgb kOtherColour{30, 150, 30};      ///< green: any other trajectory

// What a scan drawing shows (the paper's Fig. 6, the inspector's window and renders).
inline constexpr Rgb kScanPointColour{90, 90, 90};   ///< dark grey: a scan's raw points
inline constexpr Rgb kDoorColour{220, 20, 20};       ///< red: a door and its jambs
inline constexpr Rgb kCornerColour{20, 170, 20};     ///< green: a corner
inline constexpr Rgb kRobotColour{200, 40, 40};      ///< red: the sensor (robot) itself

/// The colour of each reference trajectory (named on the command line or read beside a
/// log), in the order given: a ground truth (named "gt" or containing "truth") black, an
/// MRPT ICP trajectory (containing "icp" or "ICP") red, and the others green and grey in
/// turn, in the order they come among the others. O(number of names).
std::vector<Rgb> referenceColours(const std::vector<std::string>& names);

}  // namespace lidarseg::report
