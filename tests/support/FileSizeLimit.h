#pragma once
// A child process whose files may not grow beyond a limit: how tests meet a full disk
// without one (a write beyond the limit fails with EFBIG, as ENOSPC would).

#include <csignal>
#include <functional>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace lidarseg::testing {

/// Runs `body` in a child whose file size limit is `limit` bytes (SIGXFSZ ignored, so a write
/// beyond it fails with EFBIG as on a full disk); returns the child's exit code (body's
/// value; 90-92 for the harness's own failures, -1/-2 when the child could not run or died).
inline int inChildWithFileSizeLimit(rlim_t limit, const std::function<int()>& body) {
  const pid_t child = fork();
  if (child < 0) return -1;
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit cap{limit, limit};
    if (setrlimit(RLIMIT_FSIZE, &cap) != 0) _exit(90);
    int code = 91;
    try {
      code = body();
    } catch (...) {
      code = 92;
    }
    _exit(code);
  }
  int status = 0;
  if (waitpid(child, &status, 0) != child || !WIFEXITED(status)) return -2;
  return WEXITSTATUS(status);
}

}  // namespace lidarseg::testing
