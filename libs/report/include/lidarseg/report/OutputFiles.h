#pragma once
/// @file
/// lidarseg::report: writing outputs without ever leaving a partial file, a file
/// another run is writing, or a temporary file after an interruption.

#include <fstream>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace lidarseg::report {

/// A command line that cannot be run as given (an output that is an input, two outputs on
/// one path, an out-of-range value): the tools report it as a usage error, exit status 2,
/// before anything is read or written (issue 16).
class UsageError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Whether two paths name the same file or folder: the same file when both exist
/// (std::filesystem::equivalent), else the same path once made absolute, canonical where it
/// exists (weakly_canonical: symbolic links and `..` resolved) and lexically normal (a
/// trailing `/` dropped).
bool samePath(const std::string& a, const std::string& b);

/// The first entry of `folder` (its own, not its subfolders') that `ours` does not accept,
/// as "FOLDER/NAME"; empty when there is none or no such folder. A tool replacing a folder
/// it wrote earlier checks it first: one holding anything else is the user's (or holds an
/// input), and is refused rather than removed.
std::string foreignEntry(const std::string& folder,
                         const std::function<bool(const std::filesystem::directory_entry&)>& ours);

/// A temporary name for `path`, unique to this process and call ("path.tmp.PID.N"), and
/// removed by the SIGINT/SIGTERM handler until released (see installCleanupOnSignals()).
std::string uniqueTemporary(const std::string& path);
/// `temporary` (a file or a folder) was renamed or removed: the signal handler forgets it.
void releaseTemporary(const std::string& temporary);
/// Registers a temporary folder of files (no sub-folders) that the SIGINT/SIGTERM handler
/// removes with its files until released with releaseTemporary() (e.g. the simulator's
/// PREFIX_Images.tmp/, renamed into place when the run succeeds). The caller chooses the name
/// and creates the folder, after registering it.
void registerTemporaryFolder(const std::string& folder);
/// SIGINT, SIGTERM, SIGHUP and SIGQUIT (the last two unless ignored when the process started,
/// as under nohup) remove every registered temporary file and folder, then end the process
/// with the signal's default action; SIGXFSZ is ignored (a write beyond `ulimit -f` fails with
/// EFBIG and is reported naming its file). Idempotent; every tool calls it first thing
/// (through parseCommandLine()).
void installCleanupOnSignals();

/// Writes `content` to `path` through a unique temporary file and a rename, so that a
/// failure never leaves a partial file behind.
/// @throws std::runtime_error naming the file.
void writeFileAtomically(const std::string& path, const std::string& content);

/// @throws UsageError when `output` is the same file as `input` (an output must never
/// overwrite its input), naming both and the option.
void refuseOverwritingInput(const std::string& output, const std::string& input, const std::string& option);

/// A text output written as it goes under a unique temporary name (removed by the
/// SIGINT/SIGTERM handler, decision 47) and renamed to its path by commit(); destroyed
/// without commit(), it removes its temporary file. The stream is set to std::fixed.
class PendingFile {
 public:
  /// @throws std::runtime_error naming the file when it cannot be written.
  explicit PendingFile(std::string path);
  /// The stream to write to.
  std::ofstream& out() { return out_; }
  /// Closes the file, all of it written (a set finishes every file before it publishes any,
  /// so that a full disk leaves none of them in place).
  /// @throws std::runtime_error naming the file when writing failed (disk full); the
  ///         temporary is then removed.
  void finish();
  /// Renames the finished file to its path (finish() first when not done).
  void commit();
  ~PendingFile();
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

 private:
  std::string path_, tmp_;
  std::ofstream out_;
  bool published_ = false;
};

/// Numbered files a tool writes in an output folder: PREFIX, a number (any count of
/// digits), SUFFIX, e.g. {"frames/scan_", ".png"} for `frames/scan_12.png`. PREFIX may start
/// with a subfolder.
struct NumberedName {
  std::string prefix;
  std::string suffix;
};

/// An output named on the command line: its path (empty: not asked for) and its option.
/// For an output folder, `contents` are the names of the files the tool writes in it (those
/// this run may write): each is checked against the inputs and the other outputs;
/// `numbered` the patterns of the numbered files it writes there: an input whose name in
/// the folder matches one is refused (which numbers a run writes is only known once read).
struct NamedOutput {
  std::string path;
  std::string option;
  std::vector<std::string> contents = {};
  std::vector<NumberedName> numbered = {};
};

/// A set of outputs prepared under temporary names and put in place together by commit();
/// destroyed without commit(), it removes its temporary files. Each output folder is locked
/// for the set's lifetime: a second run writing into the same folder is refused. Sets of
/// one process share its locks (the last one destroyed releases a folder).
///
/// A set holding a manifest (`summary.json`) is published as a whole: commit() removes the
/// manifest it replaces first and renames the new one last, so a reader who finds
/// `summary.json` finds every file of its run beside it, never an older run's
/// (docs/reliability.md, "Publishing a set"). The files of the set it replaces that this one
/// does not write (per the old manifest's `files` list, and the publishing record of a run
/// stopped half-way) are removed before the new files are renamed into place; no other file
/// of the folder is touched.
class OutputSet {
 public:
  /// The file name that seals a set: present only when its whole set is in place.
  static constexpr const char* kManifest = "summary.json";
  /// The manifest's key listing the file names of its set (names in the manifest's folder).
  static constexpr const char* kManifestFiles = "files";
  /// While a set is published: the names of both the set replaced and the new one, one per
  /// line, so that a run stopped between two renames is cleaned up by the next.
  static constexpr const char* kPublishing = ".lidarseg.publishing";
  /// Beside numbered files (NumberedName): the names of those a run wrote, one per line, so
  /// that the next run removes only these, never a file of the user's named alike.
  static constexpr const char* kNumberedRecord = ".lidarseg.numbered";
  /// The text of a manifest, given the names of the files of its set in its folder (itself
  /// included), in the order they were added.
  using ManifestText = std::function<std::string(const std::vector<std::string>& files)>;

  OutputSet() = default;
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  /// Locks the folder that will hold `path` (created if needed) before any work is done.
  /// @throws std::runtime_error when another process holds its lock.
  void claim(const std::string& path);
  /// Locks `folder` itself (created if needed), for a tool writing files into it.
  void claimFolder(const std::string& folder);
  /// Locks `folder` (created if needed) as one of several cooperating writers: a shared
  /// flock, held together with other shared holders and refused beside an exclusive one
  /// (claim(), claimFolder()), which is refused beside it in turn. A shared holder never
  /// removes the folder or its lock file. `lidarseg-batch one` jobs share their results
  /// folder this way, each writing only its own seed's run.
  /// @throws std::runtime_error when another process holds the lock exclusively.
  void claimFolderShared(const std::string& folder);
  /// The descriptor of this process's lock on `folder`, a folder this set has claimed, for a
  /// child process to inherit (claimInheritedFolder()). The set keeps it open.
  /// @throws std::logic_error when this set holds no lock on `folder`.
  int folderLockDescriptor(const std::string& folder) const;
  /// In a child process started by a holder of `folder`'s lock (lidarseg-batch's jobs): takes
  /// part in that lock through descriptor `fd`, inherited from the holder, after checking that
  /// it is the folder's lock file and holds its lock (the holder's own open file: another
  /// writer's open file would be refused it). Kept until the set is destroyed, then closed;
  /// the holder's lock stays, since a flock belongs to the open file.
  /// @throws std::runtime_error naming the folder and its lock file when `fd` is not that.
  void claimInheritedFolder(const std::string& folder, int fd);
  /// What every tool does before its work, the one check of its command line's paths
  /// (issue 16), all before any folder is created or any lock taken:
  /// - an output (a file, a folder, or a file of a folder's `contents`) that is one of
  ///   `inputs` is refused (refuseOverwritingInput), and so is an input in an output folder
  ///   named like one of the folder's `numbered` files;
  /// - two outputs on one path are refused, naming both options (a file of one and a folder
  ///   of another included; two options naming the same folder are allowed, their files are
  ///   checked through `contents`);
  /// - an output file that is an existing folder, and an output folder that is an existing
  ///   file, are refused;
  /// then each output's folder is claimed; empty paths are skipped. The inputs are
  /// remembered: commit() never removes one as an older set's file. A folder's `numbered`
  /// files are replaced by this set's (replaceNumbered()). `folders` are output
  /// folders (claimed themselves), `files` output files.
  /// @throws UsageError for a refused command line; std::runtime_error when a folder cannot
  ///         be created (with the reason) or another run holds its lock.
  void claimOutputs(const std::vector<NamedOutput>& files, const std::vector<NamedOutput>& folders,
                    const std::vector<std::string>& inputs);
  /// The files of `folder` named like `numbered` are this set's kind: commit() removes those
  /// an earlier run recorded as written (kNumberedRecord) that this set does not write,
  /// before it renames its own into place, never an input, never a file no run recorded
  /// (a user's picture named alike). Files of other names are not touched.
  void replaceNumbered(const std::string& folder, const NumberedName& numbered);
  /// Adds a text output, written at once under its temporary name.
  /// @throws std::runtime_error naming `path` when it cannot be written (a full disk); the
  ///         set then holds nothing of it, so a caller may go on and commit the rest.
  void add(const std::string& path, std::string content);
  /// Registers an output someone else writes: returns the temporary name to write it under.
  std::string addWritten(const std::string& path);
  /// Adds the manifest (`path` named kManifest), written by commit() once the set's files are
  /// known: `text` receives their names and must list them under kManifestFiles, which is
  /// how the next set finds the files this one leaves behind. `own_names`: every name the
  /// tool may write beside the manifest in any of its runs; only those are removed as the
  /// files of an older set (a manifest edited by hand, or copied from elsewhere, can then
  /// name no other file of the folder), and never a file that is one of the run's inputs.
  /// @throws std::invalid_argument when `path` is not named kManifest.
  void addManifest(const std::string& path, ManifestText text, std::vector<std::string> own_names);
  /// Renames every temporary file to its final name, the manifest last, after removing the
  /// manifest it replaces and the files of its set that this one does not write (see the
  /// class comment).
  /// @throws std::runtime_error naming the file that could not be written; the folder then
  ///         holds no manifest of this set or of the one before.
  void commit();
  ~OutputSet();

 private:
  // claim() and claimFolderShared(): `folder`'s lock, taken or shared within the process.
  void lockFolder(const std::string& folder, bool shared);
  struct Pending {
    std::string path, temporary;
  };
  std::vector<std::string> namesBeside(const std::string& manifest) const;
  void writeManifests();
  void retirePreviousSet(const std::string& manifest);
  bool isInput(const std::filesystem::path& path) const;
  void retireNumbered() const;
  std::vector<Pending> pending_;
  std::vector<std::pair<std::string, ManifestText>> manifests_;  // written by commit()
  std::vector<std::string> own_names_;  // what an older set's manifest may have removed
  std::vector<std::string> inputs_;     // by claimOutputs(): never removed
  std::vector<std::pair<std::string, NumberedName>> numbered_;  // by replaceNumbered()
  std::vector<std::string> locked_folders_;  // canonical; the locks are shared within the process
  std::vector<std::string> created_folders_;  // by claim(): removed again when nothing was published
  bool committed_ = false;
};

}  // namespace lidarseg::report
