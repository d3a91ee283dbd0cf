#pragma once
/// @file WarningTally.h
/// A run's warnings counted per kind in full, while only the first messages are kept.

#include <cstddef>
#include <string>
#include <unordered_map>
#include <vector>

namespace lidarseg {

/// The warnings of a run (a log read, its stamps repaired, its odometry judged), counted per
/// kind in full whatever their number, in bounded memory: the first kKeptMessages messages,
/// at most kMaxKinds kinds (each with its count and first message) and the warnings of any
/// further kind counted together under kOtherKinds. O(length of the message) per warning.
class WarningTally {
 public:
  /// Messages kept in full (the first ones of the run, all kinds together).
  static constexpr std::size_t kKeptMessages = 100;
  /// Distinct kinds counted by name; a log with more (crafted, or a million distinct line
  /// types) has the rest counted under kOtherKinds.
  static constexpr std::size_t kMaxKinds = 200;
  /// The kind under which the warnings of kinds beyond kMaxKinds are counted.
  static constexpr const char* kOtherKinds = "(other kinds)";

  /// One kind: its name, how many warnings of it, and the first one in full.
  struct Kind {
    std::string kind;
    std::size_t count = 0;
    std::string first;
  };

  /// A message's kind: its text after its place ("FILE:LINE: ", "rawlog 'F', entry N: ": up
  /// to the first ": ") with each run of digits (a number's) written '#', at most 120
  /// characters: "F:7: time gap of 4.9 s; …" is of kind "time gap of #.# s; …".
  static std::string kindOf(const std::string& message);

  /// Counts `message` under its kind and keeps it when fewer than kKeptMessages are kept.
  void add(const std::string& message);
  /// Counts `n` more warnings of `kind` (whose messages were counted elsewhere, e.g. by a
  /// reader that keeps its own first ones); `first` is its first message if known.
  void count(const std::string& kind, std::size_t n, const std::string& first = {});
  /// Adds every kind and kept message of `other` (the messages up to kKeptMessages).
  void merge(const WarningTally& other);

  /// The kept messages, in the order they came.
  const std::vector<std::string>& messages() const { return messages_; }
  /// The kinds in the order they were first met; kOtherKinds last when used.
  std::vector<Kind> kinds() const;
  /// Warnings counted in all (every kind).
  std::size_t total() const { return total_; }
  /// Warnings counted under `kind` (0 when none).
  std::size_t countOf(const std::string& kind) const;

 private:
  Kind& slot(const std::string& kind);
  std::vector<Kind> kinds_;
  std::unordered_map<std::string, std::size_t> index_;  // kind -> position in kinds_
  Kind other_{kOtherKinds, 0, {}};
  std::vector<std::string> messages_;
  std::size_t total_ = 0;
};

}  // namespace lidarseg
