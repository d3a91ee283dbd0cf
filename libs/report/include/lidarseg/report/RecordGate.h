#pragma once
/// @file
/// lidarseg::report: the gate every record of a log passes in every tool, after its reader
/// (pipeline::readRecords) and before the tool's own work: its stamp repaired (StampPolicy),
/// and used or skipped (a scan the tool's step refuses with std::invalid_argument), with the
/// counts and warnings every report gives alike. lidarseg-odometry (through OdometryRun),
/// lidarseg-features and lidarseg-segment all pass their records through it, so one log
/// gives the same records, skipped and counted with the same messages, everywhere.

#include <cstddef>
#include <functional>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "lidarseg/core/ScanRecord.h"
#include "lidarseg/core/StampPolicy.h"
#include "lidarseg/core/WarningTally.h"

namespace lidarseg::report {

/// The text of the frequent warnings' kinds, after their place in the log: counted in full
/// by RecordCounts (the list keeps the first 100).
inline constexpr const char* kTimeGapWarning = "time gap of ";
inline constexpr const char* kClockJumpWarning = "the clock jumps back by ";

/// Messages of a kind kept in RecordCounts' lists (the first 100); the counts go on.
inline constexpr std::size_t kKeptMessages = 100;

/// What a run made of its log's records: the counts every tool reports alike.
/// (The stamp counts: non-increasing stamps, time gaps, clock jumps.)
struct RecordCounts : StampCounts {
  /// Records used (scans processed).
  std::size_t frames = 0;
  /// Scans or lines skipped, with where and why (the first 100), and the count.
  std::vector<std::string> skipped;
  std::size_t skipped_count = 0;
  /// What was read or repaired but is worth a word, with its place in the log (the first 100).
  std::vector<std::string> warnings;
  /// Every warning of the run and of its reader, counted per kind in full (at most
  /// WarningTally::kMaxKinds kinds, the rest as "(other kinds)"): `warnings` lists the first
  /// 100 only.
  WarningTally warning_kinds;
};

/// The stamp policy and the counts of one run, record after record (in the log's order).
/// O(1) per record.
class RecordGate {
 public:
  /// @throws std::invalid_argument for invalid stamp parameters (naming the key).
  explicit RecordGate(const StampPolicyParams& params = {});

  /// What the record's stamp becomes; nothing changes until accept().
  StampStep time(const ScanRecord& record) const { return stamps_.next(record.stamp_s); }
  /// The record could not be used: counted, and its message "WHERE (scan N): why" kept
  /// (the first 100) and returned. The clock stays where it was.
  std::string skip(const ScanRecord& record, const std::string& why);
  /// The record was used at `time`: its stamp counted (repeated or backwards, a gap, a
  /// clock jump, each jump or gap warned about with its place) and the clock moved on.
  void accept(const ScanRecord& record, const StampStep& time);
  /// The record through `use` at its stamp step: a std::invalid_argument from `use` skips
  /// it (skip()), otherwise it is accepted. Returns whether it was used.
  template <class Use>
  bool pass(const ScanRecord& record, Use&& use) {
    const StampStep step = time(record);
    try {
      use(step);
    } catch (const std::invalid_argument& e) {
      skip(record, e.what());
      return false;
    }
    accept(record, step);
    return true;
  }
  /// A warning of the run (the first 100 kept).
  void warn(const std::string& message);
  const StampPolicy& stamps() const { return stamps_; }
  const RecordCounts& counts() const { return counts_; }

 private:
  StampPolicy stamps_;
  RecordCounts counts_;
};

/// Warnings for stderr, one line per kind, "TOOL: warning: N x, the first: WHERE: what"
/// ("449 x, the first: FILE:1130: time gap of 1.6 s; ..."), N counted in full
/// (WarningTally::kindOf() says what a kind is); at most WarningTally::kMaxKinds + 1 lines.
void printWarningKinds(const WarningTally& warnings, const std::string& tool, std::ostream& err);

/// A run's record warnings (the reader's and the stamp policy's), as every tool reading a
/// log prints them on stderr (printWarningKinds()).
void printRecordWarnings(const WarningTally& warnings, const std::string& tool, std::ostream& err);

/// "skipped: N, non-increasing stamps: N, time gaps: N, clock jumps: N": the counts every
/// tool reading a log prints in its summary.
std::string recordCountsLine(std::size_t skipped_count, const StampCounts& stamps);

}  // namespace lidarseg::report
