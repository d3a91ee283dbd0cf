#pragma once
/// @file ParallelJobs.h
/// Independent jobs run as child processes a few at a time (lidarseg-batch: one simulated
/// run per seed), so that a job that fails or crashes is reported while the others finish;
/// and the small pieces that make such jobs resumable: a waiting file lock and a file digest.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace lidarseg::pipeline {

/// One child process: its command line (args[0] is the program's path, run as is) and the
/// file its stderr goes to.
struct ChildJob {
  std::vector<std::string> args;
  std::string log_path;
  /// Descriptors of the parent the child inherits under the same numbers (opened close-on-exec
  /// by the parent, which keeps them; e.g. the runner's folder lock).
  std::vector<int> inherited_fds;
};

/// Runs `jobs`, `at_a_time` (at least 1) at a time, in the order given. Each child dies with
/// its parent (PR_SET_PDEATHSIG), so no orphan keeps writing after a runner is killed.
/// `on_done(k, status)` is called as job k ends, `status` as waitpid() gives it.
/// @throws std::runtime_error when a process cannot be started.
void runChildJobs(const std::vector<ChildJob>& jobs, std::size_t at_a_time,
                  const std::function<void(std::size_t k, int status)>& on_done);

/// "exit code C (last line of LOG)" or "killed by signal S (...)" for a waitpid() status;
/// the log's last non-empty line when there is one.
std::string exitDescription(int status, const std::string& log_path);

/// An exclusive lock (flock) on a file, created if needed with its folder, waited for and
/// held for the object's lifetime; released by the kernel if the process dies.
class FileLock {
 public:
  /// @throws std::runtime_error naming the file when it cannot be created or locked.
  explicit FileLock(const std::string& path);
  ~FileLock();
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_ = -1;
};

/// FNV-1a (64 bit) of a file's bytes, as hex: a stable digest for an experiment's record.
/// "-" for an empty path, "unreadable" when the file cannot be read.
std::string fileDigest(const std::string& path);

}  // namespace lidarseg::pipeline
