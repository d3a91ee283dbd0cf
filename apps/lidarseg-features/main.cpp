// lidarseg-features: doors and corners in every scan of a laser log (paper §III.B).
#include <iostream>

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include "lidarseg/apps/CommandLine.h"
#include "lidarseg/apps/FeaturesApp.h"
#include "lidarseg/report/OutputFiles.h"

int main(int argc, char** argv) {
  try {
    TCLAP::CmdLine cmd("Doors and corners from the low-level segments of every scan of a laser log", ' ', "0.1.0");
    TCLAP::UnlabeledValueArg<std::string> input("input", "laser log: MRPT .rawlog or CARMEN", true, "", "LOG", cmd);
    TCLAP::ValueArg<std::string> config("c", "config", "INI/YAML file with [segmentation] and [features]", false, "",
                                        "FILE", cmd);
    TCLAP::ValueArg<std::string> label("l", "sensor-label", "laser to use (default: first)", false, "", "LABEL", cmd);
    TCLAP::ValueArg<std::size_t> max_scans("n", "max-scans", "stop after N scans (0: all)", false, 0, "N", cmd);
    TCLAP::ValueArg<std::string> out("o", "out",
                                     "output folder: features.csv (t,type,x,y,theta,width,confidence,...), "
                                     "features.md, features.json",
                                     false, "", "DIR", cmd);
    TCLAP::ValueArg<std::string> truth("", "gt", "ground truth: PREFIX.features.csv of lidarseg-simulate", false, "",
                                       "FILE", cmd);
    TCLAP::SwitchArg quiet("q", "quiet", "no progress on stderr", cmd);
    TCLAP::ValueArg<std::string> matches("", "matches-out",
                                         "with --gt: every true feature and detection with its match (CSV)", false,
                                         "", "FILE", cmd);
    TCLAP::ValueArg<double> gate("", "gate", "match gate against the truth (m)", false, 0.2, "M", cmd);
    TCLAP::ValueArg<std::string> report("r", "report", "deprecated (use -o): folder for features.md and features.json",
                                        false, "", "DIR", cmd);
    TCLAP::ValueArg<std::size_t> figure_scan("", "figure-scan", "scan to draw (with --figure)", false, 0, "N", cmd);
    TCLAP::ValueArg<std::string> figure("", "figure", "PNG of that scan: raw points, segments, doors, corners", false,
                                        "", "FILE.png", cmd);
    TCLAP::ValueArg<std::string> rois("", "rois-out",
                                      "regions of interest of every camera image (CSV image,scan,t,file,feature,type,"
                                      "u_min,v_min,u_max,v_max,clipped); camera from [camera] or the image's own",
                                      false, "", "FILE.csv", cmd);
    TCLAP::ValueArg<std::string> images("", "images-out", "camera images with the ROI boxes drawn (paper Fig. 7)",
                                        false, "", "DIR", cmd);
    if (const auto status = lidarseg::apps::parseCommandLine(cmd, argc, argv, "lidarseg-features", {{"--truth", "--gt"}})) return *status;

    lidarseg::apps::FeaturesOptions options;
    options.input = input.getValue();
    options.config_path = config.getValue();
    options.sensor_label = label.getValue();
    options.max_scans = max_scans.getValue();
    const auto target = lidarseg::apps::outputTarget(out.getValue(), ".csv", "lidarseg-features");
    options.out_csv = target.folder.empty() ? target.legacy_file : target.folder + "/features.csv";
    // Both name the report's folder: the -o folder silently went without it (issue 16).
    // The same folder twice (`-o X -r X/`) names one output: accepted.
    if (!target.folder.empty() && report.isSet() && !lidarseg::report::samePath(target.folder, report.getValue())) {
      throw lidarseg::apps::UsageError("-o/--out DIR and -r/--report (its old form) both name the folder of features.md; give one");
    }
    options.report_dir = report.getValue().empty() ? target.folder : report.getValue();
    options.truth_path = truth.getValue();
    options.matches_out = matches.getValue();
    options.gate_m = gate.getValue();
    options.gate_given = gate.isSet();
    options.progress = !quiet.getValue();
    if (!figure.getValue().empty()) {
      options.figure_scan = figure_scan.getValue();
      options.figure_path = figure.getValue();
    }
    options.rois_out = rois.getValue();
    options.images_out = images.getValue();
    lidarseg::apps::FeaturesApp app(options);
    const lidarseg::apps::FeaturesReport result = app.run();
    lidarseg::apps::FeaturesApp::print(result, std::cout);
    std::cout.flush();
    lidarseg::apps::FeaturesApp::printWarnings(result, std::cerr);
    return lidarseg::apps::exitAfterStdout("lidarseg-features", 0);
  } catch (const std::exception& e) {
    return lidarseg::apps::errorExit("lidarseg-features", e);
  }
}
