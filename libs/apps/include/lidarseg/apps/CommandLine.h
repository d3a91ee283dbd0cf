#pragma once
/// @file CommandLine.h
/// How every lidarseg tool parses its command line (MRPT's TCLAP): a usage error is a
/// message and exit status 2 with nothing run; --help and --version print and exit 0.

#include <exception>
#include <optional>
#include <string>
#include <vector>

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include "lidarseg/report/OutputFiles.h"

namespace lidarseg::apps {

/// A command line that cannot be run as given (thrown by the tools' option checks and by
/// report::OutputSet::claimOutputs); errorExit() makes it exit status 2.
using report::UsageError;

/// Exit status of a usage error (a bad flag or value, a missing argument).
inline constexpr int kUsageError = 2;

/// A flag the one vocabulary of docs/cli.md renamed, still accepted for one release: the old
/// spelling (`--sensor`, `-s`) is read as the new one (`--sensor-label`) with a note on stderr.
struct RenamedFlag {
  std::string old_name;  ///< with its dashes: "--sensor", "-s"
  std::string new_name;  ///< with its dashes: "--sensor-label"
};

/// Installs the SIGINT/SIGTERM cleanup of temporary files, then parses `argv` into `cmd`'s
/// arguments (adding -v/--verbose, which makes describeError() keep the whole message:
/// MRPT's backtraces included). The old spellings in `renamed` are read as their new
/// names (also as `--old=value`), before a `--` that ends the flags.
/// A value of an unsigned option (`-n`, `--every`, `--frame`, ...) that is not a whole
/// number of digits (`-1`, `''`, `1e3`) is a usage error naming the option: TCLAP would read
/// `-1` as 2^64 - 1 and `''` as 0.
/// @return std::nullopt when the tool should run; otherwise the status to exit with:
///         0 after --help or --version (printed on stdout), kUsageError after a usage error
///         (one line "TOOL: usage error: ..." on stderr).
std::optional<int> parseCommandLine(TCLAP::CmdLine& cmd, int argc, char** argv, const std::string& tool,
                                    const std::vector<RenamedFlag>& renamed = {});

/// What `-o/--out VALUE` names for a tool whose output used to be one file (docs/cli.md):
/// an output folder, or, for one release, the file itself when VALUE ends in
/// `legacy_suffix` (".csv"), with a note on stderr.
struct OutputTarget {
  std::string folder;       ///< empty when VALUE is the old file form (or empty)
  std::string legacy_file;  ///< VALUE in the old file form, else empty
};
OutputTarget outputTarget(const std::string& value, const std::string& legacy_suffix, const std::string& tool);

/// What every tool's main() does with an exception that ends it: "TOOL: usage error: ..."
/// and kUsageError for a UsageError, else "TOOL: error: ..." and 1.
int errorExit(const std::string& tool, const std::exception& e);

/// The exit status of a run that printed its report on stdout: `status`, or 1 after an
/// error line on stderr when stdout could not be written (a full disk, a closed pipe: the
/// report lost while the run said success).
int exitAfterStdout(const std::string& tool, int status);

/// Runs `check`, a parser or validator of option `option`'s value, and makes the
/// std::invalid_argument it throws a UsageError naming the option (once: a message that
/// starts with the option's name is kept as it is).
template <class Check>
auto checkedOption(const std::string& option, Check&& check) -> decltype(check()) {
  try {
    return check();
  } catch (const UsageError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    throw UsageError(message.rfind(option, 0) == 0 ? message : option + ": " + message);
  }
}

/// The one-line message of an error for the user: MRPT's exceptions (a banner, a backtrace,
/// then "Message: ...") are reduced to their message, unless --verbose was given.
std::string describeError(const std::exception& e);

}  // namespace lidarseg::apps
