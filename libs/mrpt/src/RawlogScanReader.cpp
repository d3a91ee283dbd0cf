#include "lidarseg/mrpt/RawlogScanReader.h"

#include <algorithm>
#include <stdexcept>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

namespace lidarseg::mrpt_adapter {

// Forwards reads to the file and counts the bytes, so that an end of file met before the
// first byte of an entry (a complete log) can be told from one met inside an entry (a
// truncated log).
class RawlogScanReader::CountingStream : public mrpt::io::CStream {
 public:
  explicit CountingStream(mrpt::io::CFileGZInputStream& in) : in_(in) {}
  size_t Read(void* buffer, size_t count) override {
    const size_t n = in_.Read(buffer, count);
    bytes_ += n;
    return n;
  }
  size_t Write(const void*, size_t) override {
    throw std::logic_error("RawlogScanReader: the input stream is read-only");
  }
  uint64_t Seek(int64_t, mrpt::io::CStream::TSeekOrigin) override {
    throw std::logic_error("RawlogScanReader: the input stream cannot seek");
  }
  uint64_t getTotalBytesCount() const override { return in_.getTotalBytesCount(); }
  uint64_t getPosition() const override { return in_.getPosition(); }
  std::uint64_t bytes() const { return bytes_; }

 private:
  mrpt::io::CFileGZInputStream& in_;
  std::uint64_t bytes_ = 0;
};

RawlogScanReader::RawlogScanReader(const std::string& path, std::string sensor_label)
    : path_(path), label_(std::move(sensor_label)) {
  file_ = std::make_unique<mrpt::io::CFileGZInputStream>();
  bool opened = false;
  try {
    opened = file_->open(path_);
  } catch (const std::exception&) {
    opened = false;
  }
  if (!opened) throw std::runtime_error("cannot open rawlog '" + path_ + "'");
  counter_ = std::make_unique<CountingStream>(*file_);
}

RawlogScanReader::~RawlogScanReader() = default;

bool RawlogScanReader::accept(const mrpt::obs::CObservation2DRangeScan::Ptr& scan) {
  if (!scan) return false;
  if (std::find(labels_seen_.begin(), labels_seen_.end(), scan->sensorLabel) ==
      labels_seen_.end()) {
    labels_seen_.push_back(scan->sensorLabel);
  }
  if (label_.empty()) label_ = scan->sensorLabel;
  return scan->sensorLabel == label_;
}

void RawlogScanReader::take(const mrpt::obs::CObservation::Ptr& obs) {
  if (!obs) return;
  if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs)) {
    odometry_ = odo->odometry;
  }
  auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs);
  if (!accept(scan)) {
    companions_.push_back(obs);
    return;
  }
  RawlogScan out;
  out.entry_index = entries_read_ - 1;
  out.observation = scan;
  out.odometry = odometry_;
  out.companions = std::move(companions_);
  companions_.clear();
  pending_.push_back(std::move(out));
}

std::optional<RawlogScan> RawlogScanReader::next() {
  while (true) {
    if (!pending_.empty()) {
      RawlogScan out = std::move(pending_.front());
      pending_.erase(pending_.begin());
      out.scan_index = scans_returned_++;
      return out;
    }
    if (at_end_) return std::nullopt;

    mrpt::serialization::CSerializable::Ptr object;
    const std::uint64_t before = counter_->bytes();
    try {
      auto archive = mrpt::serialization::archiveFrom(*counter_);
      object = archive.ReadObject();
    } catch (const std::exception& e) {
      if (counter_->bytes() == before) {  // nothing left: the log ends between entries
        at_end_ = true;
        return std::nullopt;
      }
      std::string what = e.what();
      // MRPT's messages carry a stack trace; the line after "Message:" says what failed.
      const auto m = what.find("Message:");
      if (m != std::string::npos) what = what.substr(m + 8);
      const auto first = what.find_first_not_of(' ');
      what = first == std::string::npos ? std::string() : what.substr(first);
      what = what.substr(0, what.find('\n'));
      throw std::runtime_error("rawlog '" + path_ + "', entry " + std::to_string(entries_read_) +
                               ": truncated or corrupt (" + what + ")");
    }
    ++entries_read_;
    if (!object) continue;

    if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(object)) {
      for (const auto& obs : *sf) take(obs);
    } else if (auto actions = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(object)) {
      if (auto move = actions->getBestMovementEstimation()) {
        const mrpt::poses::CPose2D increment = move->poseChange->getMeanVal();
        odometry_ = odometry_ ? *odometry_ + increment : increment;
      }
    } else if (auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(object)) {
      take(obs);
    }
  }
}

}  // namespace lidarseg::mrpt_adapter
