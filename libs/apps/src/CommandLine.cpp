#include "lidarseg/apps/CommandLine.h"

#include <iostream>

namespace lidarseg::apps {

namespace {

// TCLAP's standard output, except that a failure is remembered and reported in the
// tools' one-line format instead of exiting.
class RecordingOutput : public TCLAP::StdOutput {
 public:
  explicit RecordingOutput(std::string tool) : tool_(std::move(tool)) {}
  void failure(TCLAP::CmdLineInterface& cmd, TCLAP::ArgException& e) override {
    failed_ = true;
    (void)cmd;
    const std::string arg = e.argId();
    const bool named = arg.find_first_not_of(' ') != std::string::npos;
    std::cerr << tool_ << ": usage error: " << (named ? arg + ": " : std::string()) << e.error() << " (see " << tool_
              << " --help)\n";
  }
  bool failed() const { return failed_; }

 private:
  std::string tool_;
  bool failed_ = false;
};

}  // namespace

std::optional<int> parseCommandLine(TCLAP::CmdLine& cmd, int argc, char** argv, const std::string& tool) {
  RecordingOutput output(tool);
  // setOutput() makes TCLAP forget its own default output, which it would otherwise delete.
  delete cmd.getOutput();
  cmd.setOutput(&output);
  const bool run = cmd.parse(argc, argv);
  cmd.setOutput(nullptr);  // nothing may print through the local output any more
  if (run) return std::nullopt;
  return output.failed() ? kUsageError : 0;
}

}  // namespace lidarseg::apps
