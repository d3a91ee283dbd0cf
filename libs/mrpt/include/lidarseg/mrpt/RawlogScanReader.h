#pragma once
/// @file RawlogScanReader.h
/// Streams the 2D laser scans of an MRPT .rawlog file.

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/serialization/CSerializable.h>

#include "lidarseg/core/WarningTally.h"

namespace mrpt::io {
class CFileGZInputStream;
}

namespace lidarseg::mrpt_adapter {

/// One laser scan of a rawlog, with its place in the file.
struct RawlogScan {
  /// 0-based index of the top-level rawlog entry (sensory frame, action collection or
  /// observation) that held the scan.
  std::size_t entry_index = 0;
  /// 0-based index of this scan among the scans returned so far.
  std::size_t scan_index = 0;
  mrpt::obs::CObservation2DRangeScan::Ptr observation;
  /// Wheel odometry of the robot when the scan was read (odometry frame): the sum of the
  /// `CActionRobotMovement2D` increments so far (sensory-frame layout) or the last
  /// `CObservationOdometry` (observations layout); empty when the log has none yet.
  std::optional<mrpt::poses::CPose2D> odometry;
  /// The other observations read since the previous scan (same sensory frame, or between
  /// the two scans), in file order: cameras, other lasers, odometry observations.
  std::vector<mrpt::obs::CObservation::Ptr> companions;
};

/// Reads the `CObservation2DRangeScan`s of an MRPT rawlog one at a time, in both rawlog
/// layouts (sensory frames with actions, and observations only; gzip-compressed or not),
/// without loading the whole file.
///
/// When the log holds several lasers, only those with the requested sensor label are
/// returned; with no label requested, the label of the first scan is used. A requested
/// label no scan has is an error at the end of the file, listing the labels the log has.
///
/// An entry holding a camera image whose JPEG data is corrupt (libjpeg fails on it while
/// MRPT deserialises the entry) is read again with a 1 x 1 placeholder in place of that
/// image, and skipped: the reading goes on with the next entry, and the entry is listed in
/// skippedEntries() with its place ("rawlog 'F', entry N: a corrupt JPEG image (…); entry
/// skipped"). Of a sensory frame, the laser scans and odometry readings (which hold no image)
/// are kept. This relies on MRPT reading an image's JPEG length and bytes just before it
/// decodes them; an entry read otherwise, or longer than 256 MiB, is the "truncated or
/// corrupt" error (decision 80).
///
/// Memory stays bounded whatever the layout: at most kMaxCompanions observations are kept
/// between two returned scans (the latest; the others are counted in droppedCompanions()),
/// and at most kMaxLabelsListed distinct labels are remembered.
class RawlogScanReader {
 public:
  /// Observations kept as one scan's companions (an image or odometry reading is the one
  /// just before the scan; a thousand covers a 1 kHz sensor beside a 1 Hz laser).
  static constexpr std::size_t kMaxCompanions = 1000;
  /// Distinct laser labels remembered for labelsSeen() and the messages.
  static constexpr std::size_t kMaxLabelsListed = 100;
  /// Corrupt JPEG images replaced in one entry at most; more is the entry's error.
  static constexpr std::size_t kMaxCorruptImagesPerEntry = 64;

  /// Opens the file.
  /// @throws std::runtime_error naming the file when it cannot be opened.
  explicit RawlogScanReader(const std::string& path, std::string sensor_label = {});
  ~RawlogScanReader();
  RawlogScanReader(const RawlogScanReader&) = delete;
  RawlogScanReader& operator=(const RawlogScanReader&) = delete;

  /// The next scan, or std::nullopt at the end of the file.
  /// @throws std::runtime_error naming the file and entry index when the file is truncated
  /// or holds data that is not a valid MRPT object, or when a gzip rawlog's stream is cut or
  /// fails its trailer's check (CRC-32 and size of the data, checked at the end); naming the file and the labels it has
  /// when it ends without a scan of the requested label.
  std::optional<RawlogScan> next();

  const std::string& path() const { return path_; }
  /// Share of the rawlog's bytes read so far, 0 to 1, for a progress's time left: of a gzip
  /// rawlog, its uncompressed bytes over the size its gzip trailer declares (modulo 2^32,
  /// taken above half the file's size); of a plain one, its bytes over the file's size.
  double fractionRead() const;
  /// The label scans are filtered by (empty until the first scan when none was given).
  const std::string& sensorLabel() const { return label_; }
  /// Laser labels seen so far, including skipped ones (the first kMaxLabelsListed).
  const std::vector<std::string>& labelsSeen() const { return labels_seen_; }
  /// Observations dropped because more than kMaxCompanions came between two scans.
  std::size_t droppedCompanions() const { return dropped_companions_; }
  /// Number of top-level rawlog entries read so far.
  std::size_t entriesRead() const { return entries_read_; }
  /// Odometry readings or movements dropped because a value was not finite ("entry N: ..."),
  /// the first 100, and how many.
  const std::vector<std::string>& droppedOdometry() const { return dropped_odometry_; }
  std::size_t droppedOdometryCount() const { return dropped_odometry_count_; }
  /// The dropped odometry readings and movements as warnings counted per kind in full.
  const WarningTally& droppedOdometryTally() const { return dropped_odometry_tally_; }
  /// Entries skipped because they hold a corrupt JPEG image, "rawlog 'F', entry N: a corrupt
  /// JPEG image (libjpeg's message); entry skipped" (the first 100), how many in all, and
  /// as warnings counted per kind in full.
  const std::vector<std::string>& skippedEntries() const { return skipped_entries_; }
  std::size_t skippedEntryCount() const { return skipped_entry_count_; }
  const WarningTally& skippedEntriesTally() const { return skipped_entries_tally_; }

 private:
  class CountingStream;
  bool accept(const mrpt::obs::CObservation2DRangeScan::Ptr& scan);
  /// At the end of a gzip-compressed rawlog: throws if the compressed stream was cut or its
  /// trailer (CRC-32, size) does not match the data read.
  void checkCompressedEnd() const;
  /// zlib's reading of the whole gzip file: "" when the stream is whole, else what is wrong.
  std::string compressedStreamError() const;
  bool gzip_ = false;
  double expected_bytes_ = 0;  // the uncompressed size, for fractionRead()

  std::string path_;
  std::string label_;
  std::unique_ptr<mrpt::io::CFileGZInputStream> file_;
  std::unique_ptr<CountingStream> counter_;
  bool at_end_ = false;
  void take(const mrpt::obs::CObservation::Ptr& obs);
  std::vector<RawlogScan> pending_;  // from one sensory frame
  std::optional<mrpt::poses::CPose2D> odometry_;
  std::vector<mrpt::obs::CObservation::Ptr> companions_;
  std::vector<std::string> labels_seen_;
  bool more_labels_ = false;  // distinct labels beyond kMaxLabelsListed were seen
  bool label_requested_ = false;
  std::size_t dropped_companions_ = 0;
  void keepCompanion(const mrpt::obs::CObservation::Ptr& obs);
  [[noreturn]] void throwLabelAbsent() const;
  std::size_t entries_read_ = 0;
  std::size_t scans_returned_ = 0;
  std::vector<std::string> dropped_odometry_;
  std::size_t dropped_odometry_count_ = 0;
  WarningTally dropped_odometry_tally_;
  void dropOdometry(const char* what);
  std::vector<std::string> skipped_entries_;
  std::size_t skipped_entry_count_ = 0;
  WarningTally skipped_entries_tally_;
  void skipEntryWithCorruptImages(const mrpt::serialization::CSerializable::Ptr& object,
                                  const std::vector<std::string>& corrupt_images);
};

}  // namespace lidarseg::mrpt_adapter
