#pragma once
// Test files written under the test binary's scratch folder (LIDARSEG_TEST_TMP_DIR, defined
// for every test target).

#include <fstream>
#include <string>

namespace lidarseg::testing {

/// Writes `text` to LIDARSEG_TEST_TMP_DIR/name and returns the path.
inline std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/" + name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace lidarseg::testing
