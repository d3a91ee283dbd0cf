#include "lidarseg/apps/CommandLine.h"

#include <iostream>

#include "lidarseg/mrpt/ExceptionMessage.h"
#include "lidarseg/report/OutputFiles.h"

namespace lidarseg::apps {

using report::installCleanupOnSignals;

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
  return g_verbose ? std::string(e.what()) : mrpt_adapter::exceptionMessage(e.what());
}

namespace {

// argv with the renamed flags' old spellings replaced (each noted on stderr).
std::vector<std::string> withNewNames(int argc, char** argv, const std::vector<RenamedFlag>& renamed,
                                      const std::string& tool) {
  std::vector<std::string> args(argv, argv + argc);
  bool flags = true;
  for (std::size_t i = 1; i < args.size() && flags; ++i) {
    std::string& a = args[i];
    if (a == "--") {
      flags = false;
      continue;
    }
    for (const RenamedFlag& r : renamed) {
      const bool exact = a == r.old_name;
      const bool with_value = r.old_name.rfind("--", 0) == 0 && a.rfind(r.old_name + "=", 0) == 0;
      if (!exact && !with_value) continue;
      std::cerr << tool << ": note: " << r.old_name << " is now " << r.new_name
                << " (docs/cli.md); the old spelling goes in a later release\n";
      a = r.new_name + a.substr(r.old_name.size());
      break;
    }
  }
  return args;
}

// Whether `a` takes an unsigned number.
bool isUnsignedArg(TCLAP::Arg* a) {
  return dynamic_cast<TCLAP::ValueArg<unsigned long>*>(a) != nullptr ||
         dynamic_cast<TCLAP::ValueArg<unsigned long long>*>(a) != nullptr ||
         dynamic_cast<TCLAP::ValueArg<unsigned int>*>(a) != nullptr ||
         dynamic_cast<TCLAP::ValueArg<unsigned short>*>(a) != nullptr;
}

bool isWholeNumber(const std::string& v) {
  return !v.empty() && v.find_first_not_of("0123456789") == std::string::npos;
}

// The first unsigned option of `cmd` given a value that is not a whole number of digits
// (TCLAP reads "-1" as 2^64 - 1 and "" as 0), as a message naming it; nothing when none.
std::optional<std::string> badUnsignedValue(TCLAP::CmdLine& cmd, const std::vector<std::string>& args) {
  for (TCLAP::Arg* a : cmd.getArgList()) {
    if (!isUnsignedArg(a)) continue;
    const std::string shortName = a->getFlag().empty() ? std::string() : "-" + a->getFlag();
    const std::string longName = "--" + a->getName();
    const std::string both = shortName.empty() ? longName : shortName + "/" + longName;
    for (std::size_t i = 1; i < args.size(); ++i) {
      const std::string& t = args[i];
      if (t == "--") break;
      const auto named = [&](const std::string& f) { return f == longName || (!shortName.empty() && f == shortName); };
      std::optional<std::string> value;
      // TCLAP also splits one argument at its first blank after the second character (the
      // tools' delimiter): "-n -1" in one argument is -n given "-1".
      const std::size_t blank = t.find(' ');
      if (blank != std::string::npos && blank > 1 && named(t.substr(0, blank))) {
        value = t.substr(blank + 1);
      } else if (named(t) && i + 1 < args.size()) {
        value = args[i + 1];
      } else if (t.rfind(longName + "=", 0) == 0) {
        value = t.substr(longName.size() + 1);
      }
      if (value && !isWholeNumber(*value)) {
        return both + ": '" + *value + "' is not a whole number (0, 1, 2, ...)";
      }
    }
  }
  return std::nullopt;
}

}  // namespace

int errorExit(const std::string& tool, const std::exception& e) {
  if (dynamic_cast<const UsageError*>(&e) != nullptr) {
    std::cerr << tool << ": usage error: " << describeError(e) << " (see " << tool << " --help)\n";
    return kUsageError;
  }
  std::cerr << tool << ": error: " << describeError(e) << "\n";
  return 1;
}

int exitAfterStdout(const std::string& tool, int status) {
  std::cout.flush();
  if (std::cout) return status;
  std::cerr << tool << ": error: cannot write the report to standard output (a full disk or a closed pipe)\n";
  return 1;
}

OutputTarget outputTarget(const std::string& value, const std::string& legacy_suffix, const std::string& tool) {
  OutputTarget t;
  const bool legacy = value.size() > legacy_suffix.size() &&
                      value.compare(value.size() - legacy_suffix.size(), legacy_suffix.size(), legacy_suffix) == 0;
  if (legacy) {
    std::cerr << tool << ": note: -o " << value << ": -o names an output folder now (docs/cli.md); a " << legacy_suffix
              << " file is still written there for one release\n";
    t.legacy_file = value;
  } else {
    t.folder = value;
  }
  return t;
}

std::optional<int> parseCommandLine(TCLAP::CmdLine& cmd, int argc, char** argv, const std::string& tool,
                                    const std::vector<RenamedFlag>& renamed) {
  installCleanupOnSignals();  // every tool: an interrupted run leaves no temporary file
  // One switch object per process: TCLAP keeps a pointer to it.
  static TCLAP::SwitchArg verbose("v", "verbose", "on an error, the whole message (MRPT's backtrace included)");
  cmd.add(verbose);
  RecordingOutput output(tool);
  // setOutput() makes TCLAP forget its own default output, which it would otherwise delete.
  delete cmd.getOutput();
  cmd.setOutput(&output);
  std::vector<std::string> args = withNewNames(argc, argv, renamed, tool);
  std::vector<const char*> pointers;
  for (const std::string& a : args) pointers.push_back(a.c_str());
  const bool run = cmd.parse(static_cast<int>(pointers.size()), pointers.data());
  cmd.setOutput(nullptr);  // nothing may print through the local output any more
  g_verbose = verbose.getValue();
  if (run) {
    // A configuration flag given an empty name (`-c ''`, an unset shell variable) is a
    // usage error, not a run with the defaults (issue 16).
    for (TCLAP::Arg* arg : cmd.getArgList()) {
      auto* value = dynamic_cast<TCLAP::ValueArg<std::string>*>(arg);
      if (value == nullptr || !value->isSet() || !value->getValue().empty()) continue;
      if (value->getName() != "config" && value->getName() != "sim-config") continue;
      const std::string flag = (value->getFlag().empty() ? std::string() : "-" + value->getFlag() + "/") + "--" +
                               value->getName();
      std::cerr << tool << ": usage error: " << flag << ": an empty file name (see " << tool << " --help)\n";
      return kUsageError;
    }
    if (const auto bad = badUnsignedValue(cmd, args)) {
      std::cerr << tool << ": usage error: " << *bad << " (see " << tool << " --help)\n";
      return kUsageError;
    }
    return std::nullopt;
  }
  return output.failed() ? kUsageError : 0;
}

}  // namespace lidarseg::apps
