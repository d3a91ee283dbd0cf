#pragma once
// Test files written under the test binary's scratch folder (LIDARSEG_TEST_TMP_DIR, defined
// for every test target).

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

namespace lidarseg::testing {

/// Writes `text` to LIDARSEG_TEST_TMP_DIR/name and returns the path.
inline std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/" + name;
  std::ofstream(path) << text;
  return path;
}

/// The file's bytes ("" when it cannot be read).
inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A folder of the running test's own under `parent`, created: CTest runs the tests of a file
/// as parallel processes, and every tool locks its output folder for its whole run (issue 16).
inline std::string testFolder(const std::string& parent) {
  const std::string dir = parent + "/" + ::testing::UnitTest::GetInstance()->current_test_info()->name();
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace lidarseg::testing
