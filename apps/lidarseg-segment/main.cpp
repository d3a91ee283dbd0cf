// lidarseg-segment: segments every scan of a laser log (MRPT rawlog or CARMEN) and prints per-level statistics.
#include <iostream>

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include "lidarseg/apps/CommandLine.h"
#include "lidarseg/apps/SegmentStatsApp.h"

int main(int argc, char** argv) {
  try {
    TCLAP::CmdLine cmd("Wall-Danielsson segmentation and cascade filter statistics of a laser log (MRPT rawlog or CARMEN)",
                       ' ', "0.1.0");
    TCLAP::UnlabeledValueArg<std::string> input("input", "MRPT .rawlog or CARMEN log (.clf/.log, optionally .gz)", true, "", "FILE",
                                                cmd);
    TCLAP::ValueArg<std::string> config("c", "config", "INI or YAML parameter file", false, "",
                                        "FILE", cmd);
    TCLAP::ValueArg<std::string> section("", "section", "section of the parameters", false,
                                         "segmentation", "NAME", cmd);
    TCLAP::ValueArg<std::string> label("l", "sensor-label", "laser to use (default: first)",
                                       false, "", "LABEL", cmd);
    TCLAP::ValueArg<std::size_t> max_scans("n", "max-scans", "stop after N scans (0: all)", false,
                                           0, "N", cmd);
    TCLAP::ValueArg<std::string> csv("", "csv", "deprecated (use -o): write per-scan counts and times to FILE", false,
                                     "", "FILE", cmd);
    TCLAP::ValueArg<std::string> out("o", "out", "output folder: segments.csv (per-scan counts and times)", false, "",
                                     "DIR", cmd);
    TCLAP::SwitchArg quiet("q", "quiet", "no progress on stderr", cmd);
    if (const auto status = lidarseg::apps::parseCommandLine(cmd, argc, argv, "lidarseg-segment")) return *status;
    if (section.isSet() && !config.isSet()) {  // it would be ignored (issue 16)
      std::cerr << "lidarseg-segment: usage error: --section " << section.getValue()
                << ": a section of a parameter file, given without -c/--config (see lidarseg-segment --help)\n";
      return lidarseg::apps::kUsageError;
    }

    if (section.isSet() && section.getValue().find_first_not_of(" \t") == std::string::npos) {
      throw lidarseg::apps::UsageError("--section: an empty name names no section");
    }
    // Both name the per-scan table's place: one was silently not written (issue 16).
    if (out.isSet() && csv.isSet()) {
      throw lidarseg::apps::UsageError("-o/--out and --csv (its old form) both say where segments.csv goes; give one");
    }
    lidarseg::apps::SegmentStatsOptions options;
    options.input = input.getValue();
    options.config_path = config.getValue();
    options.section = section.getValue();
    options.sensor_label = label.getValue();
    options.max_scans = max_scans.getValue();
    options.csv_path = out.getValue().empty() ? csv.getValue() : out.getValue() + "/segments.csv";
    options.progress = !quiet.getValue();
    lidarseg::apps::SegmentStatsApp app(options);
    const lidarseg::apps::SegmentStatsReport result = app.run();
    lidarseg::apps::SegmentStatsApp::print(result, std::cout);
    std::cout.flush();
    lidarseg::apps::SegmentStatsApp::printWarnings(result, std::cerr);
    return lidarseg::apps::exitAfterStdout("lidarseg-segment", 0);
  } catch (const std::exception& e) {
    return lidarseg::apps::errorExit("lidarseg-segment", e);
  }
}
