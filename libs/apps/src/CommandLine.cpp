#include "lidarseg/apps/CommandLine.h"

#include <iostream>

#include "OutputFiles.h"

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

bool g_verbose = false;

}  // namespace

std::string describeError(const std::exception& e) {
  const std::string what = e.what();
  if (g_verbose) return what;
  std::string message = what;
  const auto m = what.rfind("Message:");
  if (m != std::string::npos) message = what.substr(m + 8);
  const auto first = message.find_first_not_of(" \t\n");
  message = first == std::string::npos ? std::string() : message.substr(first);
  message = message.substr(0, message.find('\n'));
  if (message.empty()) message = what.substr(0, what.find('\n'));
  return message;
}

std::optional<int> parseCommandLine(TCLAP::CmdLine& cmd, int argc, char** argv, const std::string& tool) {
  installCleanupOnSignals();  // every tool: an interrupted run leaves no temporary file
  // One switch object per process: TCLAP keeps a pointer to it.
  static TCLAP::SwitchArg verbose("", "verbose", "on an error, the whole message (MRPT's backtrace included)");
  cmd.add(verbose);
  RecordingOutput output(tool);
  // setOutput() makes TCLAP forget its own default output, which it would otherwise delete.
  delete cmd.getOutput();
  cmd.setOutput(&output);
  const bool run = cmd.parse(argc, argv);
  cmd.setOutput(nullptr);  // nothing may print through the local output any more
  g_verbose = verbose.getValue();
  if (run) return std::nullopt;
  return output.failed() ? kUsageError : 0;
}

}  // namespace lidarseg::apps
