#pragma once
// What happens to a folder's names while a test runs, in order: "-name" removed, "+name"
// renamed into place (inotify; a test reads them after the fact, never waits on time).

#include <string>
#include <vector>

#include <sys/inotify.h>
#include <unistd.h>

namespace lidarseg::testing {

/// Watches `dir` from construction; read() returns the events so far.
class FolderEvents {
 public:
  explicit FolderEvents(const std::string& dir) : fd_(::inotify_init1(IN_NONBLOCK | IN_CLOEXEC)) {
    if (fd_ >= 0) ::inotify_add_watch(fd_, dir.c_str(), IN_MOVED_TO | IN_DELETE);
  }
  ~FolderEvents() {
    if (fd_ >= 0) ::close(fd_);
  }
  FolderEvents(const FolderEvents&) = delete;
  FolderEvents& operator=(const FolderEvents&) = delete;
  /// Whether inotify could be set up (a test skips its order checks otherwise).
  bool watching() const { return fd_ >= 0; }
  std::vector<std::string> read() const {
    std::vector<std::string> out;
    alignas(inotify_event) char buf[8192];
    ssize_t n = 0;
    while ((n = ::read(fd_, buf, sizeof buf)) > 0) {
      for (ssize_t at = 0; at < n;) {
        const auto* e = reinterpret_cast<const inotify_event*>(buf + at);
        at += static_cast<ssize_t>(sizeof(inotify_event) + e->len);
        if (e->len > 0) out.push_back(std::string(e->mask & IN_DELETE ? "-" : "+") + e->name);
      }
    }
    return out;
  }

 private:
  int fd_;
};

}  // namespace lidarseg::testing
