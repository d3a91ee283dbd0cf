#include "lidarseg/pipeline/RawlogWriter.h"

#include <stdexcept>

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include "lidarseg/mrpt/ExceptionMessage.h"
#include "lidarseg/mrpt/FeatureObservation.h"
#include "lidarseg/mrpt/PoseConversion.h"

namespace lidarseg::pipeline {

using mrpt_adapter::toMrpt;

RawlogWriter::RawlogWriter(const std::string& path, report::OutputSet& outputs, bool landmarks)
    : path_(path), landmarks_(landmarks), out_(outputs.addWritten(path), path, 1) {}

void RawlogWriter::close() {
  try {
    out_.close();
  } catch (const std::exception&) {
    throw std::runtime_error("cannot write the rawlog '" + path_ + "': " + out_.failure());
  }
}

void RawlogWriter::write(const mrpt_adapter::LaserRecord& record,
                         const mrpt_adapter::LaserOdometryStep& step, double stamp_s,
                         const std::vector<Feature>& features) {
  const auto observation = mrpt_adapter::observationOf(record);
  const auto& obs = *observation;
  auto archive = mrpt::serialization::archiveFrom(out_);
  const Pose2D pose = mrpt_adapter::toPose2D(step.robot_pose.mean);
  const Pose2D inc = step.core.first ? Pose2D{} : relative(pose, last_pose_);
  last_pose_ = pose;
  mrpt::obs::CActionCollection actions;
  mrpt::obs::CActionRobotMovement2D move;
  move.rawOdometryIncrementReading = toMrpt(inc);
  move.estimationMethod = mrpt::obs::CActionRobotMovement2D::emScan2DMatching;
  move.poseChange = mrpt::poses::CPosePDFGaussian::Create(toMrpt(inc), step.increment.cov);
  move.timestamp = mrpt::Clock::fromDouble(stamp_s);
  actions.insert(move);
  mrpt::obs::CSensoryFrame frame;
  // The log's own odometry observations are replaced by lidarseg's action.
  for (const auto& other : record.companions) {
    if (!std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(other)) frame.insert(other);
  }
  frame.insert(observation);
  if (landmarks_) {
    auto landmarks = mrpt_adapter::makeBearingRangeObservation(features, obs.sensorPose,
                                                               obs.maxRange, obs.aperture);
    landmarks->timestamp = obs.timestamp;
    frame.insert(landmarks);
  }
  // The stream's own failure says why (disk full, file size limit); MRPT's archive may
  // wrap it in its banner and backtrace.
  try {
    archive << actions << frame;
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot write the rawlog '" + path_ + "': " +
                             (out_.failure().empty() ? mrpt_adapter::exceptionMessage(e.what()) : out_.failure()));
  }
}

}  // namespace lidarseg::pipeline
