#include "lidarseg/pipeline/ReadRecords.h"

#include <algorithm>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/report/Progress.h"

namespace lidarseg::pipeline {

namespace {
// A log with no usable scan names this many of the records it skipped.
constexpr std::size_t kNamedSkips = 3;

// A log with no usable scan, and why: the first lines or scans the reader skipped, with
// their place.
std::runtime_error noUsableScan(const mrpt_adapter::LaserLogReader& reader, const std::string& sensor) {
  const auto& issues = reader.issues();
  std::string why;
  for (std::size_t k = 0; k < std::min(issues.size(), kNamedSkips); ++k) why += "; " + issues[k];
  if (issues.size() > kNamedSkips) why += "; ... (" + std::to_string(issues.size()) + " skipped in all)";
  if (const std::string unread = reader.unreadScans(); !unread.empty()) why += "; " + unread;
  // A pipe or device is read as CARMEN text (it cannot be sniffed and read again).
  std::error_code ec;
  if (reader.format() == mrpt_adapter::LogFormat::kCarmen && std::filesystem::exists(reader.path(), ec) &&
      !std::filesystem::is_regular_file(reader.path(), ec)) {
    why += "; read as a CARMEN text log, as every pipe or device is (a rawlog is read from a file)";
  }
  return std::runtime_error("'" + reader.path() + "' holds no usable laser scan" +
                            (sensor.empty() ? std::string() : " with sensor '" + sensor + "'") + why);
}
}  // namespace

std::string readRecords(mrpt_adapter::LaserLogReader& reader, const report::RecordCounts& counts, const ReadSettings& settings,
                        const std::function<void(const mrpt_adapter::LaserRecord&)>& use,
                        const std::function<void(const mrpt_adapter::LaserRecord&)>& companions) {
  const auto full = [&] { return settings.max_scans > 0 && counts.frames >= settings.max_scans; };
  report::Progress progress(settings.tool, settings.progress, settings.max_scans);
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

void addReaderCounts(const mrpt_adapter::LaserLogReader& reader, report::RecordCounts& counts) {
  for (const auto& s : reader.issues()) {
    if (counts.skipped.size() < report::kKeptMessages) counts.skipped.push_back(s);
  }
  counts.skipped_count += reader.skipped();
  for (const auto& s : reader.unknownTypes()) counts.warnings.push_back(s);
  for (const auto& s : reader.warnings()) counts.warnings.push_back(s);
  counts.warning_kinds.merge(reader.warningTally());
}

}  // namespace lidarseg::pipeline
