#include "lidarseg/mrpt/GzipOutputStream.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

namespace lidarseg::mrpt_adapter {

namespace {
// deflateInit2's window bits: 15 (32 KiB, the largest) + 16 for a gzip header and trailer.
constexpr int kGzipWindowBits = 15 + 16;
constexpr int kMemoryLevel = 8;  // zlib's default
}  // namespace

struct GzipOutputStream::Deflater {
  z_stream stream{};
  bool initialised = false;
  std::vector<unsigned char> out = std::vector<unsigned char>(kBufferBytes);
  ~Deflater() {
    if (initialised) deflateEnd(&stream);
  }
};

GzipOutputStream::GzipOutputStream(const std::string& path, const std::string& name, int level)
    : name_(name.empty() ? path : name), z_(std::make_unique<Deflater>()) {
  if (level < 0 || level > 9) throw std::invalid_argument("gzip level " + std::to_string(level) + " is not in [0, 9]");
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) fail(std::strerror(errno));
  if (deflateInit2(&z_->stream, level, Z_DEFLATED, kGzipWindowBits, kMemoryLevel, Z_DEFAULT_STRATEGY) != Z_OK) {
    ::close(fd_);
    fd_ = -1;
    fail("zlib cannot start a gzip stream");
  }
  z_->initialised = true;
  z_->stream.next_out = z_->out.data();
  z_->stream.avail_out = static_cast<uInt>(z_->out.size());
}

GzipOutputStream::~GzipOutputStream() {
  if (fd_ >= 0) ::close(fd_);
}

void GzipOutputStream::fail(const std::string& reason) {
  if (failure_.empty()) failure_ = reason;
  throw std::runtime_error("cannot write '" + name_ + "': " + failure_);
}

void GzipOutputStream::writeOut(const unsigned char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd_, data, size);
    if (n < 0 && errno == EINTR) continue;
    // A write that takes no byte (0) is taken as a full disk, so the loop ends.
    if (n <= 0) fail(n < 0 ? std::strerror(errno) : std::strerror(ENOSPC));
    data += n;
    size -= static_cast<std::size_t>(n);
  }
}

void GzipOutputStream::drain(bool finish) {
  z_stream& s = z_->stream;
  while (true) {
    const int rc = deflate(&s, finish ? Z_FINISH : Z_NO_FLUSH);
    if (rc == Z_STREAM_ERROR) fail("zlib's deflate failed");
    if (s.avail_out == 0 || (finish && rc == Z_STREAM_END)) {
      writeOut(z_->out.data(), z_->out.size() - s.avail_out);
      s.next_out = z_->out.data();
      s.avail_out = static_cast<uInt>(z_->out.size());
    }
    if (finish ? rc == Z_STREAM_END : s.avail_in == 0 && s.avail_out > 0) return;
  }
}

std::size_t GzipOutputStream::Write(const void* buffer, std::size_t count) {
  if (!failure_.empty()) fail(failure_);
  // A write after a successful close() is the caller's mistake, not a failure of the file:
  // it is refused without touching the stream's state, so the file stays complete and a
  // later close() does nothing (it used to record "closed" as the stream's failure, which
  // that close() then threw).
  if (fd_ < 0) {
    throw std::logic_error("cannot write '" + name_ + "': the stream is closed (a write after close()); the file " +
                           "is complete and unchanged");
  }
  const auto* bytes = static_cast<const unsigned char*>(buffer);
  std::size_t left = count;
  while (left > 0) {
    // avail_in is 32 bits: larger buffers go in pieces.
    const std::size_t piece = std::min<std::size_t>(left, std::size_t{1} << 30);
    z_->stream.next_in = const_cast<unsigned char*>(bytes);
    z_->stream.avail_in = static_cast<uInt>(piece);
    drain(false);
    bytes += piece;
    left -= piece;
  }
  written_ += count;
  return count;
}

void GzipOutputStream::close() {
  if (fd_ < 0) {
    if (!failure_.empty()) fail(failure_);
    return;
  }
  if (!failure_.empty()) fail(failure_);
  z_->stream.next_in = nullptr;
  z_->stream.avail_in = 0;
  drain(true);
  // The last blocks and the trailer are on their way; a full disk can still be reported by
  // fsync (delayed allocation, network file systems) or by close.
  if (::fsync(fd_) != 0 && errno != EINVAL && errno != EROFS) fail(std::strerror(errno));
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0 && errno != EINTR) fail(std::strerror(errno));
}

std::size_t GzipOutputStream::Read(void*, std::size_t) {
  throw std::logic_error("GzipOutputStream '" + name_ + "' is write-only");
}

std::uint64_t GzipOutputStream::Seek(std::int64_t, mrpt::io::CStream::TSeekOrigin) {
  throw std::logic_error("GzipOutputStream '" + name_ + "' cannot seek");
}

std::uint64_t GzipOutputStream::getTotalBytesCount() const { return written_; }
std::uint64_t GzipOutputStream::getPosition() const { return written_; }
std::string GzipOutputStream::getStreamDescription() const { return "gzip file '" + name_ + "'"; }

}  // namespace lidarseg::mrpt_adapter
