#include "lidarseg/pipeline/ParallelJobs.h"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace lidarseg::pipeline {

namespace {

// Starts `args` (args[0] is the program) in a child process with its stderr in `log` and
// the descriptors `inherited` kept open across exec.
pid_t startJob(std::vector<std::string> args, const std::string& log, const std::vector<int>& inherited) {
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("cannot start a job (fork failed)");
  if (pid == 0) {
    // A job dies with its runner (killed or not), so that no orphan keeps writing
    // while a new runner resumes; a lock of the caller (a seed's) covers the instant in between.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    FILE* f = std::freopen(log.c_str(), "w", stderr);
    (void)f;
    for (const int fd : inherited) ::fcntl(fd, F_SETFD, 0);  // in the child only: no other exec inherits it
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(args[0].c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

}  // namespace

std::string exitDescription(int status, const std::string& log) {
  const std::string why = WIFSIGNALED(status)
                              ? "killed by signal " + std::to_string(WTERMSIG(status))
                              : "exit code " + std::to_string(WEXITSTATUS(status));
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  return why + (last.empty() ? "" : " (" + last + ")");
}

void runChildJobs(const std::vector<ChildJob>& jobs, std::size_t at_a_time,
                  const std::function<void(std::size_t k, int status)>& on_done) {
  std::map<pid_t, std::size_t> running;
  std::size_t next = 0;
  while (next < jobs.size() || !running.empty()) {
    while (next < jobs.size() && running.size() < std::max<std::size_t>(at_a_time, 1)) {
      running[startJob(jobs[next].args, jobs[next].log_path, jobs[next].inherited_fds)] = next;
      ++next;
    }
    int status = 0;
    const pid_t pid = wait(&status);
    if (pid < 0) break;
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const std::size_t k = it->second;
    running.erase(it);
    on_done(k, status);
  }
}

FileLock::FileLock(const std::string& path) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error("cannot create the lock file '" + path + "'");
  while (::flock(fd_, LOCK_EX) != 0) {
    if (errno != EINTR) throw std::runtime_error("cannot lock '" + path + "'");
  }
}

FileLock::~FileLock() { ::close(fd_); }  // releases the lock

std::string fileDigest(const std::string& path) {
  if (path.empty()) return "-";
  std::ifstream in(path, std::ios::binary);
  if (!in) return "unreadable";
  std::uint64_t h = 14695981039346656037ull;
  char c = 0;
  while (in.get(c)) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  std::ostringstream os;
  os << std::hex << h;
  return os.str();
}

}  // namespace lidarseg::pipeline
