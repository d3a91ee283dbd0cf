// lidarseg-inspect: a RawLogViewer-style inspector of lidarseg's pipeline, scan by scan.
#include <iostream>

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include "lidarseg/apps/CommandLine.h"
#include "lidarseg/apps/InspectApp.h"
#include "lidarseg/report/OutputFiles.h"

int main(int argc, char** argv) {
  try {
    TCLAP::CmdLine cmd("Inspect what lidarseg sees in each scan of a laser log: segments of every cascade level, the "
                       "match, doors and corners, trajectories, the camera's regions of interest",
                       ' ', "0.1.0");
    TCLAP::UnlabeledValueArg<std::string> input("input", "laser log: MRPT .rawlog or CARMEN", true, "", "LOG", cmd);
    TCLAP::ValueArg<std::string> config("c", "config", "INI/YAML parameters (config/default.ini lists every key)", false,
                                        "", "FILE", cmd);
    TCLAP::ValueArg<std::string> label("l", "sensor-label", "laser to use (default: first)", false, "", "LABEL", cmd);
    TCLAP::MultiArg<std::string> trajectory("", "trajectory", "another trajectory to show (repeatable)", false,
                                            "NAME=FILE.tum", cmd);
    TCLAP::ValueArg<std::string> truth("", "gt", "ground truth TUM file (default: <log>.gt.tum when present)", false,
                                       "", "FILE.tum", cmd);
    TCLAP::ValueArg<std::size_t> frame("f", "frame", "scan to open at / to draw", false, 0, "N", cmd);
    TCLAP::ValueArg<double> time("", "time", "open at the scan nearest this time (s from the first scan)", false, 0,
                                 "S", cmd);
    TCLAP::ValueArg<std::string> layers("", "layers",
                                        "comma list: raw,l0,l1,l2,l3,indices,predicted,matches,features,trajectory,"
                                        "camera,all (default: raw,l1,l3,predicted,matches,features,trajectory,camera)",
                                        false, "", "LIST", cmd);
    TCLAP::ValueArg<int> width("", "width", "picture width (pixels)", false, 1100, "PX", cmd);
    TCLAP::ValueArg<int> height("", "height", "picture height (pixels)", false, 850, "PX", cmd);
    TCLAP::ValueArg<std::string> render("", "draw", "headless: draw --frame to FILE.png or FILE.svg and exit", false, "",
                                        "FILE", cmd);
    TCLAP::ValueArg<std::string> screenshot("", "screenshot", "open the window at --frame, save a screenshot, exit",
                                            false, "", "FILE.png", cmd);
    TCLAP::ValueArg<std::string> out("o", "out", "output folder: a static HTML report of the whole log", false, "", "DIR",
                                     cmd);
    TCLAP::SwitchArg quiet("q", "quiet", "no progress on stderr", cmd);
    TCLAP::ValueArg<std::string> report("", "report", "deprecated (use -o): report folder", false, "", "DIR",
                                        cmd);
    TCLAP::ValueArg<std::size_t> gallery("", "gallery", "frames in the report's gallery", false, 12, "N", cmd);
    TCLAP::ValueArg<std::string> save("", "save", "where the window's 's' key saves the parameters", false,
                                      "lidarseg-inspect.ini", "FILE.ini", cmd);
    TCLAP::ValueArg<std::size_t> render_frame("", "render", "same as --frame, for --draw", false, 0, "N", cmd);
    TCLAP::SwitchArg trace("", "trace", "window: print each shown scan on stdout (for scripts driving it)", cmd);
    if (const auto status = lidarseg::apps::parseCommandLine(cmd, argc, argv, "lidarseg-inspect", {{"--truth", "--gt"}})) return *status;

    // -f, --render and --time each choose the scan: two of them contradict (one was ignored).
    if (static_cast<int>(frame.isSet()) + static_cast<int>(render_frame.isSet()) + static_cast<int>(time.isSet()) > 1) {
      std::cerr << "lidarseg-inspect: usage error: -f/--frame, --render and --time each choose the scan; give one\n";
      return lidarseg::apps::kUsageError;
    }
    lidarseg::apps::InspectOptions o;
    o.input = input.getValue();
    o.config_path = config.getValue();
    o.sensor_label = label.getValue();
    o.references = trajectory.getValue();
    o.truth_path = truth.getValue();
    o.frame = render_frame.isSet() ? render_frame.getValue() : frame.getValue();
    if (time.isSet()) o.time_s = time.getValue();
    o.layers = layers.getValue();
    o.width = width.getValue();
    o.height = height.getValue();
    // -o used to be the picture of --frame: a .png or .svg name keeps that meaning for one release.
    const std::string out_value = out.getValue();
    const bool picture = out_value.size() > 4 && (out_value.compare(out_value.size() - 4, 4, ".png") == 0 ||
                                                  out_value.compare(out_value.size() - 4, 4, ".svg") == 0);
    if (picture) {
      std::cerr << "lidarseg-inspect: note: --out " << out_value
                << " draws the frame as before; that is --draw now (docs/cli.md)\n";
    }
    // Two names for one output: one of them was silently not written (issue 16).
    if (picture && render.isSet()) {
      throw lidarseg::apps::UsageError("-o " + out_value + " (its old form) and --draw both name the picture; give one");
    }
    // The same folder twice (`-o X --report X/`) names one output: accepted.
    if (!picture && out.isSet() && report.isSet() && !lidarseg::report::samePath(out_value, report.getValue())) {
      throw lidarseg::apps::UsageError("-o/--out and --report (its old form) both name the report folder; give one");
    }
    o.render_out = picture ? out_value : render.getValue();
    o.screenshot_out = screenshot.getValue();
    o.report_dir = !picture && !out_value.empty() ? out_value : report.getValue();
    o.progress = !quiet.getValue();
    o.gallery = gallery.getValue();
    o.save_path = save.getValue();
    o.trace = trace.getValue();
    return lidarseg::apps::InspectApp(o).run();
  } catch (const std::exception& e) {
    return lidarseg::apps::errorExit("lidarseg-inspect", e);
  }
}
