// lidarseg-odometry: laser odometry of a rawlog or CARMEN log with lidarseg, compared
// with MRPT's ICP in the same run.
#include <iostream>
#include <optional>
#include <sstream>

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include "lidarseg/apps/CommandLine.h"
#include "lidarseg/apps/OdometryApp.h"
#include "lidarseg/core/NumberText.h"
#include "lidarseg/eval/Csv.h"
#include "lidarseg/report/ReportWriters.h"

namespace {

using lidarseg::apps::OdometryOptions;

// The flags, registered on the command line in the order --help lists them.
struct CommandLine {
  TCLAP::CmdLine cmd{"Segment-based laser odometry (lidarseg) of a log, optionally beside MRPT ICP", ' ', "0.1.0"};
  TCLAP::UnlabeledValueArg<std::string> input{"input", "MRPT .rawlog or CARMEN .clf/.log[.gz]", true, "", "FILE", cmd};
  TCLAP::ValueArg<std::string> config{"c", "config", "INI/YAML with [segmentation] [matcher] [odometry] [icp]",
                                      false, "", "FILE", cmd};
  TCLAP::ValueArg<std::string> sensor{"l", "sensor-label", "rawlog sensor label or CARMEN laser type", false, "",
                                      "LABEL", cmd};
  TCLAP::ValueArg<std::size_t> max_scans{"n", "max-scans", "stop after N scans (0: all)", false, 0, "N", cmd};
  TCLAP::ValueArg<std::string> baseline{"", "baseline", "also run baselines in the same run: 'icp' (MRPT ICP with lidarseg's keyframes), 'icp-s2s' (scan to scan), or 'icp,icp-s2s'", false,
                                        "", "NAME", cmd};
  TCLAP::SwitchArg use_odometry{"", "use-odometry", "prior from the log's wheel odometry (default: constant velocity)", cmd};
  TCLAP::ValueArg<std::string> out{"o", "out", "output folder: *.tum, timing.csv, summary.json, results.md, PNGs",
                                   false, "", "DIR", cmd};
  TCLAP::ValueArg<std::string> gt{"", "gt", "ground truth (TUM); default PREFIX.gt.tum beside PREFIX.rawlog",
                                  false, "", "FILE", cmd};
  TCLAP::SwitchArg allow_truncated{"", "allow-truncated",
                                   "a log ending in a truncated or corrupt entry: process the scans before it, "
                                   "write the outputs, warn and exit with code 3 (default: error, no output)", cmd};
  TCLAP::SwitchArg no_gt{"", "no-gt", "do not look for ground truth beside the input", cmd};
  TCLAP::ValueArg<std::string> relations{"", "relations", "Freiburg relations file to evaluate", false, "",
                                         "FILE", cmd};
  TCLAP::ValueArg<double> rel_tol{"", "relations-tolerance", "time tolerance of relation stamps (s)", false,
                                  0.01, "S", cmd};
  TCLAP::SwitchArg log_reference{"", "log-reference", "evaluate per-scan motion against the log's own poses (CARMEN corrected logs)", cmd};
  TCLAP::ValueArg<std::string> write_rawlog{"", "write-rawlog", "write the input with lidarseg odometry as actions",
                                            false, "", "FILE", cmd};
  TCLAP::SwitchArg write_landmarks{"", "write-landmarks",
                                   "with --write-rawlog: add each scan's doors and corners as range-bearing landmarks", cmd};
  TCLAP::ValueArg<std::string> features_out{"", "features-out", "doors and corners of every scan (CSV, robot frame)",
                                            false, "", "FILE.csv", cmd};
  TCLAP::ValueArg<double> scanner_hz{"", "scanner-hz", "scanner rotation frequency for rolling-shutter correction (Hz)",
                                     false, -1.0, "HZ", cmd};
  TCLAP::ValueArg<std::string> scan_stamp{"", "scan-stamp",
                                          "which beam's instant the log's stamps are, for --scanner-hz: first, middle or last",
                                          false, "", "first|middle|last", cmd};
  TCLAP::ValueArg<double> max_lost{"", "max-lost-ratio",
                                   "share of lost scans above which the run is reported as lost (default 0.01)",
                                   false, 0.01, "SHARE", cmd};
  TCLAP::SwitchArg quiet{"q", "quiet", "no progress on stderr", cmd};
  TCLAP::SwitchArg no_plots{"", "no-plots", "do not draw PNG pictures", cmd};
};

// Sets the baselines --baseline names ("icp", "icp-s2s"); false after printing an unknown one.
bool setBaselines(const std::string& list, OdometryOptions& o) {
  for (const std::string& name : lidarseg::eval::splitCsvLine(list)) {
    if (name == "icp") {
      o.baseline_icp = true;
    } else if (name == "icp-s2s") {
      o.baseline_icp_s2s = true;
    } else {
      throw lidarseg::apps::UsageError("--baseline '" + name +
                                       "' (known: 'icp' keyframed like lidarseg, 'icp-s2s' scan to scan, or both: 'icp,icp-s2s')");
    }
  }
  return true;
}

// The options given by the parsed flags; nothing after printing why they are invalid.
std::optional<OdometryOptions> optionsOf(CommandLine& c) {
  OdometryOptions o;
  o.input = c.input.getValue();
  o.config_path = c.config.getValue();
  o.sensor = c.sensor.getValue();
  o.max_scans = c.max_scans.getValue();
  if (!setBaselines(c.baseline.getValue(), o)) return std::nullopt;
  o.use_odometry = c.use_odometry.getValue();
  o.out_dir = c.out.getValue();
  o.gt_path = c.gt.getValue();
  o.auto_gt = !c.no_gt.getValue();
  o.relations_path = c.relations.getValue();
  o.relations_tolerance_s = c.rel_tol.getValue();
  // Options that contradict each other or act on nothing are usage errors (issue 16).
  if (!o.gt_path.empty() && c.no_gt.getValue()) {
    throw lidarseg::apps::UsageError("--gt " + o.gt_path + " and --no-gt contradict each other (give one)");
  }
  if (c.rel_tol.isSet() && o.relations_path.empty()) {
    throw lidarseg::apps::UsageError("--relations-tolerance applies to the relations of --relations, which is not given");
  }
  o.log_reference = c.log_reference.getValue();
  o.write_rawlog = c.write_rawlog.getValue();
  o.features_out = c.features_out.getValue();
  o.write_landmarks = c.write_landmarks.getValue();
  if (c.scanner_hz.isSet()) o.scanner_rotation_hz = c.scanner_hz.getValue();
  o.scan_stamp = c.scan_stamp.getValue();
  o.max_lost_ratio = c.max_lost.getValue();
  if (!(o.max_lost_ratio >= 0.0 && o.max_lost_ratio <= 1.0)) {
    throw lidarseg::apps::UsageError("--max-lost-ratio must be in [0, 1] (got " + lidarseg::numberText(o.max_lost_ratio) + ")");
  }
  o.progress = !c.quiet.getValue();
  o.plots = !c.no_plots.getValue();
  o.allow_truncated = c.allow_truncated.getValue();
  return o;
}

// Warns on stderr when lidarseg lost track on more than `max_lost_ratio` of the scans.
void warnIfLost(const lidarseg::apps::OdometryReport& report, double max_lost_ratio) {
  if (report.lidarseg.tracking != "lost") return;
  std::cerr << "lidarseg-odometry: warning: lidarseg lost track on " << report.lidarseg.lost
            << " of " << report.frames << " scans (more than " << max_lost_ratio * 100.0
            << " %); see lost_scans in summary.json\n";
}

}  // namespace

int main(int argc, char** argv) {
  try {
    CommandLine command_line;
    if (const auto status = lidarseg::apps::parseCommandLine(command_line.cmd, argc, argv, "lidarseg-odometry", {{"--sensor", "--sensor-label"}})) {
      return *status;
    }
    const std::optional<OdometryOptions> options = optionsOf(command_line);
    if (!options) return 2;
    const auto report = lidarseg::apps::OdometryApp(*options).run();
    lidarseg::report::printRunSummary(report, std::cout);
    lidarseg::report::printRunWarnings(report, "lidarseg-odometry", std::cerr);
    warnIfLost(report, options->max_lost_ratio);
    return lidarseg::apps::exitAfterStdout("lidarseg-odometry", report.log_error.empty() ? 0 : 3);
  } catch (const std::exception& e) {
    return lidarseg::apps::errorExit("lidarseg-odometry", e);
  }
}
