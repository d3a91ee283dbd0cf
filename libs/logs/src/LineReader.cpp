#include "lidarseg/logs/LineReader.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <zlib.h>

namespace lidarseg::logs {

LineReader::LineReader(const std::string& path) : path_(path) {
  errno = 0;
  gzFile f = gzopen(path.c_str(), "rb");
  if (f == nullptr) {
    // The system's reason (no such file, permission denied); zlib's own failures set none.
    const int err = errno;
    throw std::runtime_error("cannot open '" + path + "'" + (err != 0 ? ": " + std::string(std::strerror(err)) : std::string()));
  }
  file_ = f;
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  file_bytes_ = ec ? 0.0 : static_cast<double>(size);
}

double LineReader::fractionRead() const {
  if (file_bytes_ <= 0) return 0.0;
  const z_off_t at = gzoffset(static_cast<gzFile>(file_));
  return at < 0 ? 0.0 : std::clamp(static_cast<double>(at) / file_bytes_, 0.0, 1.0);
}

LineReader::~LineReader() {
  if (file_ != nullptr) gzclose(static_cast<gzFile>(file_));
}

bool LineReader::fill() {
  if (eof_) return false;
  if (begin_ > 0) {
    buffer_.erase(0, begin_);
    begin_ = 0;
  }
  char chunk[1 << 16];
  const int n = gzread(static_cast<gzFile>(file_), chunk, sizeof chunk);
  int code = Z_OK;
  const char* message = gzerror(static_cast<gzFile>(file_), &code);
  const bool failed = n < 0 || (code != Z_OK && code != Z_STREAM_END);
  if (failed && n > 0) {
    // The bytes before the damage are lines too: return them, fail at the next read.
    buffer_.append(chunk, static_cast<std::size_t>(n));
    return true;
  }
  if (failed) {
    throw std::runtime_error(path_ + ":" + std::to_string(line_ + 1) + ": corrupt or truncated compressed data (" +
                             (message ? message : "zlib error") + ")");
  }
  if (n == 0) {
    eof_ = true;
    return false;
  }
  buffer_.append(chunk, static_cast<std::size_t>(n));
  return true;
}

bool LineReader::next(std::string& line) {
  std::size_t scanned = begin_;
  while (true) {
    const std::size_t eol = buffer_.find('\n', scanned);
    if (eol != std::string::npos) {
      line.assign(buffer_, begin_, eol - begin_);
      begin_ = eol + 1;
      break;
    }
    if (buffer_.size() - begin_ > kMaxLineBytes) {
      throw std::runtime_error(path_ + ":" + std::to_string(line_ + 1) + ": a line longer than " +
                               std::to_string(kMaxLineBytes >> 20) + " MiB (not a text log?)");
    }
    const std::size_t kept = buffer_.size() - begin_;
    if (!fill()) {
      if (kept == 0) return false;
      line.assign(buffer_, begin_, std::string::npos);  // a last line without '\n'
      begin_ = buffer_.size();
      break;
    }
    scanned = kept;  // fill() moved the unreturned bytes to the front
  }
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.pop_back();
  ++line_;
  // A UTF-8 byte-order mark (an editor's) before the first line is no part of its first word.
  if (line_ == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
  return true;
}

}  // namespace lidarseg::logs
