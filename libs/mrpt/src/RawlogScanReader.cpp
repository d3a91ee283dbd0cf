#include "lidarseg/mrpt/RawlogScanReader.h"
#include "lidarseg/core/ScanRecord.h"
#include "lidarseg/logs/CompressedInput.h"
#include "lidarseg/vision/ImageFile.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <cstdio>  // before jpeglib.h, which needs FILE

#include <dlfcn.h>
#include <jpeglib.h>
#include <zlib.h>

#include <opencv2/core/mat.hpp>

#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/io/CStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

// MRPT decodes a rawlog's JPEG-compressed camera images with libjpeg and its default error
// handler, which prints one line and calls exit(1): a corrupt image ended every tool without
// the file's name and left its temporary files. While this reader deserialises an entry
// (and only then, on that thread: other users of libjpeg in the process keep its default),
// the error manager libjpeg sets up throws instead, and the reader reports the entry:
// "rawlog 'F', entry N: truncated or corrupt (a corrupt JPEG image: ...)". The decoder's
// memory is released before the throw (as jpeg_destroy does); MRPT does not touch it again.
// An image whose JPEG data does not reach its end-of-image marker is corrupt too (libjpeg
// would only warn and fill its missing rows with grey): the reader checks the bytes as they
// are read (CountingStream::Read) and fails the entry as libjpeg's error would.
// MRPT reads an image's whole JPEG data (its length, then its bytes) before decoding it, so
// the reader can then read the entry again with a placeholder image in place of the corrupt
// one, and skip it (decision 80): see RawlogScanReader::next().
namespace {
constexpr const char* kJpegErrorPrefix = "a corrupt JPEG image: ";
// An image whose JPEG header declares more pixels than the tools read (8192 x 8192, decision
// 52) is refused from that header, before MRPT's libjpeg allocates and decodes it, and its
// entry read again like a corrupt image's.
constexpr const char* kJpegOversizePrefix = "an oversized JPEG image: ";
thread_local int jpeg_errors_throw = 0;  // > 0 while RawlogScanReader deserialises an entry
thread_local int jpeg_errors_thrown = 0;  // counts throwJpegError's throws on this thread

/// Makes libjpeg's errors throw on this thread for its lifetime (decision 78).
struct JpegErrorsThrow {
  JpegErrorsThrow() { ++jpeg_errors_throw; }
  ~JpegErrorsThrow() { --jpeg_errors_throw; }
  JpegErrorsThrow(const JpegErrorsThrow&) = delete;
  JpegErrorsThrow& operator=(const JpegErrorsThrow&) = delete;
};

[[noreturn]] void throwJpegError(j_common_ptr cinfo) {
  char message[JMSG_LENGTH_MAX] = {};
  (*cinfo->err->format_message)(cinfo, message);
  // What jpeg_destroy does, through the memory manager's own entry (libjpeg is MRPT's
  // dependency, not linked here).
  if (cinfo->mem != nullptr) (*cinfo->mem->self_destruct)(cinfo);
  cinfo->mem = nullptr;
  cinfo->global_state = 0;
  ++jpeg_errors_thrown;
  throw std::runtime_error(std::string(kJpegErrorPrefix) + message);
}
}  // namespace

namespace {
// An image MRPT sizes from its declared width and height before it reads the pixels (a raw
// or zipped grey image: the buffer is allocated first) is refused above the tools' cap
// (8192 x 8192, decision 52) while an entry is deserialised on this thread: OpenCV's default
// Mat allocator is wrapped once per process, and passes every other allocation through
// (decision 105).
constexpr const char* kImageOversizePrefix = "an oversized image: ";

class CappedImageAllocator final : public cv::MatAllocator {
 public:
  explicit CappedImageAllocator(cv::MatAllocator* next) : next_(next) {}
  cv::UMatData* allocate(int dims, const int* sizes, int type, void* data, size_t* step, cv::AccessFlag flags,
                         cv::UMatUsageFlags usage) const override {
    if (jpeg_errors_throw > 0 && data == nullptr && dims == 2) {
      const auto rows = static_cast<std::uint64_t>(std::max(sizes[0], 0));
      const auto cols = static_cast<std::uint64_t>(std::max(sizes[1], 0));
      try {
        if (rows > 0 && cols > 0) lidarseg::vision::requireImageSize(cols, rows, "image", "image");
      } catch (const std::runtime_error& e) {  // "image: image of W x H pixels; ..."
        throw std::runtime_error(std::string(kImageOversizePrefix) + (e.what() + std::strlen("image: ")));
      }
    }
    return next_->allocate(dims, sizes, type, data, step, flags, usage);
  }
  bool allocate(cv::UMatData* data, cv::AccessFlag flags, cv::UMatUsageFlags usage) const override {
    return next_->allocate(data, flags, usage);
  }
  void deallocate(cv::UMatData* data) const override { next_->deallocate(data); }

 private:
  cv::MatAllocator* next_;
};

void capImageAllocations() {
  static const bool installed = [] {
    static CappedImageAllocator capped(cv::Mat::getDefaultAllocator());
    cv::Mat::setDefaultAllocator(&capped);
    return true;
  }();
  (void)installed;
}
}  // namespace

extern "C" struct jpeg_error_mgr* jpeg_std_error(struct jpeg_error_mgr* err) {
  using StdError = struct jpeg_error_mgr* (*)(struct jpeg_error_mgr*);
  static const auto libjpeg = reinterpret_cast<StdError>(dlsym(RTLD_NEXT, "jpeg_std_error"));
  if (libjpeg == nullptr) {
    std::fputs("lidarseg: libjpeg's jpeg_std_error not found\n", stderr);
    std::abort();
  }
  libjpeg(err);
  if (jpeg_errors_throw > 0) err->error_exit = throwJpegError;
  return err;
}

namespace lidarseg::mrpt_adapter {

// Forwards reads to the file and counts the bytes, so that an end of file met before the
// first byte of an entry (a complete log) can be told from one met inside an entry (a
// truncated log). A read that comes back short throws: MRPT 2.5 does not check the count
// of every read, and a log cut inside a length field left that length's bytes
// uninitialised, so the deserialiser sized a vector from them (gigabytes, seconds to tens of
// seconds per attempt; found by BadInputs.RawlogTruncatedAtEveryByte under load). It also
// keeps the CRC-32 of the bytes read, for the gzip trailer's check at the end.
//
// While an entry is deserialised it also records the bytes it gives, and the places of the
// last two reads, so that an entry whose JPEG image is corrupt can be given
// again from memory with that image replaced (replayWithImage()), then from the file on.
class RawlogScanReader::CountingStream : public mrpt::io::CStream {
 public:
  /// Bytes of one entry recorded at most; a longer entry with a corrupt image is an error.
  static constexpr std::size_t kMaxRecordedBytes = std::size_t{256} << 20;
  /// Recording memory kept between entries.
  static constexpr std::size_t kKeptCapacity = std::size_t{16} << 20;

  explicit CountingStream(mrpt::io::CFileGZInputStream& in) : in_(in) {}
  size_t Read(void* buffer, size_t count) override {
    auto* out = static_cast<unsigned char*>(buffer);
    const size_t replayed = std::min(count, replay_.size() - replay_at_);
    if (replayed > 0) std::memcpy(out, replay_.data() + replay_at_, replayed);
    replay_at_ += replayed;
    if (replay_at_ == replay_.size()) {
      if (replay_.capacity() > kKeptCapacity) replay_ = {};  // one large entry does not stay
      replay_.clear();
      replay_at_ = 0;
    }
    if (replayed < count) readFile(out + replayed, count - replayed, count);
    remember(out, count);
    if (jpeg_errors_throw > 0) requireWholeJpeg(out, count);
    return count;
  }

  /// Starts an entry: what was recorded is dropped.
  void startEntry() {
    if (record_.capacity() > kKeptCapacity) record_ = {};  // one large image does not stay
    record_.clear();
    overflow_ = false;
    reads_ = {};
  }
  /// When the entry's last two reads were an image's JPEG length (4 bytes, little-endian)
  /// and that many bytes, as MRPT reads them just before decoding: the entry's bytes up to
  /// there, with `jpeg` in place of those bytes, are given again from the next read on (then
  /// the file's), and true is returned. False when the entry read otherwise or is too long.
  bool replayWithImage(const std::vector<unsigned char>& jpeg) {
    const Place length = reads_[0], data = reads_[1];
    if (overflow_ || length.count != 4 || length.at + 4 != data.at || data.at + data.count != record_.size()) {
      return false;
    }
    const std::uint32_t declared = lengthAt(length.at);
    if (declared != data.count) return false;
    std::vector<unsigned char> again(record_.begin(), record_.begin() + static_cast<std::ptrdiff_t>(length.at));
    const auto size = static_cast<std::uint32_t>(jpeg.size());
    for (int shift = 0; shift < 32; shift += 8) again.push_back(static_cast<unsigned char>(size >> shift));
    again.insert(again.end(), jpeg.begin(), jpeg.end());
    // Bytes of an earlier replay not read yet stay after this one.
    again.insert(again.end(), replay_.begin() + static_cast<std::ptrdiff_t>(replay_at_), replay_.end());
    replay_ = std::move(again);
    replay_at_ = 0;
    startEntry();
    return true;
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
  /// CRC-32 (gzip's) of the bytes read so far.
  std::uint32_t crc() const { return static_cast<std::uint32_t>(crc_); }
  /// zlib reported damaged data (not an end of file).
  bool damaged() const { return damaged_; }

 private:
  // The little-endian 32-bit length recorded at `at`.
  std::uint32_t lengthAt(std::size_t at) const {
    return static_cast<std::uint32_t>(record_[at]) | (static_cast<std::uint32_t>(record_[at + 1]) << 8) |
           (static_cast<std::uint32_t>(record_[at + 2]) << 16) | (static_cast<std::uint32_t>(record_[at + 3]) << 24);
  }
  // The place of one read in record_.
  struct Place {
    std::size_t at = 0;
    std::size_t count = 0;
  };
  void remember(const unsigned char* bytes, std::size_t count) {
    reads_[0] = reads_[1];
    reads_[1] = Place{record_.size(), count};
    if (overflow_ || record_.size() + count > kMaxRecordedBytes) {
      overflow_ = true;
      record_.clear();
      return;
    }
    if (record_.size() + count > record_.capacity()) {  // grown by doubling, never beyond the cap
      record_.reserve(std::min(kMaxRecordedBytes, std::max(2 * record_.capacity(), record_.size() + count)));
    }
    record_.insert(record_.end(), bytes, bytes + count);
  }
  // Bytes read right after their own length (4 bytes, little-endian) that start as a JPEG
  // stream (FF D8) are an image's JPEG data, as MRPT reads them just before decoding: data
  // that does not reach its end-of-image marker fails like a corrupt image, and a frame
  // header declaring more than the cap's pixels fails before libjpeg allocates them.
  void requireWholeJpeg(const unsigned char* bytes, std::size_t count) const {
    const Place length = reads_[0];
    if (length.count != 4 || count < 2 || bytes[0] != 0xFF || bytes[1] != 0xD8 || overflow_) return;
    const std::uint32_t declared = lengthAt(length.at);
    if (declared != count) return;
    if (!vision::reachesJpegEnd(bytes, count)) {
      ++jpeg_errors_thrown;
      throw std::runtime_error(std::string(kJpegErrorPrefix) + "its data ends before the end-of-image marker");
    }
    std::string refused;
    try {
      const vision::ImageHeader header =
          vision::readJpegHeader(std::string(reinterpret_cast<const char*>(bytes), count), "image");
      vision::requireImageSize(header.width, header.height, "image", "JPEG image");
      return;
    } catch (const std::runtime_error& e) {
      refused = e.what();
    }
    ++jpeg_errors_thrown;
    // "image: JPEG image of W x H pixels; ..." (or "'image': invalid JPEG header (...)").
    if (refused.rfind("image: ", 0) == 0) {
      throw std::runtime_error(std::string(kJpegOversizePrefix) + refused.substr(std::strlen("image: ")));
    }
    throw std::runtime_error(std::string(kJpegErrorPrefix) + refused);
  }
  void readFile(unsigned char* buffer, size_t count, size_t asked) {
    const size_t n = in_.Read(buffer, count);
    if (n > count) {
      // zlib's gzread returned -1 (the data or the trailer's check is wrong), which MRPT
      // passes on as a size: nothing was read, and this is no end of file.
      damaged_ = true;
      throw std::runtime_error("the compressed data is damaged");
    }
    crc_ = crc32_z(crc_, static_cast<const Bytef*>(buffer), n);
    bytes_ += n;
    if (n < count) {
      throw std::runtime_error("the file ends inside an entry (" + std::to_string(n + asked - count) + " of " +
                               std::to_string(asked) + " bytes read)");
    }
  }

  mrpt::io::CFileGZInputStream& in_;
  std::uint64_t bytes_ = 0;
  uLong crc_ = crc32(0L, Z_NULL, 0);
  bool damaged_ = false;
  std::vector<unsigned char> record_;  // the bytes given since startEntry()
  bool overflow_ = false;              // more than kMaxRecordedBytes: nothing recorded
  std::array<Place, 2> reads_{};       // the last two reads, the latest last
  std::vector<unsigned char> replay_;  // given before the file's bytes
  std::size_t replay_at_ = 0;
};

namespace {
// A 1 x 1 grey JPEG image, in place of a corrupt one while its entry is read again.
const std::vector<unsigned char>& placeholderJpeg() {
  static const std::vector<unsigned char> jpeg = [] {
    mrpt::img::CImage image(1, 1, mrpt::img::CH_GRAY);
    image.setPixel(0, 0, 128);
    mrpt::io::CMemoryStream out;
    image.saveToStreamAsJPEG(out);
    const auto* data = static_cast<const unsigned char*>(out.getRawBufferData());
    return std::vector<unsigned char>(data, data + out.getTotalBytesCount());
  }();
  return jpeg;
}

// What MRPT's message says failed: the line after "Message:" (its messages carry a stack
// trace), or a corrupt or oversized JPEG image's message (throwJpegError, requireWholeJpeg)
// whatever MRPT wrapped around it.
std::string failureOf(const std::exception& e) {
  std::string what = e.what();
  auto jpeg = what.find(kJpegErrorPrefix);
  if (jpeg == std::string::npos) jpeg = what.find(kJpegOversizePrefix);
  if (jpeg == std::string::npos) jpeg = what.find(kImageOversizePrefix);
  if (jpeg != std::string::npos) what = "Message: " + what.substr(jpeg);
  const auto m = what.find("Message:");
  if (m != std::string::npos) what = what.substr(m + 8);
  const auto first = what.find_first_not_of(' ');
  what = first == std::string::npos ? std::string() : what.substr(first);
  return what.substr(0, what.find('\n'));
}

// What was wrong with an image its entry was read again without: "a corrupt JPEG image
// (why)" or "an oversized JPEG image (JPEG image of W x H pixels; ...)".
std::string imageFailure(const std::string& what) {
  if (what.rfind(kJpegOversizePrefix, 0) == 0) {
    return "an oversized JPEG image (" + what.substr(std::strlen(kJpegOversizePrefix)) + ")";
  }
  const bool corrupt = what.rfind(kJpegErrorPrefix, 0) == 0;
  return "a corrupt JPEG image (" + (corrupt ? what.substr(std::strlen(kJpegErrorPrefix)) : what) + ")";
}
}  // namespace

RawlogScanReader::RawlogScanReader(const std::string& path, std::string sensor_label)
    : path_(path), label_(std::move(sensor_label)), label_requested_(!label_.empty()) {
  capImageAllocations();
  file_ = std::make_unique<mrpt::io::CFileGZInputStream>();
  bool opened = false;
  try {
    opened = file_->open(path_);
  } catch (const std::exception&) {
    opened = false;
  }
  if (!opened) throw std::runtime_error("cannot open rawlog '" + path_ + "'");
  counter_ = std::make_unique<CountingStream>(*file_);
  std::ifstream raw(path_, std::ios::binary);
  std::array<char, 2> magic{};
  gzip_ = raw.read(magic.data(), 2) && static_cast<unsigned char>(magic[0]) == 0x1f &&
          static_cast<unsigned char>(magic[1]) == 0x8b;
  std::error_code ec;
  const double file_bytes = static_cast<double>(std::filesystem::file_size(path_, ec));
  if (ec) return;
  expected_bytes_ = file_bytes;
  if (!gzip_ || file_bytes < 18) return;
  // The trailer's size is modulo 2^32: for a log of more than 4 GiB, 2^32 is added until the
  // size is at least half the file's (no rawlog compresses to more than twice its size; a
  // file under 1 MB cannot hold 4 GiB of rawlog at deflate's ratio, and keeps the size read).
  std::ifstream tail(path_, std::ios::binary);
  tail.seekg(-4, std::ios::end);
  std::array<unsigned char, 4> b{};
  if (!tail.read(reinterpret_cast<char*>(b.data()), 4)) return;
  double isize = static_cast<double>(b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<std::uint32_t>(b[3]) << 24));
  while (file_bytes > 1e6 && isize < 0.5 * file_bytes) isize += 4294967296.0;
  expected_bytes_ = isize;
}

double RawlogScanReader::fractionRead() const {
  if (expected_bytes_ <= 0) return 0.0;
  // MRPT's getPosition() of a gzip stream counts uncompressed bytes, its getTotalBytesCount()
  // compressed ones: both sides are counted here in uncompressed bytes instead.
  return std::clamp(static_cast<double>(counter_->bytes()) / expected_bytes_, 0.0, 1.0);
}

std::string RawlogScanReader::compressedStreamError() const { return logs::CompressedInput::problemOf(path_); }

void RawlogScanReader::checkCompressedEnd() const {
  if (!gzip_) return;
  // The gzip trailer holds the CRC-32 of the uncompressed data and its size modulo 2^32:
  // both equal to what was read, the stream is whole (the common case, one read of 8 bytes).
  std::ifstream raw(path_, std::ios::binary | std::ios::ate);
  const std::streamoff size = raw.tellg();
  if (size >= 18) {
    std::array<unsigned char, 8> b{};
    raw.seekg(size - 8);
    raw.read(reinterpret_cast<char*>(b.data()), 8);
    const auto word = [&](int at) {
      return static_cast<std::uint32_t>(b[at] | (b[at + 1] << 8) | (b[at + 2] << 16)) |
             (static_cast<std::uint32_t>(b[at + 3]) << 24);
    };
    if (raw && word(4) == static_cast<std::uint32_t>(counter_->bytes()) && word(0) == counter_->crc()) return;
  }
  // Otherwise (a cut stream, a trailer that does not match its data, or a file of several
  // gzip members) the whole stream is read once more, member by member: MRPT's stream (and
  // zlib's gzread()) report a cut stream, a damaged later member or garbage after the last
  // as a normal end.
  const std::string error = compressedStreamError();
  if (!error.empty()) {
    throw std::runtime_error("rawlog '" + path_ + "', entry " + std::to_string(entries_read_) +
                             ": truncated or corrupt (the compressed data ends early or fails its check: " + error +
                             ")");
  }
}

namespace {
// An odometry pose or increment usable as such: finite and within kMaxLogCoordinate (a
// corrupt 1e308 would overflow every later sum of increments).
bool usablePose(const mrpt::poses::CPose2D& p) {
  const auto ok = [](double v) { return std::isfinite(v) && std::abs(v) <= kMaxLogCoordinate; };
  return ok(p.x()) && ok(p.y()) && ok(p.phi());
}
}  // namespace

RawlogScanReader::~RawlogScanReader() = default;

void RawlogScanReader::dropOdometry(const char* what) {
  ++dropped_odometry_count_;
  const std::string message =
      "rawlog '" + path_ + "', entry " + std::to_string(entries_read_ - 1) + ": " + what + " is not finite or beyond +-1e6 (m or rad); not used";
  if (dropped_odometry_.size() < 100) dropped_odometry_.push_back(message);
  dropped_odometry_tally_.add(message);
}

bool RawlogScanReader::accept(const mrpt::obs::CObservation2DRangeScan::Ptr& scan) {
  if (!scan) return false;
  if (std::find(labels_seen_.begin(), labels_seen_.end(), scan->sensorLabel) == labels_seen_.end()) {
    if (labels_seen_.size() < kMaxLabelsListed) {
      labels_seen_.push_back(scan->sensorLabel);
    } else {
      more_labels_ = true;
    }
  }
  if (label_.empty()) label_ = scan->sensorLabel;
  return scan->sensorLabel == label_;
}

void RawlogScanReader::keepCompanion(const mrpt::obs::CObservation::Ptr& obs) {
  companions_.push_back(obs);
  // Trimmed in batches (amortised O(1)) to the latest kMaxCompanions: a label no scan has,
  // or a laser far rarer than the other sensors, must not keep the whole log in memory.
  if (companions_.size() >= 2 * kMaxCompanions) {
    const std::size_t excess = companions_.size() - kMaxCompanions;
    companions_.erase(companions_.begin(), companions_.begin() + static_cast<std::ptrdiff_t>(excess));
    dropped_companions_ += excess;
  }
}

void RawlogScanReader::throwLabelAbsent() const {
  std::string labels;
  for (const std::string& l : labels_seen_) labels += (labels.empty() ? "'" : ", '") + l + "'";
  if (more_labels_) labels += " and more";
  throw std::runtime_error("rawlog '" + path_ + "': no laser scan labelled '" + label_ + "' (its laser labels: " +
                           labels + ")");
}

void RawlogScanReader::take(const mrpt::obs::CObservation::Ptr& obs) {
  if (!obs) return;
  if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs)) {
    const auto& p = odo->odometry;
    // A non-finite reading is not kept: it would poison every later odometry pose.
    if (usablePose(p)) {
      odometry_ = p;
    } else {
      // The scans after it have no odometry until the next good reading: the last good one
      // would stand for them and make the robot stand still.
      odometry_.reset();
      dropOdometry("an odometry reading");
    }
  }
  auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs);
  if (!accept(scan)) {
    keepCompanion(obs);
    return;
  }
  RawlogScan out;
  out.entry_index = entries_read_ - 1;
  out.observation = scan;
  out.odometry = odometry_;
  if (companions_.size() > kMaxCompanions) {
    const std::size_t excess = companions_.size() - kMaxCompanions;
    companions_.erase(companions_.begin(), companions_.begin() + static_cast<std::ptrdiff_t>(excess));
    dropped_companions_ += excess;
  }
  out.companions = std::move(companions_);
  companions_.clear();
  pending_.push_back(std::move(out));
}

void RawlogScanReader::skipEntryWithCorruptImages(const mrpt::serialization::CSerializable::Ptr& object,
                                                  const std::vector<std::string>& corrupt_images) {
  // The entry's observations that hold no image are whole: a sensory frame's laser scans and
  // odometry readings are kept, the rest of the entry (the placeholders among it) skipped.
  // Counted as the scans the reader returns: those of the requested label only.
  const std::size_t pending_before = pending_.size();
  if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(object)) {
    for (const auto& obs : *sf) {
      if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs) ||
          std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs)) {
        take(obs);
      }
    }
  }
  const std::size_t kept_scans = pending_.size() - pending_before;
  std::string message = "rawlog '" + path_ + "', entry " + std::to_string(entries_read_ - 1) + ": " + corrupt_images.front();
  if (corrupt_images.size() > 1) message += " and " + std::to_string(corrupt_images.size() - 1) + " more";
  message += kept_scans > 0 ? "; the entry skipped but its " + std::to_string(kept_scans) + " laser scan(s)"
                            : "; entry skipped";
  ++skipped_entry_count_;
  if (skipped_entries_.size() < 100) skipped_entries_.push_back(message);
  skipped_entries_tally_.add(message);
}

std::optional<RawlogScan> RawlogScanReader::next() {
  while (true) {
    if (!pending_.empty()) {
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // GCC 12: std::optional<CPose2D>'s move
      RawlogScan out = std::move(pending_.front());
#pragma GCC diagnostic pop
      pending_.erase(pending_.begin());
      out.scan_index = scans_returned_++;
      return out;
    }
    if (at_end_) return std::nullopt;

    mrpt::serialization::CSerializable::Ptr object;
    const std::uint64_t before = counter_->bytes();
    counter_->startEntry();
    // The corrupt JPEG images of this entry, each replaced by a placeholder when the entry
    // is read again (MRPT's deserialiser cannot be resumed inside an entry).
    std::vector<std::string> corrupt_images;
    while (true) {
      const int jpeg_errors_before = jpeg_errors_thrown;
      try {
        auto archive = mrpt::serialization::archiveFrom(*counter_);
        const JpegErrorsThrow jpeg_errors_throw_here;
        object = archive.ReadObject();
        break;
      } catch (const std::exception& e) {
        if (corrupt_images.empty() && counter_->bytes() == before && !counter_->damaged()) {
          // nothing left: the log ends between entries
          at_end_ = true;
          checkCompressedEnd();
          if (label_requested_ && scans_returned_ == 0 && !labels_seen_.empty()) throwLabelAbsent();
          return std::nullopt;
        }
        std::string what = failureOf(e);
        bool replayed = false;
        if (jpeg_errors_thrown != jpeg_errors_before && corrupt_images.size() < kMaxCorruptImagesPerEntry) {
          try {
            replayed = counter_->replayWithImage(placeholderJpeg());
          } catch (const std::exception& again) {  // no memory for the copy: the entry's error below
            what += std::string("; it could not be read again: ") + again.what();
          }
        }
        if (replayed) {
          corrupt_images.push_back(imageFailure(what));
          continue;
        }
        // A gzip rawlog: zlib says what is wrong with the compressed data (a cut, a check that
        // fails), when something is; zlib drops the bytes of a damaged block, so the entry
        // named is where the loss begins.
        if (gzip_) {
          const std::string error = compressedStreamError();
          if (!error.empty()) what += "; gzip: " + error;
        }
        at_end_ = true;  // nothing more is read from a stream out of step with its entries
        throw std::runtime_error("rawlog '" + path_ + "', entry " + std::to_string(entries_read_) +
                                 ": truncated or corrupt (" + what + ")");
      }
    }
    ++entries_read_;
    if (!object) continue;
    if (!corrupt_images.empty()) {
      skipEntryWithCorruptImages(object, corrupt_images);
      continue;
    }

    if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(object)) {
      for (const auto& obs : *sf) take(obs);
    } else if (auto actions = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(object)) {
      if (auto move = actions->getBestMovementEstimation()) {
        const mrpt::poses::CPose2D increment = move->poseChange->getMeanVal();
        // A non-finite increment is dropped: summed, it would poison every later pose.
        if (usablePose(increment)) {
          odometry_ = odometry_ ? *odometry_ + increment : increment;
        } else {
          dropOdometry("a robot movement");
        }
      }
    } else if (auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(object)) {
      take(obs);
    }
  }
}

}  // namespace lidarseg::mrpt_adapter
