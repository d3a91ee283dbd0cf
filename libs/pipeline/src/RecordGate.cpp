#include "lidarseg/pipeline/RecordGate.h"

#include <algorithm>
#include <optional>
#include <ostream>

#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/pipeline/Progress.h"

namespace lidarseg::pipeline {

namespace {
// The first 100 messages of a kind are kept; the counts go on.
constexpr std::size_t kKeptMessages = 100;
// A log with no usable scan names this many of the records it skipped.
constexpr std::size_t kNamedSkips = 3;

// A log with no usable scan, and why: the first lines or scans the reader skipped, with
// their place.
std::runtime_error noUsableScan(const mrpt_adapter::LaserLogReader& reader, const std::string& sensor) {
  const auto& issues = reader.issues();
  std::string why;
  for (std::size_t k = 0; k < std::min(issues.size(), kNamedSkips); ++k) why += "; " + issues[k];
  if (issues.size() > kNamedSkips) why += "; ... (" + std::to_string(issues.size()) + " skipped in all)";
  return std::runtime_error("'" + reader.path() + "' holds no usable laser scan" +
                            (sensor.empty() ? std::string() : " with sensor '" + sensor + "'") + why);
}
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

std::string readRecords(mrpt_adapter::LaserLogReader& reader, const RecordCounts& counts, const ReadSettings& settings,
                        const std::function<void(const mrpt_adapter::LaserRecord&)>& use,
                        const std::function<void(const mrpt_adapter::LaserRecord&)>& companions) {
  const auto full = [&] { return settings.max_scans > 0 && counts.frames >= settings.max_scans; };
  Progress progress(settings.tool, settings.progress, settings.max_scans);
  std::string log_error;
  while (companions || !full()) {
    std::optional<mrpt_adapter::LaserRecord> record;
    try {
      record = reader.next();
    } catch (const std::runtime_error& e) {
      if (!settings.allow_truncated || counts.frames == 0) throw;
      log_error = e.what();  // the records before it stand
      break;
    }
    if (!record) break;
    if (companions) companions(*record);
    if (full()) break;
    use(*record);
    progress.update(counts.frames, reader.fractionRead());
  }
  progress.done(counts.frames);
  if (counts.frames == 0) throw noUsableScan(reader, settings.sensor);
  return log_error;
}

void addReaderCounts(const mrpt_adapter::LaserLogReader& reader, RecordCounts& counts) {
  for (const auto& s : reader.issues()) {
    if (counts.skipped.size() < kKeptMessages) counts.skipped.push_back(s);
  }
  counts.skipped_count += reader.skipped();
  for (const auto& s : reader.unknownTypes()) counts.warnings.push_back(s);
  for (const auto& s : reader.warnings()) counts.warnings.push_back(s);
  counts.warning_kinds.merge(reader.warningTally());
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

}  // namespace lidarseg::pipeline
