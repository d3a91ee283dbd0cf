// lidarseg-people: HOG people detection on the whole frame and only inside regions of interest.
#include <iostream>

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include "lidarseg/apps/CommandLine.h"
#include "lidarseg/apps/PeopleApp.h"
#include "lidarseg/report/OutputFiles.h"

int main(int argc, char** argv) {
  try {
    TCLAP::CmdLine cmd("OpenCV's HOG people detector on every frame, on the whole frame and only inside regions of "
                       "interest: time per frame, share of the image analysed, people still found",
                       ' ', "0.1.0");
    TCLAP::UnlabeledValueArg<std::string> input("input", "video file, directory of images, or one image", true, "",
                                                "INPUT", cmd);
    TCLAP::ValueArg<std::string> rois("", "rois",
                                      "regions per frame: CSV with u_min,v_min,u_max,v_max and frame|image|file "
                                      "(lidarseg-features --rois-out writes one)",
                                      false, "", "FILE.csv", cmd);
    TCLAP::MultiArg<std::string> roi("", "roi", "a region for every frame (repeatable)", false,
                                     "u_min,v_min,u_max,v_max", cmd);
    TCLAP::ValueArg<std::string> config("c", "config", "INI/YAML file with a [people] section", false, "", "FILE",
                                        cmd);
    TCLAP::ValueArg<std::size_t> max_frames("n", "max-frames", "stop after N analysed frames (0: all)", false, 0, "N",
                                            cmd);
    TCLAP::ValueArg<std::size_t> every("", "every", "analyse every N-th frame", false, 1, "N", cmd);
    TCLAP::ValueArg<int> threads("j", "jobs", "OpenCV worker threads", false, 1, "N", cmd);
    TCLAP::SwitchArg quiet("q", "quiet", "no progress on stderr", cmd);
    TCLAP::ValueArg<std::string> out("o", "out",
                                     "output folder: people.csv (frame,mode,u_min,v_min,u_max,v_max,score), people.md, "
                                     "people.json",
                                     false, "", "DIR", cmd);
    TCLAP::ValueArg<std::string> report("r", "report", "deprecated (use -o): folder for people.md and people.json", false,
                                        "", "DIR", cmd);
    TCLAP::ValueArg<std::string> draw("", "draw", "directory for annotated frames", false, "", "DIR", cmd);
    TCLAP::ValueArg<std::size_t> draw_every("", "draw-every", "draw every N-th analysed frame", false, 50, "N", cmd);
    if (const auto status = lidarseg::apps::parseCommandLine(cmd, argc, argv, "lidarseg-people", {{"--threads", "--jobs"}})) return *status;

    lidarseg::apps::PeopleOptions options;
    options.input = input.getValue();
    options.rois_path = rois.getValue();
    options.rois = roi.getValue();
    options.config_path = config.getValue();
    options.max_frames = max_frames.getValue();
    options.every = every.getValue();
    options.threads = threads.getValue();
    const auto target = lidarseg::apps::outputTarget(out.getValue(), ".csv", "lidarseg-people");
    options.out_csv = target.folder.empty() ? target.legacy_file : target.folder + "/people.csv";
    // Both name the report's folder: the -o folder silently went without it (issue 16).
    // The same folder twice (`-o X -r X/`) names one output: accepted.
    if (!target.folder.empty() && report.isSet() && !lidarseg::report::samePath(target.folder, report.getValue())) {
      throw lidarseg::apps::UsageError("-o/--out DIR and -r/--report (its old form) both name the folder of people.md; give one");
    }
    options.report_dir = report.getValue().empty() ? target.folder : report.getValue();
    options.progress = !quiet.getValue();
    options.draw_dir = draw.getValue();
    options.draw_every = draw_every.getValue();
    lidarseg::apps::PeopleApp app(options);
    const lidarseg::apps::PeopleReport result = app.run();
    lidarseg::apps::PeopleApp::print(result, std::cout);
    lidarseg::apps::PeopleApp::printWarnings(result, std::cerr);
    return lidarseg::apps::exitAfterStdout("lidarseg-people", 0);
  } catch (const std::exception& e) {
    return lidarseg::apps::errorExit("lidarseg-people", e);
  }
}
