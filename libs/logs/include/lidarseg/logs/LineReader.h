#pragma once
/// @file LineReader.h
/// Reads a text file line by line, gzip-compressed or not.

#include <cstddef>
#include <memory>
#include <string>

#include "lidarseg/logs/CompressedInput.h"

namespace lidarseg::logs {

/// Line-by-line reader of a plain or gzip-compressed text file (detected from its first
/// bytes, not its name). A final line without '\n' is returned too; a NUL byte is kept in
/// its line (never ends it); a line longer than kMaxLineBytes is an error.
class LineReader {
 public:
  /// The longest line accepted (bytes): a CARMEN laser line of 100,000 beams is under 2 MiB.
  static constexpr std::size_t kMaxLineBytes = std::size_t{16} << 20;

  /// @throws std::runtime_error naming the file when it cannot be opened.
  explicit LineReader(const std::string& path);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  /// Reads the next line (without its end-of-line characters) into `line`.
  /// @return false at the end of the file.
  /// @throws std::runtime_error naming the file and line for a corrupt or truncated gzip
  /// stream (any member of it, or bytes after its last member: CompressedInput), a read
  /// error or a line longer than kMaxLineBytes.
  bool next(std::string& line);

  /// Share of the file's bytes (compressed bytes for a gzip file) read so far, 0 to 1: for
  /// a progress's time left. Read ahead by up to 64 KiB.
  double fractionRead() const;

  /// 1-based number of the last line returned.
  std::size_t lineNumber() const { return line_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::unique_ptr<CompressedInput> input_;
  std::size_t line_ = 0;
  double file_bytes_ = 0;   // the file's size on disk
  std::string buffer_;      // bytes read but not yet returned
  std::size_t begin_ = 0;   // first unreturned byte of buffer_
  bool eof_ = false;
  bool fill();              // reads more into buffer_; false at the end
};

}  // namespace lidarseg::logs
