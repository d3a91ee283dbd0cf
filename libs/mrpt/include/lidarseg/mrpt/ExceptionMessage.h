#pragma once
/// @file ExceptionMessage.h
/// What an MRPT exception says, without its banner and backtrace.

#include <string>

namespace lidarseg::mrpt_adapter {

/// The message of an exception's text: for MRPT's ("==== MRPT exception ====", a backtrace,
/// then "Message: ..."), the first non-empty line after its last "Message:"; for any other,
/// its first line. Never empty when `what` holds a non-blank line.
std::string exceptionMessage(const std::string& what);

}  // namespace lidarseg::mrpt_adapter
