#pragma once
/// @file PoseConversion.h
/// lidarseg's planar poses and covariances to MRPT's types and back.

#include <Eigen/Core>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose2D.h>

#include "lidarseg/core/Pose2D.h"

namespace lidarseg::mrpt_adapter {

inline mrpt::poses::CPose2D toMrpt(const Pose2D& p) { return {p.x, p.y, p.yaw}; }
inline Pose2D toPose2D(const mrpt::poses::CPose2D& p) { return {p.x(), p.y(), p.phi()}; }
/// A 3x3 covariance of (x, y, yaw).
inline mrpt::math::CMatrixDouble33 toMrpt(const Eigen::Matrix3d& m) {
  mrpt::math::CMatrixDouble33 out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out(r, c) = m(r, c);
  return out;
}

}  // namespace lidarseg::mrpt_adapter
