#pragma once
/// @file CommandLine.h
/// How every lidarseg tool parses its command line (MRPT's TCLAP): a usage error is a
/// message and exit status 2 with nothing run; --help and --version print and exit 0.

#include <exception>
#include <optional>
#include <string>

#include <mrpt/3rdparty/tclap/CmdLine.h>

namespace lidarseg::apps {

/// Exit status of a usage error (a bad flag or value, a missing argument).
inline constexpr int kUsageError = 2;

/// Installs the SIGINT/SIGTERM cleanup of temporary files, then parses `argv` into `cmd`'s
/// arguments (adding --verbose, which makes describeError() keep the whole message: MRPT's
/// backtraces included).
/// @return std::nullopt when the tool should run; otherwise the status to exit with:
///         0 after --help or --version (printed on stdout), kUsageError after a usage error
///         (one line "TOOL: usage error: ..." on stderr).
std::optional<int> parseCommandLine(TCLAP::CmdLine& cmd, int argc, char** argv, const std::string& tool);

/// The one-line message of an error for the user: MRPT's exceptions (a banner, a backtrace,
/// then "Message: ...") are reduced to their message, unless --verbose was given.
std::string describeError(const std::exception& e);

}  // namespace lidarseg::apps
