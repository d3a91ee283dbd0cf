#pragma once
/// @file Angles.h
/// The one definition of pi and the degree/radian factors every library uses.

namespace lidarseg {

/// pi (rad).
inline constexpr double kPi = 3.14159265358979323846;
/// Degrees per radian and radians per degree.
inline constexpr double kRadToDeg = 180.0 / kPi;
inline constexpr double kDegToRad = kPi / 180.0;

}  // namespace lidarseg
