#pragma once
/// @file LineReader.h
/// Reads a text file line by line, gzip-compressed or not.

#include <cstddef>
#include <string>

namespace lidarseg::logs {

/// Line-by-line reader of a plain or gzip-compressed text file (detected from its first
/// bytes, not its name). Lines of any length; a final line without '\n' is returned too.
class LineReader {
 public:
  /// @throws std::runtime_error naming the file when it cannot be opened.
  explicit LineReader(const std::string& path);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  /// Reads the next line (without its end-of-line characters) into `line`.
  /// @return false at the end of the file.
  /// @throws std::runtime_error naming the file and line for a corrupt or truncated gzip
  /// stream or a read error.
  bool next(std::string& line);

  /// 1-based number of the last line returned.
  std::size_t lineNumber() const { return line_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  void* file_ = nullptr;  // gzFile
  std::size_t line_ = 0;
};

}  // namespace lidarseg::logs
