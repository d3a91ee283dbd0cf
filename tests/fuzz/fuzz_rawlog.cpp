/// @file fuzz_rawlog.cpp
/// libFuzzer target: rawlogs read through lidarseg's reader (both layouts, plain or gzip,
/// truncated anywhere), the conversion to core scans and the segmentation.
///
/// Structure-aware: the input is a program that writes a rawlog with MRPT's own serialiser
/// (sensory frames with scans of any beam count, range, aperture, label, stamp and
/// validity; odometry actions; bare observations: scans, odometry, images), then cuts the
/// file at an input-chosen byte. Raw byte mutation is not used because MRPT 2.5's
/// deserialiser sizes strings and vectors from the file before reading them: a corrupt
/// length makes it allocate up to 16 GiB, and under memory pressure its aligned allocator
/// returns null and it writes through it (docs/reliability.md, "Findings in dependencies").
/// lidarseg cannot intercept that from outside the deserialiser; what lidarseg owns (entry
/// accounting, truncation, layouts, labels, odometry, conversion) is what this exercises.

#include <cmath>
#include <cstdint>
#include <limits>

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include "FuzzInput.h"
#include "LogThroughCore.h"

using namespace lidarseg;

namespace {

float rangeOf(std::uint8_t code, double max_range) {
  switch (code) {
    case 255: return std::numeric_limits<float>::quiet_NaN();
    case 254: return std::numeric_limits<float>::infinity();
    case 253: return -1.0f;
    case 252: return 1e30f;
    case 251: return static_cast<float>(max_range);
    default: return static_cast<float>(code) * 0.05f;  // 0 .. 12.5 m
  }
}

mrpt::obs::CObservation2DRangeScan::Ptr makeScan(fuzz::ByteReader& in, double& stamp) {
  auto scan = mrpt::obs::CObservation2DRangeScan::Create();
  const std::uint8_t shape = in.u8();
  const std::size_t beams = shape % 4 == 0 ? in.u8() % 4 : 2 + in.u16() % 1200;  // 0..3 beams too
  scan->aperture = static_cast<float>(in.in(0.0, 2.0 * M_PI + 0.2));
  scan->rightToLeft = (shape & 4) == 0;
  scan->maxRange = static_cast<float>(in.in(0.0, 40.0));
  scan->sensorLabel = (shape & 8) ? "LASER2" : "LASER";
  scan->sensorPose = mrpt::poses::CPose3D(in.in(-1, 1), in.in(-1, 1), 0.3, in.in(-M_PI, M_PI), 0, 0);
  const std::uint8_t dt = in.u8();
  stamp += dt == 255 ? -0.5 : dt == 254 ? 0.0 : dt == 253 ? 10.0 : dt * 0.001;  // backwards, repeated, gaps
  scan->timestamp = mrpt::Clock::fromDouble(stamp);
  scan->resizeScan(beams);
  for (std::size_t i = 0; i < beams; ++i) {
    const std::uint8_t code = in.u8();
    scan->setScanRange(i, rangeOf(code, scan->maxRange));
    scan->setScanRangeValidity(i, code != 250);
  }
  return scan;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::ByteReader in(data, size);
  const std::uint8_t mode = in.u8();
  const std::string path = fuzz::writeInput(nullptr, 0, "input.rawlog");
  {
    mrpt::io::CFileGZOutputStream file;
    file.open(path, (mode & 1) ? 1 : 0);  // gzip level 1 or plain
    auto archive = mrpt::serialization::archiveFrom(file);
    double stamp = 1000.0;
    for (int entry = 0; entry < 24 && in.remaining() > 0; ++entry) {
      const std::uint8_t kind = in.u8() % 6;
      if (kind == 0 || kind == 1) {  // a sensory frame with one or two scans (and an image)
        mrpt::obs::CSensoryFrame frame;
        frame.insert(makeScan(in, stamp));
        if (kind == 1) {
          auto image = mrpt::obs::CObservationImage::Create();
          image->sensorLabel = "CAMERA";
          image->timestamp = mrpt::Clock::fromDouble(stamp);
          frame.insert(image);
          frame.insert(makeScan(in, stamp));
        }
        archive << frame;
      } else if (kind == 2) {  // an odometry action
        mrpt::obs::CActionCollection actions;
        mrpt::obs::CActionRobotMovement2D move;
        const mrpt::poses::CPose2D inc(in.in(-2, 2), in.in(-2, 2), in.in(-M_PI, M_PI));
        move.rawOdometryIncrementReading = inc;
        move.poseChange = mrpt::poses::CPosePDFGaussian::Create(inc);
        actions.insert(move);
        archive << actions;
      } else if (kind == 3 || kind == 4) {  // a bare scan observation
        archive << *makeScan(in, stamp);
      } else {  // a bare odometry observation
        auto odo = mrpt::obs::CObservationOdometry::Create();
        odo->odometry = mrpt::poses::CPose2D(in.in(-50, 50), in.in(-50, 50), in.in(-M_PI, M_PI));
        odo->timestamp = mrpt::Clock::fromDouble(stamp);
        archive << *odo;
      }
    }
  }
  if (mode & 2) {  // cut the file at a chosen byte
    std::FILE* f = std::fopen(path.c_str(), "r+b");
    std::fseek(f, 0, SEEK_END);
    const long length = std::ftell(f);
    std::fclose(f);
    const long cut = length == 0 ? 0 : static_cast<long>(in.u16()) % length;
    if (truncate(path.c_str(), cut) != 0) std::abort();
  }

  fuzz::readLogThroughCore(path);
  return 0;
}
