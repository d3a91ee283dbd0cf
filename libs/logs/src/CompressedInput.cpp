#include "lidarseg/logs/CompressedInput.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <zlib.h>

namespace lidarseg::logs {

struct CompressedInput::Stream {
  z_stream zs{};
  bool ready = false;
  ~Stream() {
    if (ready) inflateEnd(&zs);
  }
};

namespace {
constexpr std::size_t kChunk = std::size_t{1} << 16;
}  // namespace

CompressedInput::CompressedInput(const std::string& path) : in_(kChunk), z_(std::make_unique<Stream>()) {
  errno = 0;
  file_ = std::fopen(path.c_str(), "rb");
  if (file_ == nullptr) {
    const int err = errno;
    throw std::runtime_error("cannot open '" + path + "'" + (err != 0 ? ": " + std::string(std::strerror(err)) : std::string()));
  }
  // The first two bytes decide (a pipe cannot be read again: they are kept as input).
  while (in_end_ < 2 && refill()) {
  }
  gzip_ = in_end_ >= 2 && in_[0] == 0x1f && in_[1] == 0x8b;
  if (gzip_) {
    // 15 + 16: a gzip wrapper (header, CRC-32 and size checked by inflate()).
    if (inflateInit2(&z_->zs, 15 + 16) != Z_OK) throw std::runtime_error("zlib cannot start a gzip stream");
    z_->ready = true;
    in_member_ = true;
  }
}

CompressedInput::~CompressedInput() {
  if (file_ != nullptr) std::fclose(file_);
}

bool CompressedInput::refill() {
  if (file_end_) return false;
  if (in_begin_ > 0) {  // keep what is unread at the front
    std::memmove(in_.data(), in_.data() + in_begin_, in_end_ - in_begin_);
    in_end_ -= in_begin_;
    in_begin_ = 0;
  }
  if (in_end_ == in_.size()) return true;
  const std::size_t got = std::fread(in_.data() + in_end_, 1, in_.size() - in_end_, file_);
  if (got == 0) {
    if (std::ferror(file_)) throw std::runtime_error(std::string("read error: ") + std::strerror(errno));
    file_end_ = true;
    return false;
  }
  in_end_ += got;
  file_read_ += got;
  return true;
}

std::size_t CompressedInput::read(char* out, std::size_t n) {
  if (n == 0) return 0;
  if (!gzip_) {
    if (in_begin_ == in_end_ && !refill()) return 0;
    const std::size_t k = std::min(n, in_end_ - in_begin_);
    std::memcpy(out, in_.data() + in_begin_, k);
    in_begin_ += k;
    return k;
  }
  return readMembers(out, n);
}

std::size_t CompressedInput::readMembers(char* out, std::size_t n) {
  z_stream& zs = z_->zs;
  while (true) {
    if (!in_member_) {
      // Between members: the end, zero padding (as gzip allows), or another member.
      while (in_end_ - in_begin_ < 2 && refill()) {
      }
      const std::size_t left = in_end_ - in_begin_;
      if (left == 0) return 0;
      if (left >= 2 && in_[in_begin_] == 0x1f && in_[in_begin_ + 1] == 0x8b) {
        inflateReset(&zs);
        in_member_ = true;
        continue;
      }
      // Zeros to the end are padding; anything else is not a gzip member.
      const std::uint64_t at = file_read_ - left;
      do {
        for (std::size_t i = in_begin_; i < in_end_; ++i) {
          if (in_[i] != 0) {
            throw std::runtime_error("bytes after the end of the compressed data at byte " + std::to_string(at) +
                                     " that are no gzip member (a damaged or cut member, or garbage appended)");
          }
        }
        in_begin_ = in_end_;
      } while (refill());
      return 0;
    }
    if (in_begin_ == in_end_) refill();
    zs.next_in = in_.data() + in_begin_;
    zs.avail_in = static_cast<uInt>(in_end_ - in_begin_);
    zs.next_out = reinterpret_cast<Bytef*>(out);
    zs.avail_out = static_cast<uInt>(std::min<std::size_t>(n, 1u << 30));
    const int rc = inflate(&zs, Z_NO_FLUSH);
    in_begin_ = in_end_ - zs.avail_in;
    const std::size_t produced = std::min<std::size_t>(n, 1u << 30) - zs.avail_out;
    if (rc == Z_STREAM_END) {
      in_member_ = false;
      if (produced > 0) return produced;
      continue;
    }
    if (rc == Z_OK || (rc == Z_BUF_ERROR && !file_end_)) {
      if (produced > 0) return produced;
      continue;
    }
    if (rc == Z_BUF_ERROR) {  // no progress possible: the input ended inside a member
      if (produced > 0) return produced;
      throw std::runtime_error("unexpected end of file: the compressed data ends early (a truncated file)");
    }
    throw std::runtime_error(std::string("corrupt compressed data (") + (zs.msg != nullptr ? zs.msg : "zlib error") + ")");
  }
}

std::string CompressedInput::problemOf(const std::string& path) {
  try {
    CompressedInput in(path);
    if (!in.gzip()) return {};
    std::vector<char> buffer(kChunk);
    while (in.read(buffer.data(), buffer.size()) > 0) {
    }
    return {};
  } catch (const std::exception& e) {
    return e.what();
  }
}

}  // namespace lidarseg::logs
