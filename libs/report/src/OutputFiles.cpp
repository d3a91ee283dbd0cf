#include "lidarseg/report/OutputFiles.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <stdexcept>
#include <utility>

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

namespace lidarseg::report {

namespace fs = std::filesystem;

namespace {

// Temporary files and folders a signal must remove: fixed slots, so that the handler only
// reads memory that never moves (async-signal-safe: atomics, unlink(), and for a folder
// open(), getdents64(), unlinkat() and rmdir()). A slot is taken (free -> writing), filled,
// then published (ready); the handler removes ready slots only, so it never sees a
// half-copied name.
constexpr std::size_t kSlots = 256;
constexpr std::size_t kPathBytes = 4096;
enum SlotState : int { kFree = 0, kWriting = 1, kReady = 2 };
// What a slot names: a temporary file, a temporary folder (removed with its files), or an
// output folder this run created (removed only when nothing but its lock and empty
// subfolders is left, after the temporaries).
enum SlotKind : int { kFile = 0, kFolder = 1, kCreatedFolder = 2 };
struct Slot {
  std::atomic<int> state{kFree};
  int kind = kFile;
  char path[kPathBytes];
};
std::array<Slot, kSlots> g_slots;

void registerTemporary(const std::string& temporary, int kind) {
  if (temporary.size() >= kPathBytes) return;  // not removable on a signal; still removed otherwise
  for (Slot& s : g_slots) {
    int expected = kFree;
    if (s.state.compare_exchange_strong(expected, kWriting, std::memory_order_acquire)) {
      std::memcpy(s.path, temporary.c_str(), temporary.size() + 1);
      s.kind = kind;
      s.state.store(kReady, std::memory_order_release);
      return;
    }
  }
}

// An output folder this run made, from a signal handler once its temporaries are gone: its
// empty subfolders, its lock file, then itself; anything else in it keeps it (rmdir fails).
void removeCreatedFolderOnSignal(const char* folder) {
  const int fd = ::open(folder, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  alignas(struct dirent64) char entries[4096];
  ssize_t n = 0;
  while ((n = ::getdents64(fd, entries, sizeof entries)) > 0) {
    for (ssize_t at = 0; at < n;) {
      const auto* e = reinterpret_cast<const struct dirent64*>(entries + at);
      at += e->d_reclen;
      const bool dots = e->d_name[0] == '.' && (e->d_name[1] == '\0' || (e->d_name[1] == '.' && e->d_name[2] == '\0'));
      if (!dots && e->d_type == DT_DIR) ::unlinkat(fd, e->d_name, AT_REMOVEDIR);  // only when empty
    }
  }
  ::unlinkat(fd, ".lidarseg.lock", 0);
  ::close(fd);
  ::rmdir(folder);
}

// The files of `folder`, then the folder, from a signal handler (no opendir(): it allocates).
// Another thread may still be adding a file meanwhile, so the folder is emptied again until
// rmdir() succeeds, a few times at most.
void removeFolderOnSignal(const char* folder) {
  constexpr int kPasses = 8;
  for (int pass = 0; pass < kPasses; ++pass) {
    const int fd = ::open(folder, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    alignas(struct dirent64) char entries[4096];
    ssize_t n = 0;
    while ((n = ::getdents64(fd, entries, sizeof entries)) > 0) {
      for (ssize_t at = 0; at < n;) {
        const auto* e = reinterpret_cast<const struct dirent64*>(entries + at);
        at += e->d_reclen;
        const bool dots = e->d_name[0] == '.' && (e->d_name[1] == '\0' || (e->d_name[1] == '.' && e->d_name[2] == '\0'));
        if (!dots) ::unlinkat(fd, e->d_name, 0);
      }
    }
    ::close(fd);
    if (::rmdir(folder) == 0) return;
  }
}

extern "C" void removeTemporariesAndDie(int sig) {
  for (Slot& s : g_slots) {
    if (s.state.load(std::memory_order_acquire) != kReady) continue;
    if (s.kind == kFolder) {
      removeFolderOnSignal(s.path);
    } else if (s.kind == kFile) {
      ::unlink(s.path);
    }
  }
  for (Slot& s : g_slots) {  // the folders made for the outputs, now without temporaries
    if (s.state.load(std::memory_order_acquire) == kReady && s.kind == kCreatedFolder) removeCreatedFolderOnSignal(s.path);
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

// Writes `content` to the temporary `tmp` of the output `path`; errors name the output
// (the file the user asked for) with the system's reason.
void writeTemporary(const std::string& tmp, const std::string& content, const std::string& path) {
  errno = 0;
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (!out) {
    throw std::runtime_error("cannot write '" + path + "'" + (errno != 0 ? ": " + std::string(std::strerror(errno)) : ""));
  }
  out << content;
  out.flush();
  if (!out) {
    const int error = errno;
    out.close();
    std::remove(tmp.c_str());
    throw std::runtime_error("error while writing '" + path + "'" +
                             (error != 0 ? ": " + std::string(std::strerror(error)) : std::string(" (disk full?)")));
  }
}

// The key a folder is locked under. Absolute first: weakly_canonical leaves a relative path
// relative while no prefix of it exists, so a folder made between two claims would get a
// second key and lock itself out.
std::string folderKey(const std::string& folder) {
  std::error_code ec;
  return fs::weakly_canonical(fs::absolute(folder, ec), ec).string();
}

std::string folderOf(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

}  // namespace

std::string uniqueTemporary(const std::string& path) {
  static std::atomic<unsigned long> counter{0};
  // The file's name, cut so that name and suffix fit a file system's 255-byte name: a legal
  // output name of 250 bytes had no legal temporary.
  constexpr std::size_t kMaxNameBytes = 255;
  const std::string suffix = ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  const fs::path p(path);
  std::string name = p.filename().string();
  if (name.size() + suffix.size() > kMaxNameBytes) name.resize(kMaxNameBytes - suffix.size());
  const std::string tmp = (p.parent_path() / (name + suffix)).string();
  registerTemporary(tmp, kFile);
  return tmp;
}

void registerTemporaryFolder(const std::string& folder) { registerTemporary(folder, kFolder); }

void releaseTemporary(const std::string& temporary) {
  for (Slot& s : g_slots) {
    int expected = kReady;
    // Take the slot back for writing while comparing, so no other thread reuses it meanwhile.
    if (s.state.compare_exchange_strong(expected, kWriting, std::memory_order_acquire)) {
      if (temporary == s.path) {
        s.state.store(kFree, std::memory_order_release);
        return;
      }
      s.state.store(kReady, std::memory_order_release);
    }
  }
}

void installCleanupOnSignals() {
  std::signal(SIGINT, removeTemporariesAndDie);
  std::signal(SIGTERM, removeTemporariesAndDie);
  // A closed terminal (SIGHUP) or Ctrl-\ (SIGQUIT) left the temporaries behind. A run
  // started with SIGHUP or SIGQUIT ignored (nohup) keeps ignoring it.
  for (const int sig : {SIGHUP, SIGQUIT}) {
    struct sigaction current {};
    if (::sigaction(sig, nullptr, &current) == 0 && current.sa_handler == SIG_IGN) continue;
    std::signal(sig, removeTemporariesAndDie);
  }
  // A file beyond the size limit (ulimit -f) fails its write with EFBIG, which the writers
  // report naming the file, instead of killing the process with its temporaries left.
  std::signal(SIGXFSZ, SIG_IGN);
}

void writeFileAtomically(const std::string& path, const std::string& content) {
  const std::string tmp = uniqueTemporary(path);
  try {
    writeTemporary(tmp, content, path);
  } catch (...) {
    releaseTemporary(tmp);
    throw;
  }
  const bool renamed = std::rename(tmp.c_str(), path.c_str()) == 0;
  const int error = errno;
  if (!renamed) std::remove(tmp.c_str());
  releaseTemporary(tmp);
  if (!renamed) throw std::runtime_error("cannot put '" + path + "' in place: " + std::strerror(error));
}

namespace {

// `path` absolute, canonical as far as it exists, lexically normal, without a trailing `/`.
fs::path normalPath(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::absolute(path, ec);
  if (ec) p = fs::path(path);
  const fs::path canonical = fs::weakly_canonical(p, ec);
  p = (ec ? p : canonical).lexically_normal();
  if (!p.has_filename() && p.has_parent_path() && p != p.root_path()) p = p.parent_path();
  return p;
}

}  // namespace

bool samePath(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return false;
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec)) return true;
  return normalPath(a) == normalPath(b);
}

std::string foreignEntry(const std::string& folder, const std::function<bool(const fs::directory_entry&)>& ours) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return {};
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    if (!ours(entry)) return entry.path().string();
  }
  if (ec) return folder + " (unreadable: " + ec.message() + ")";
  return {};
}

void refuseOverwritingInput(const std::string& output, const std::string& input, const std::string& option) {
  if (output.empty() || input.empty()) return;
  if (samePath(output, input)) {
    throw UsageError(option + " '" + output + "' is the input '" + input + "': an output never overwrites its input");
  }
}

namespace {

// The folder locks this process holds, by canonical folder, and how many output sets hold
// each: a tool that claims its folder before the work and writes it through another set
// later (the inspector's report, the batch runner's aggregation) shares its own lock, which
// a second flock() from the same process would be refused (flock locks belong to the open
// file, not the process).
struct HeldLock {
  int fd = -1;
  int holders = 0;
};
std::mutex g_locks_mutex;
std::map<std::string, HeldLock> g_locks;

}  // namespace

void OutputSet::claim(const std::string& path) { lockFolder(folderOf(path), false); }

void OutputSet::claimFolderShared(const std::string& folder) { lockFolder(folder, true); }

void OutputSet::lockFolder(const std::string& folder, bool shared) {
  std::error_code ec;
  const std::string key = folderKey(folder);
  if (std::find(locked_folders_.begin(), locked_folders_.end(), key) != locked_folders_.end()) return;
  const std::lock_guard<std::mutex> guard(g_locks_mutex);
  if (const auto held = g_locks.find(key); held != g_locks.end()) {
    ++held->second.holders;
    locked_folders_.push_back(key);
    return;
  }
  const bool created = !fs::exists(folder, ec);
  fs::create_directories(folder, ec);
  if (ec || !fs::is_directory(folder)) {
    const std::string why = ec ? ec.message() : std::string("a file of that name exists");
    throw std::runtime_error("cannot create the output folder '" + folder + "': " + why);
  }
  const std::string lock = (fs::path(folder) / ".lidarseg.lock").string();
  int fd = -1;
  for (int attempt = 0; fd < 0; ++attempt) {
    fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error("cannot create the lock '" + lock + "': " + std::strerror(errno));
    if (::flock(fd, (shared ? LOCK_SH : LOCK_EX) | LOCK_NB) != 0) {
      ::close(fd);
      throw std::runtime_error("another run is writing into '" + folder + "' (lock '" + lock +
                               "' held); wait for it or choose another output");
    }
    // A failed run removes its lock file while holding it: a lock taken on that removed file
    // locks nothing, so check that the file locked is still the one at the path.
    struct stat held {}, current {};
    if (::fstat(fd, &held) != 0 || ::stat(lock.c_str(), &current) != 0 || held.st_ino != current.st_ino ||
        held.st_dev != current.st_dev) {
      ::close(fd);
      fd = -1;
      if (attempt >= 10) throw std::runtime_error("cannot take the lock '" + lock + "': it keeps being removed");
      fs::create_directories(folder, ec);
    }
  }
  g_locks[key] = HeldLock{fd, 1};
  locked_folders_.push_back(key);
  // A shared holder never removes the folder or its lock: the other holders' locks are on it.
  if (created && !shared) {
    created_folders_.push_back(folder);
    registerTemporary(folder, kCreatedFolder);  // removed on a signal when nothing was published
  }
}

int OutputSet::folderLockDescriptor(const std::string& folder) const {
  const std::string key = folderKey(folder);
  const std::lock_guard<std::mutex> guard(g_locks_mutex);
  const auto held = g_locks.find(key);
  if (std::find(locked_folders_.begin(), locked_folders_.end(), key) == locked_folders_.end() ||
      held == g_locks.end()) {
    throw std::logic_error("the lock of '" + folder + "' is not held by this output set");
  }
  return held->second.fd;
}

void OutputSet::claimInheritedFolder(const std::string& folder, int fd) {
  const std::string lock = (fs::path(folder) / ".lidarseg.lock").string();
  struct stat inherited {}, current {};
  const bool same_file = ::fstat(fd, &inherited) == 0 && ::stat(lock.c_str(), &current) == 0 &&
                         inherited.st_ino == current.st_ino && inherited.st_dev == current.st_dev;
  // On the holder's own open file an exclusive flock is granted again at once (locks belong
  // to the open file); on another open file it is refused while the holder lives.
  if (!same_file || ::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    throw std::runtime_error("descriptor " + std::to_string(fd) + " is not the held lock '" + lock +
                             "' of a run writing into '" + folder + "'; another run may be writing there");
  }
  // The runner cleared close-on-exec for this job only: set it again, so that what the job
  // starts (gnuplot) does not keep the folder locked after the runner and the job die.
  ::fcntl(fd, F_SETFD, ::fcntl(fd, F_GETFD) | FD_CLOEXEC);
  const std::string key = folderKey(folder);
  const std::lock_guard<std::mutex> guard(g_locks_mutex);
  if (g_locks.count(key) != 0) throw std::logic_error("this process already holds the lock of '" + folder + "'");
  // Kept open for the set's lifetime; closing this copy leaves the holder's lock in place.
  g_locks[key] = HeldLock{fd, 1};
  locked_folders_.push_back(key);
}

void OutputSet::claimFolder(const std::string& folder) { claim((fs::path(folder) / ".lidarseg.lock").string()); }

namespace {

// One path a command line asks a tool to write: a file, a folder, or a file of a folder.
struct PlannedOutput {
  std::string path;
  std::string option;  // the option naming it (for a folder's file, the folder's)
  bool folder = false;
  std::size_t owner = 0;  // which NamedOutput it comes from
};

std::string quoted(const PlannedOutput& o) {
  return o.option + " '" + o.path + "'";
}

// True when the file name `name` is named like `numbered`'s files (the last part of PREFIX,
// digits, SUFFIX).
bool hasNumberedName(const std::string& name, const NumberedName& numbered) {
  const std::string stem = fs::path(numbered.prefix).filename().string();
  if (name.size() <= stem.size() + numbered.suffix.size()) return false;
  if (name.compare(0, stem.size(), stem) != 0) return false;
  if (name.compare(name.size() - numbered.suffix.size(), numbered.suffix.size(), numbered.suffix) != 0) return false;
  const std::string digits = name.substr(stem.size(), name.size() - stem.size() - numbered.suffix.size());
  return digits.find_first_not_of("0123456789") == std::string::npos;
}

// True when `input` is a file of `folder` named like `numbered` (PREFIX digits SUFFIX).
bool isNumberedFile(const std::string& input, const std::string& folder, const NumberedName& numbered) {
  const fs::path input_path(input);
  if (!hasNumberedName(input_path.filename().string(), numbered)) return false;
  const fs::path input_folder = input_path.has_parent_path() ? input_path.parent_path() : fs::path(".");
  return samePath(input_folder.string(), (fs::path(folder) / fs::path(numbered.prefix).parent_path()).string());
}

}  // namespace

void OutputSet::claimOutputs(const std::vector<NamedOutput>& files, const std::vector<NamedOutput>& folders,
                             const std::vector<std::string>& inputs) {
  // Every refusal first: a refused command line creates no folder and takes no lock.
  std::vector<PlannedOutput> planned;
  std::size_t owner = 0;
  for (const NamedOutput& o : files) {
    ++owner;
    if (!o.path.empty()) planned.push_back({o.path, o.option, false, owner});
  }
  for (const NamedOutput& o : folders) {
    ++owner;
    if (o.path.empty()) continue;
    planned.push_back({o.path, o.option, true, owner});
    for (const std::string& name : o.contents) {
      planned.push_back({(fs::path(o.path) / name).string(), o.option, false, owner});
    }
  }
  for (const PlannedOutput& o : planned) {
    for (const std::string& input : inputs) refuseOverwritingInput(o.path, input, o.option);
  }
  for (const NamedOutput& o : folders) {
    if (o.path.empty()) continue;
    for (const NumberedName& numbered : o.numbered) {
      for (const std::string& input : inputs) {
        if (input.empty() || !isNumberedFile(input, o.path, numbered)) continue;
        throw UsageError(o.option + " '" + o.path + "' gets numbered files " + numbered.prefix + "N" + numbered.suffix +
                         ", and the input '" + input + "' is named like one: an output never overwrites its input");
      }
    }
  }
  std::error_code ec;
  for (const PlannedOutput& o : planned) {
    const fs::file_status status = fs::status(o.path, ec);
    if (o.folder && fs::exists(status) && !fs::is_directory(status)) {
      throw UsageError(quoted(o) + ": an output folder, but a file of that name exists; choose another folder");
    }
    if (!o.folder && fs::is_directory(status)) {
      throw UsageError(quoted(o) + ": an output file, but a folder of that name exists; choose another name");
    }
    // A device, FIFO or socket: the publish (a rename over it) would replace the node itself
    // (as root, `--csv /dev/null` replaced the machine's /dev/null with a file).
    if (!o.folder && fs::exists(status) && !fs::is_regular_file(status)) {
      throw UsageError(quoted(o) + ": an output file, but a device, FIFO or socket of that name exists, which the "
                                   "run's publish would replace; give a regular file's name");
    }
  }
  for (std::size_t i = 0; i < planned.size(); ++i) {
    for (std::size_t j = i + 1; j < planned.size(); ++j) {
      const PlannedOutput& a = planned[i];
      const PlannedOutput& b = planned[j];
      if (a.owner == b.owner || (a.folder && b.folder) || !samePath(a.path, b.path)) continue;
      throw UsageError(quoted(a) + " and " + quoted(b) + " are one path: two outputs never share a file");
    }
  }
  for (const std::string& input : inputs) {
    if (!input.empty()) inputs_.push_back(input);
  }
  for (const NamedOutput& o : files) {
    if (!o.path.empty()) claim(o.path);
  }
  for (const NamedOutput& o : folders) {
    if (o.path.empty()) continue;
    claimFolder(o.path);
    for (const NumberedName& numbered : o.numbered) replaceNumbered(o.path, numbered);
  }
}

void OutputSet::replaceNumbered(const std::string& folder, const NumberedName& numbered) {
  numbered_.emplace_back(folder, numbered);
}

void OutputSet::add(const std::string& path, std::string content) {
  claim(path);
  const std::string tmp = uniqueTemporary(path);
  pending_.push_back({path, tmp});  // registered first: removed on failure
  try {
    writeTemporary(tmp, content, path);
  } catch (...) {
    // Not part of the set: a caller that goes on without it (pictures on a full disk) must
    // not publish a name whose file was never written (issue 16).
    std::remove(tmp.c_str());
    pending_.pop_back();
    throw;
  }
}

std::string OutputSet::addWritten(const std::string& path) {
  claim(path);
  const std::string tmp = uniqueTemporary(path);
  pending_.push_back({path, tmp});
  return tmp;
}

namespace {

bool isManifest(const std::string& path) { return fs::path(path).filename() == OutputSet::kManifest; }

// A name an earlier set may have written: a plain file name of the manifest's folder, never a
// path elsewhere, the folder's lock or the publishing record.
bool isSetFileName(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
         name.find('\0') == std::string::npos && name != ".lidarseg.lock" && name != OutputSet::kPublishing &&
         name != OutputSet::kNumberedRecord;
}

// A manifest or publishing record larger than this is not one lidarseg wrote: nothing is read
// from it (and nothing removed on its word).
constexpr std::uintmax_t kMaxRecordBytes = std::uintmax_t{16} << 20;

bool readableRecord(const std::string& path) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  return !ec && size <= kMaxRecordBytes;
}

// The names an existing manifest lists under "files"; none when it is absent, not JSON, or
// has no such list (a manifest of a lidarseg before the list, or not lidarseg's).
std::vector<std::string> namesInManifest(const std::string& path) {
  if (!readableRecord(path)) return {};
  std::ifstream in(path, std::ios::binary);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return {};
  const auto files = j.find(OutputSet::kManifestFiles);
  if (files == j.end() || !files->is_array()) return {};
  std::vector<std::string> names;
  for (const auto& f : *files) {
    if (f.is_string()) names.push_back(f.get<std::string>());
  }
  return names;
}

// The names a publishing record left by a stopped run lists, one per line.
std::vector<std::string> namesInRecord(const std::string& path) {
  if (!readableRecord(path)) return {};
  std::ifstream in(path, std::ios::binary);
  std::vector<std::string> names;
  for (std::string line; std::getline(in, line);) names.push_back(line);
  return names;
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// A file of the set replaced that the new set does not write. Only files and links are
// removed (a folder of that name is not the set's); one that cannot be removed stops the
// commit, naming it, with no manifest in the folder.
void removeStaleFile(const fs::path& path) {
  std::error_code ec;
  const fs::file_type type = fs::symlink_status(path, ec).type();
  if (type != fs::file_type::regular && type != fs::file_type::symlink) return;
  if (::unlink(path.c_str()) != 0 && errno != ENOENT) {
    throw std::runtime_error("cannot remove '" + path.string() + "', a file of the previous output set: " +
                             std::strerror(errno));
  }
}

}  // namespace

void OutputSet::addManifest(const std::string& path, ManifestText text, std::vector<std::string> own_names) {
  if (!isManifest(path)) throw std::invalid_argument("'" + path + "' is not named " + std::string(kManifest));
  claim(path);
  manifests_.emplace_back(path, std::move(text));
  for (std::string& name : own_names) own_names_.push_back(std::move(name));
}

// Whether `path` is the same file as one of the run's inputs (a log the run reads may have
// been written into its output folder by an earlier run: it is never removed).
bool OutputSet::isInput(const fs::path& path) const {
  std::error_code ec;
  for (const std::string& input : inputs_) {
    if (fs::equivalent(path, input, ec)) return true;
  }
  return false;
}

// An earlier run's numbered files that this set does not write: a folder of images held two
// runs' pictures when the second wrote fewer. Only files a lidarseg run recorded as written
// (kNumberedRecord, beside them) are removed: a folder named for pictures may be the user's
// own (`--draw ~/Pictures`), whose `people_2019.png` is not an earlier run's.
void OutputSet::retireNumbered() const {
  const auto key = [](const fs::path& p) {
    std::error_code ec;
    return fs::absolute(p, ec).lexically_normal();
  };
  // The patterns by the folder their files are written in.
  std::map<fs::path, std::vector<NumberedName>> by_folder;
  for (const auto& [folder, numbered] : numbered_) {
    // The prefix itself is a file's name there: its parent is the folder, with no trailing '/'.
    by_folder[key(fs::path(folder) / numbered.prefix).parent_path()].push_back(numbered);
  }
  for (const auto& [dir, patterns] : by_folder) {
    const auto numberedName = [&patterns = patterns](const std::string& name) {
      return std::any_of(patterns.begin(), patterns.end(),
                         [&](const NumberedName& n) { return hasNumberedName(name, n); });
    };
    std::vector<std::string> mine;
    for (const Pending& p : pending_) {
      const fs::path path = key(p.path);
      const std::string name = path.filename().string();
      if (path.parent_path() == dir && numberedName(name) && !contains(mine, name)) mine.push_back(name);
    }
    const std::string record = (dir / kNumberedRecord).string();
    std::string kept;  // the record's names of other patterns (another tool's pictures there)
    for (const std::string& name : namesInRecord(record)) {
      if (!isSetFileName(name) || contains(mine, name)) continue;
      if (!numberedName(name)) {
        std::error_code ec;
        if (fs::exists(dir / name, ec)) kept += name + "\n";
      } else if (!isInput(dir / name)) {
        removeStaleFile(dir / name);
      }
    }
    // Written before the renames: a run stopped half-way leaves a record naming files that
    // may be absent (harmless), never one missing a file it wrote.
    std::string text = kept;
    for (const std::string& name : mine) text += name + "\n";
    std::error_code ec;
    if (text.empty()) {
      fs::remove(record, ec);
    } else {
      writeFileAtomically(record, text);
    }
  }
}

// The names of the set's files in the folder of `manifest`, in the order added.
std::vector<std::string> OutputSet::namesBeside(const std::string& manifest) const {
  const std::string key = folderKey(folderOf(manifest));
  std::vector<std::string> names;
  for (const auto& p : pending_) {
    const std::string name = fs::path(p.path).filename().string();
    if (folderKey(folderOf(p.path)) == key && !contains(names, name)) names.push_back(name);
  }
  return names;
}

void OutputSet::writeManifests() {
  for (const auto& [path, text] : manifests_) {
    std::vector<std::string> names = namesBeside(path);
    if (!contains(names, kManifest)) names.push_back(kManifest);
    add(path, text(names));
  }
  manifests_.clear();
}

// Before the first rename: the names of both sets recorded (a run stopped from here on is
// cleaned up by the next), the old manifest removed, then the old set's files that the new
// one does not write.
void OutputSet::retirePreviousSet(const std::string& manifest) {
  const fs::path dir = fs::path(folderOf(manifest));
  const std::string record = (dir / kPublishing).string();
  std::vector<std::string> previous = namesInManifest(manifest);
  for (std::string& name : namesInRecord(record)) previous.push_back(std::move(name));
  const std::vector<std::string> mine = namesBeside(manifest);
  std::string both;
  for (const std::string& name : mine) both += name + "\n";
  for (const std::string& name : previous) {
    if (isSetFileName(name) && !contains(mine, name)) both += name + "\n";
  }
  writeFileAtomically(record, both);
  if (std::remove(manifest.c_str()) != 0 && errno != ENOENT) {
    throw std::runtime_error("cannot remove the previous '" + manifest + "': " + std::strerror(errno));
  }
  for (const std::string& name : previous) {
    if (isSetFileName(name) && !contains(mine, name) && contains(own_names_, name) && !isInput(dir / name)) {
      removeStaleFile(dir / name);
    }
  }
}

void OutputSet::commit() {
  // summary.json is the set's seal (docs/reliability.md, "Publishing a set"): the one it
  // replaces is removed before the first rename, with the files of its set that this one
  // does not write, and it is renamed last. While it is absent the folder holds no complete
  // set; once it is back, every file of its set is, and no other file of an earlier set.
  writeManifests();
  std::stable_partition(pending_.begin(), pending_.end(), [](const Pending& p) { return !isManifest(p.path); });
  for (const auto& p : pending_) {
    if (isManifest(p.path)) retirePreviousSet(p.path);
  }
  retireNumbered();
  for (const auto& p : pending_) {
    if (std::rename(p.temporary.c_str(), p.path.c_str()) != 0) {
      throw std::runtime_error("cannot put '" + p.path + "' in place: " + std::strerror(errno) + " (from '" +
                               p.temporary + "')");
    }
    releaseTemporary(p.temporary);
  }
  for (const auto& p : pending_) {
    if (isManifest(p.path)) std::remove((fs::path(folderOf(p.path)) / kPublishing).c_str());
  }
  committed_ = true;
  for (const auto& folder : created_folders_) releaseTemporary(folder);  // published: kept on a signal
}

OutputSet::~OutputSet() {
  for (const auto& p : pending_) {
    if (!committed_) std::remove(p.temporary.c_str());
    releaseTemporary(p.temporary);
  }
  const std::lock_guard<std::mutex> guard(g_locks_mutex);
  std::vector<std::string> released;  // folders no other set of this process holds
  for (const std::string& key : locked_folders_) {
    const auto held = g_locks.find(key);
    if (held == g_locks.end() || --held->second.holders > 0) continue;
    released.push_back(key);
  }
  for (const auto& folder : created_folders_) releaseTemporary(folder);
  // A run that published nothing leaves no folder of its own behind (its lock file removed
  // while still held, see claim()).
  if (!committed_) {
    for (const auto& folder : created_folders_) {
      std::error_code ec;
      const std::string key = folderKey(folder);
      if (std::find(released.begin(), released.end(), key) == released.end()) continue;
      fs::remove(fs::path(folder) / ".lidarseg.lock", ec);
      fs::remove(folder, ec);  // only when empty
    }
  }
  for (const std::string& key : released) {
    const auto held = g_locks.find(key);
    if (held == g_locks.end()) continue;
    ::close(held->second.fd);  // closing releases the flock
    g_locks.erase(held);
  }
}

PendingFile::PendingFile(std::string path) : path_(std::move(path)), tmp_(uniqueTemporary(path_)) {
  errno = 0;
  out_.open(tmp_);
  if (!out_) {
    const int error = errno;
    releaseTemporary(tmp_);
    throw std::runtime_error("cannot write '" + path_ + "'" + (error != 0 ? ": " + std::string(std::strerror(error)) : ""));
  }
  out_ << std::fixed;
}

void PendingFile::finish() {
  if (!out_.is_open()) return;
  out_.flush();
  const int error = errno;
  const bool written = static_cast<bool>(out_);
  out_.close();
  if (written && out_) return;
  std::error_code ec;
  std::filesystem::remove(tmp_, ec);
  releaseTemporary(tmp_);
  throw std::runtime_error("error while writing '" + path_ + "'" +
                           (error != 0 ? ": " + std::string(std::strerror(error)) : std::string(" (disk full?)")));
}

void PendingFile::commit() {
  finish();
  std::filesystem::rename(tmp_, path_);
  releaseTemporary(tmp_);
  published_ = true;
}

PendingFile::~PendingFile() {
  if (published_) return;
  if (out_.is_open()) out_.close();
  std::error_code ec;
  std::filesystem::remove(tmp_, ec);
  releaseTemporary(tmp_);
}

}  // namespace lidarseg::report
