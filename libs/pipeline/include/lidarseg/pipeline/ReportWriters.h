#pragma once
/// @file
/// lidarseg::pipeline: the run report's text outputs, shared by every tool that
/// runs an OdometryRun (summary.json through nlohmann-json, timing.csv, results.md, TUM).

#include <string>

#include "lidarseg/pipeline/RunReport.h"

namespace lidarseg::pipeline {

/// A trajectory as a TUM file with a comment header.
std::string tumText(const eval::StampedTrajectory& trajectory, const std::string& header);
/// Per scan: stamps, stage times, statuses, the prior; one column per baseline's time.
std::string timingCsv(const OdometryReport& report);
/// summary.json: counts, per method time summaries, statuses, errors; non-finite numbers
/// are written as null.
std::string summaryJson(const OdometryReport& report);
/// results.md: the paper's Table I columns plus final error and ATE, then the counts.
std::string markdownTable(const OdometryReport& report);

}  // namespace lidarseg::pipeline
