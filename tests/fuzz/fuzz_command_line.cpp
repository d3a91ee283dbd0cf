/// @file fuzz_command_line.cpp
/// libFuzzer target: any argument list (the input split at NUL bytes, at most 64 arguments)
/// parsed by parseCommandLine(), the one parser of every lidarseg tool, against a command
/// line holding each kind of option the tools declare (a required input, text, unsigned,
/// signed, 64-bit seed and real values, a repeatable value, switches, a renamed flag).
/// The contract (issue 16): the tool runs (std::nullopt) or exits with 0 (--help,
/// --version) or kUsageError, never anything else; no exception escapes; a tool that runs
/// never sees an empty configuration name nor an unsigned value that was not written as a
/// whole number.

#include <cstdint>
#include <string>
#include <vector>

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include "FuzzInput.h"
#include "lidarseg/apps/CommandLine.h"

namespace {

bool wholeNumber(const std::string& v) { return !v.empty() && v.find_first_not_of("0123456789") == std::string::npos; }

// The text an option was given on `args`, found the way TCLAP finds it (the tools' delimiter
// is a blank): "-x V" or "--name V" as two arguments, or as one argument split at its first
// blank after the second character. The last occurrence, if any.
bool lastValueOf(const std::vector<std::string>& args, const std::string& flag, const std::string& name,
                 std::string& value) {
  const auto matches = [&](const std::string& t) { return (!flag.empty() && t == "-" + flag) || t == "--" + name; };
  bool found = false;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& t = args[i];
    if (t == "--") break;
    const std::size_t blank = t.find(' ');
    if (blank != std::string::npos && blank > 1 && matches(t.substr(0, blank))) {
      value = t.substr(blank + 1);
      found = true;
    } else if (matches(t) && i + 1 < args.size()) {
      value = args[i + 1];
      found = true;
    }
  }
  return found;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args{"lidarseg-fuzz"};
  std::string token;
  for (std::size_t i = 0; i < size && args.size() < 65; ++i) {
    if (data[i] == 0) {
      args.push_back(token);
      token.clear();
    } else {
      token.push_back(static_cast<char>(data[i]));
    }
  }
  if (args.size() < 65 && (!token.empty() || size == 0)) args.push_back(token);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());

  TCLAP::CmdLine cmd("fuzzed command line", ' ', "0.1.0");
  TCLAP::UnlabeledValueArg<std::string> input("input", "input log", true, "", "FILE", cmd);
  TCLAP::ValueArg<std::string> config("c", "config", "parameter file", false, "", "FILE", cmd);
  TCLAP::ValueArg<std::string> out("o", "out", "output folder", false, "", "DIR", cmd);
  TCLAP::ValueArg<std::string> label("l", "sensor-label", "laser", false, "", "LABEL", cmd);
  TCLAP::ValueArg<std::size_t> max_scans("n", "max-scans", "scans", false, 0, "N", cmd);
  TCLAP::ValueArg<unsigned int> threads("j", "jobs", "threads", false, 1, "N", cmd);
  TCLAP::ValueArg<std::uint64_t> seed("", "seed", "seed", false, 1, "N", cmd);
  TCLAP::ValueArg<int> offset("", "offset", "a signed count", false, 0, "K", cmd);
  TCLAP::ValueArg<double> hz("", "scanner-hz", "rotation rate", false, 0.0, "HZ", cmd);
  TCLAP::MultiArg<std::string> baseline("", "baseline", "baselines", false, "NAME", cmd);
  TCLAP::SwitchArg quiet("q", "quiet", "quiet", cmd);
  TCLAP::SwitchArg plots("", "no-plots", "no plots", cmd);

  int argc = static_cast<int>(argv.size());
  std::optional<int> status;
  try {
    status = lidarseg::apps::parseCommandLine(cmd, argc, argv.data(), "lidarseg-fuzz",
                                              {{"--sensor", "--sensor-label"}, {"-s", "--sensor-label"}});
  } catch (...) {
    lidarseg::fuzz::require(false, "parseCommandLine threw");
  }
  if (status) {
    lidarseg::fuzz::require(*status == 0 || *status == lidarseg::apps::kUsageError, "an exit status other than 0 or 2");
    return 0;
  }
  // The tool would run: what it reads must be what the user wrote.
  lidarseg::fuzz::require(!(config.isSet() && config.getValue().empty()), "an empty configuration name runs");
  lidarseg::fuzz::require(input.isSet(), "a run without its required input");
  std::string text;
  if (max_scans.isSet() && lastValueOf(args, "n", "max-scans", text)) {
    lidarseg::fuzz::require(wholeNumber(text), "a -n value that is not a whole number runs");
  }
  if (threads.isSet() && lastValueOf(args, "j", "jobs", text)) {
    lidarseg::fuzz::require(wholeNumber(text), "a -j value that is not a whole number runs");
  }
  if (seed.isSet() && lastValueOf(args, "", "seed", text)) {
    lidarseg::fuzz::require(wholeNumber(text), "a --seed value that is not a whole number runs");
  }
  return 0;
}
