#pragma once
// PATH pointed at an empty folder for a test's scope: the tools' child programs (gnuplot)
// are then "not installed"; the old PATH comes back when the scope ends, even on a failure.

#include <cstdlib>
#include <filesystem>
#include <string>

namespace lidarseg::testing {

/// While alive, PATH is LIDARSEG_TEST_TMP_DIR/no-programs (an empty folder).
class EmptyPath {
 public:
  EmptyPath() {
    const char* old = std::getenv("PATH");
    had_ = old != nullptr;
    if (had_) saved_ = old;
    const std::string empty = std::string(LIDARSEG_TEST_TMP_DIR) + "/no-programs";
    std::filesystem::create_directories(empty);
    ::setenv("PATH", empty.c_str(), 1);
  }
  ~EmptyPath() {
    if (had_) {
      ::setenv("PATH", saved_.c_str(), 1);
    } else {
      ::unsetenv("PATH");
    }
  }
  EmptyPath(const EmptyPath&) = delete;
  EmptyPath& operator=(const EmptyPath&) = delete;

 private:
  bool had_ = false;
  std::string saved_;
};

}  // namespace lidarseg::testing
