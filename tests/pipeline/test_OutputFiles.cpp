// How outputs are published (issue 16, class 4): the SIGINT/SIGTERM cleanup removes
// temporary folders as well as temporary files.
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "lidarseg/pipeline/OutputFiles.h"

namespace lidarseg::pipeline {
namespace {

namespace fs = std::filesystem;
const std::string kTmp = std::string(LIDARSEG_TEST_TMP_DIR) + "/output-files";

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::string freshFolder(const std::string& name) {
  const std::string dir = kTmp + "/" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// A child process that prepares temporaries with `prepare`, then is sent `sig`: how it ended.
template <typename Prepare>
int statusOfChildKilledBy(int sig, Prepare prepare) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    installCleanupOnSignals();
    prepare();
    std::raise(sig);
    ::_exit(0);  // not reached: the handler ends the process with the signal
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

TEST(OutputFiles, ASignalRemovesARegisteredTemporaryFolderWithItsFiles) {
  const std::string dir = freshFolder("signal-folder");
  const std::string images = dir + "/run_Images.tmp";
  const int status = statusOfChildKilledBy(SIGTERM, [&] {
    registerTemporaryFolder(images);
    fs::create_directories(images);
    // More names than one read of the folder returns.
    for (int i = 0; i < 300; ++i) std::ofstream(images + "/img_" + std::to_string(i) + ".png") << "png";
    std::ofstream(uniqueTemporary(dir + "/run.rawlog")) << "partial";
  });
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_FALSE(fs::exists(images));
  EXPECT_TRUE(fs::is_empty(dir)) << "the temporary file is removed too";
}

TEST(OutputFiles, AReleasedFolderIsKeptBySIGINT) {
  const std::string dir = freshFolder("released-folder");
  const std::string images = dir + "/run_Images";
  const int status = statusOfChildKilledBy(SIGINT, [&] {
    registerTemporaryFolder(dir + "/run_Images.tmp");
    fs::create_directories(dir + "/run_Images.tmp");
    std::ofstream(dir + "/run_Images.tmp/img_0.png") << "png";
    fs::rename(dir + "/run_Images.tmp", images);  // published
    releaseTemporary(dir + "/run_Images.tmp");
    fs::create_directories(dir + "/run_Images.tmp");  // the next run's, no longer registered
  });
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(WTERMSIG(status), SIGINT);
  EXPECT_EQ(slurp(images + "/img_0.png"), "png");
  EXPECT_TRUE(fs::exists(dir + "/run_Images.tmp"));
}

}  // namespace
}  // namespace lidarseg::pipeline
