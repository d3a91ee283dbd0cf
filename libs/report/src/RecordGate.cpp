#include "lidarseg/report/RecordGate.h"

#include <algorithm>
#include <optional>
#include <ostream>


namespace lidarseg::report {

namespace {
}  // namespace

RecordGate::RecordGate(const StampPolicyParams& params) : stamps_(params) {}

void RecordGate::warn(const std::string& message) {
  if (counts_.warnings.size() < kKeptMessages) counts_.warnings.push_back(message);
  counts_.warning_kinds.add(message);
}

std::string RecordGate::skip(const ScanRecord& record, const std::string& why) {
  ++counts_.skipped_count;
  std::string message = record.where + " (scan " + std::to_string(record.index) + "): " + why;
  if (counts_.skipped.size() < kKeptMessages) counts_.skipped.push_back(message);
  return message;
}

void RecordGate::accept(const ScanRecord& record, const StampStep& time) {
  if (time.non_increasing) ++counts_.non_increasing_stamps;
  if (time.clock_jump) {
    ++counts_.clock_jumps;
    warn(record.where + ": " + kClockJumpWarning + std::to_string(-time.log_step_s) +
         " s; the motion prior restarts from rest");
  } else if (time.gap) {
    ++counts_.time_gaps;
    warn(record.where + ": " + kTimeGapWarning + std::to_string(time.log_step_s) +
         " s; the motion prior restarts from rest");
  }
  stamps_.accept(time);
  ++counts_.frames;
}

void printWarningKinds(const WarningTally& warnings, const std::string& tool_name, std::ostream& err) {
  // One line per kind: how many in full, and the first in full (its place in the log).
  for (const WarningTally::Kind& k : warnings.kinds()) {
    err << tool_name << ": warning: " << k.count << " x, the first: " << (k.first.empty() ? k.kind : k.first) << "\n";
  }
}

void printRecordWarnings(const WarningTally& warnings, const std::string& tool_name, std::ostream& err) {
  printWarningKinds(warnings, tool_name, err);
}

std::string recordCountsLine(std::size_t skipped_count, const StampCounts& stamps) {
  return "skipped: " + std::to_string(skipped_count) + ", non-increasing stamps: " +
         std::to_string(stamps.non_increasing_stamps) + ", time gaps: " + std::to_string(stamps.time_gaps) +
         ", clock jumps: " + std::to_string(stamps.clock_jumps);
}

}  // namespace lidarseg::report
