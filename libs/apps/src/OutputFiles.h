#pragma once
// Private to lidarseg::apps: writing outputs without ever leaving a partial file.

#include <string>
#include <vector>

namespace lidarseg::apps {

/// Writes `content` to `path` through a temporary file and a rename, so that a failure
/// never leaves a partial file behind.
/// @throws std::runtime_error naming the file.
void writeFileAtomically(const std::string& path, const std::string& content);

/// A set of outputs prepared in memory (or under temporary names) and put in place
/// together by commit(); destroyed without commit(), it removes its temporary files.
class OutputSet {
 public:
  /// Adds a text output.
  void add(const std::string& path, std::string content);
  /// Registers a file already written at `path + ".tmp"` by someone else.
  void addWritten(const std::string& path);
  /// Renames every temporary file to its final name.
  /// @throws std::runtime_error naming the file that could not be written.
  void commit();
  ~OutputSet();

 private:
  std::vector<std::string> pending_;  // final paths, each written at path + ".tmp"
  bool committed_ = false;
};

}  // namespace lidarseg::apps
