#pragma once
// The message of the exception a call throws, for tests that check what an error says.

#include <exception>
#include <string>

namespace lidarseg::testing {

/// What `f()` throws (its what()), or "(no error)" when it returns.
template <typename F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace lidarseg::testing
