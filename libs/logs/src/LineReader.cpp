#include "lidarseg/logs/LineReader.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>


namespace lidarseg::logs {

LineReader::LineReader(const std::string& path) : path_(path), input_(std::make_unique<CompressedInput>(path)) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  file_bytes_ = ec ? 0.0 : static_cast<double>(size);
}

double LineReader::fractionRead() const {
  if (file_bytes_ <= 0) return 0.0;
  return std::clamp(static_cast<double>(input_->fileBytesRead()) / file_bytes_, 0.0, 1.0);
}

LineReader::~LineReader() = default;

bool LineReader::fill() {
  if (eof_) return false;
  if (begin_ > 0) {
    buffer_.erase(0, begin_);
    begin_ = 0;
  }
  char chunk[1 << 16];
  std::size_t n = 0;
  try {
    n = input_->read(chunk, sizeof chunk);
  } catch (const std::runtime_error& e) {
    // Every whole line before the damage has been returned (read() gives the bytes it made
    // before it fails); what is left is the damaged line.
    throw std::runtime_error(path_ + ":" + std::to_string(line_ + 1) + ": corrupt or truncated compressed data (" +
                             e.what() + ")");
  }
  if (n == 0) {
    eof_ = true;
    return false;
  }
  buffer_.append(chunk, n);
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
