// How outputs are published (issue 16, class 4): a set is sealed by its manifest, removed
// first and renamed last, the files an earlier set wrote and the new one does not are removed
// (and nothing else), and the SIGINT/SIGTERM cleanup removes temporary folders as well as
// temporary files.
#include <algorithm>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "TempFiles.h"
#include "FileSizeLimit.h"
#include "FolderEvents.h"
#include <nlohmann/json.hpp>

#include "lidarseg/report/OutputFiles.h"

namespace lidarseg::report {
namespace {

namespace fs = std::filesystem;
const std::string kTmp = std::string(LIDARSEG_TEST_TMP_DIR) + "/output-files";

using lidarseg::testing::slurp;

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

using lidarseg::testing::FolderEvents;

TEST(OutputFiles, TheManifestOfASetIsRemovedFirstAndRenamedIntoPlaceLast) {
  const std::string dir = freshFolder("manifest-order");
  // An earlier run's set.
  for (const char* name : {"lidarseg.tum", "timing.csv", "summary.json"}) {
    std::ofstream(dir + "/" + name) << "old " << name;
  }
  FolderEvents events(dir);
  ASSERT_TRUE(events.watching());
  {
    OutputSet set;
    set.add(dir + "/summary.json", "new summary.json");  // added before the files it describes
    set.add(dir + "/lidarseg.tum", "new lidarseg.tum");
    set.add(dir + "/timing.csv", "new timing.csv");
    set.add(dir + "/results.md", "new results.md");
    events.read();  // the temporaries written so far
    set.commit();
  }
  const std::vector<std::string> order = events.read();
  // The publishing record (the names of both sets) is written before the old manifest goes,
  // and removed once the new one is in place.
  const std::vector<std::string> expected = {"+.lidarseg.publishing", "-summary.json", "+lidarseg.tum", "+timing.csv",
                                             "+results.md", "+summary.json", "-.lidarseg.publishing"};
  EXPECT_EQ(order, expected);
  for (const char* name : {"lidarseg.tum", "timing.csv", "results.md", "summary.json"}) {
    EXPECT_EQ(slurp(dir + "/" + name), std::string("new ") + name);
  }
}

TEST(OutputFiles, ASetThatCannotBePublishedLeavesNoManifestBesideItsFiles) {
  const std::string dir = freshFolder("manifest-failed");
  std::ofstream(dir + "/summary.json") << "old summary.json";
  std::ofstream(dir + "/lidarseg.tum") << "old lidarseg.tum";
  fs::create_directories(dir + "/timing.csv/in-the-way");  // a file cannot be renamed over it
  std::string error;
  {
    OutputSet set;
    set.add(dir + "/lidarseg.tum", "new lidarseg.tum");
    set.add(dir + "/timing.csv", "new timing.csv");
    set.add(dir + "/summary.json", "new summary.json");
    try {
      set.commit();
    } catch (const std::runtime_error& e) {
      error = e.what();
    }
  }
  EXPECT_NE(error.find("timing.csv' in place: Is a directory"), std::string::npos) << error;
  EXPECT_NE(error.find("timing.csv"), std::string::npos) << error;
  // The new trajectory is in place, but no summary: neither the old one (which would
  // describe another run) nor the new one (whose set is not complete).
  EXPECT_EQ(slurp(dir + "/lidarseg.tum"), "new lidarseg.tum");
  EXPECT_FALSE(fs::exists(dir + "/summary.json"));
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
  }
}

// An output that cannot be written (a picture on a full disk) leaves the set: a caller that
// goes on without it publishes the rest, never a name whose file is missing (it failed with
// "cannot put 'trajectories.png' in place: No such file or directory", the folder half
// published; issue 16).
TEST(OutputFiles, AFileThatCannotBeWrittenLeavesTheSetAndTheRestIsPublished) {
  const std::string dir = freshFolder("write-failed");
  const int code = lidarseg::testing::inChildWithFileSizeLimit(4096, [&] {
    OutputSet set;
    set.add(dir + "/lidarseg.tum", "small");
    try {
      set.add(dir + "/trajectories.png", std::string(100000, 'p'));
      return 10;  // the write beyond the limit did not fail
    } catch (const std::runtime_error& e) {
      if (std::string(e.what()).find("trajectories.png") == std::string::npos) return 11;
    }
    set.add(dir + "/summary.json", "manifest");
    try {
      set.commit();
    } catch (const std::exception&) {
      return 12;
    }
    return 0;
  });
  EXPECT_EQ(code, 0);
  EXPECT_EQ(slurp(dir + "/lidarseg.tum"), "small");
  EXPECT_EQ(slurp(dir + "/summary.json"), "manifest");
  EXPECT_FALSE(fs::exists(dir + "/trajectories.png"));
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
  }
}

// A manifest as lidarseg-odometry's: JSON listing its set's files.
std::string manifestOf(const std::vector<std::string>& files) {
  return nlohmann::json{{"files", files}}.dump() + "\n";
}

std::vector<std::string> filesListedIn(const std::string& manifest) {
  return nlohmann::json::parse(slurp(manifest)).at("files").get<std::vector<std::string>>();
}

// A set of `names` (each holding "NAME of SET") sealed by a manifest listing them.
// The names a tool of these tests may write beside its manifest (its own names).
const std::vector<std::string> kOwnNames = {"lidarseg.tum", "icp.tum", "icp-s2s.tum", "timing.csv",
                                            "trajectories.png", "run.rawlog"};

void publish(const std::string& dir, const std::vector<std::string>& names, const std::string& set_name,
             const std::vector<std::string>& inputs = {}) {
  OutputSet set;
  set.claimOutputs({}, {{dir, "-o"}}, inputs);
  set.addManifest(dir + "/summary.json", manifestOf, kOwnNames);
  for (const auto& n : names) set.add(dir + "/" + n, n + " of " + set_name);
  set.commit();
}

TEST(OutputFiles, AFileOfThePreviousSetThatTheNewSetDoesNotWriteIsRemovedAndNoOtherFile) {
  const std::string dir = freshFolder("stale-files");
  publish(dir, {"lidarseg.tum", "icp.tum", "trajectories.png"}, "run 1");
  EXPECT_EQ(filesListedIn(dir + "/summary.json"),
            (std::vector<std::string>{"lidarseg.tum", "icp.tum", "trajectories.png", "summary.json"}));
  std::ofstream(dir + "/notes.txt") << "the user's";                     // never written by a set
  fs::create_directories(dir + "/plots");                                 // nor this folder
  publish(dir, {"lidarseg.tum"}, "run 2");  // no --baseline icp, no plots
  EXPECT_FALSE(fs::exists(dir + "/icp.tum"));
  EXPECT_FALSE(fs::exists(dir + "/trajectories.png"));
  EXPECT_EQ(slurp(dir + "/lidarseg.tum"), "lidarseg.tum of run 2");
  EXPECT_EQ(filesListedIn(dir + "/summary.json"), (std::vector<std::string>{"lidarseg.tum", "summary.json"}));
  EXPECT_EQ(slurp(dir + "/notes.txt"), "the user's");
  EXPECT_TRUE(fs::is_directory(dir + "/plots"));
  EXPECT_FALSE(fs::exists(dir + "/" + OutputSet::kPublishing));
  // Every file in the folder is the new set's, or not a set's at all.
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir)) left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{".lidarseg.lock", "lidarseg.tum", "notes.txt", "plots", "summary.json"}));
}

// A folder of numbered pictures (features --images-out, people --draw, the inspector's
// gallery) held two runs' files when the second wrote fewer (issue 16): a set replaces the
// numbered files of its kind, and no other file; a set that is not committed removes none.
TEST(OutputFiles, AnEarlierRunsNumberedFilesTheNewSetDoesNotWriteAreRemovedAndNoOther) {
  const std::string dir = freshFolder("numbered");
  const NumberedName rois{"rois_", ".png"};
  const auto run = [&](const std::vector<std::string>& names, const std::string& text, bool commit) {
    OutputSet s;
    s.claimOutputs({}, {{dir, "--images-out", {}, {rois}}}, {});
    s.replaceNumbered(dir, {"frames/scan_", ".png"});
    for (const std::string& n : names) s.add(dir + "/" + n, text);
    if (commit) s.commit();
  };
  fs::create_directories(dir + "/frames");
  run({"rois_000000.png", "rois_000001.png", "rois_000002.png", "frames/scan_3.png", "frames/scan_40.png"}, "run 1", true);
  for (const char* other : {"rois_notes.png", "other_000001.png", "rois_000001.png.bak", "frames/scan_x.png"}) {
    std::ofstream(dir + "/" + other) << "the user's";
  }
  run({"rois_000000.png", "frames/scan_40.png", "rois_000007.png"}, "failed run", false);
  EXPECT_EQ(slurp(dir + "/rois_000002.png"), "run 1");  // nothing removed without a commit
  run({"rois_000000.png", "frames/scan_40.png"}, "run 2", true);
  EXPECT_EQ(slurp(dir + "/rois_000000.png"), "run 2");
  EXPECT_EQ(slurp(dir + "/frames/scan_40.png"), "run 2");
  EXPECT_FALSE(fs::exists(dir + "/rois_000001.png"));
  EXPECT_FALSE(fs::exists(dir + "/rois_000002.png"));
  EXPECT_FALSE(fs::exists(dir + "/frames/scan_3.png"));
  EXPECT_FALSE(fs::exists(dir + "/rois_000007.png"));
  for (const char* other : {"rois_notes.png", "other_000001.png", "rois_000001.png.bak", "frames/scan_x.png"}) {
    EXPECT_EQ(slurp(dir + "/" + other), "the user's") << other;
  }
}

// A folder named for pictures may be the user's own (`lidarseg-people --draw ~/Pictures`):
// a file named like the tool's pictures that no run wrote is the user's, and stays; only
// what a run recorded as written (OutputSet::kNumberedRecord) is ever removed (issue 16).
TEST(OutputFiles, ANumberedFileNoRunWroteIsTheUsersAndStays) {
  const std::string dir = freshFolder("numbered-users");
  const NumberedName people{"people_", ".png"};
  std::ofstream(dir + "/people_2019.png") << "the user's";
  std::ofstream(dir + "/people_000003.png") << "the user's too";
  const auto run = [&](const std::vector<std::string>& names, const std::string& text) {
    OutputSet s;
    s.claimOutputs({}, {{dir, "--draw", {}, {people}}}, {});
    for (const std::string& n : names) s.add(dir + "/" + n, text);
    s.commit();
  };
  run({"people_000000.png", "people_000001.png"}, "run 1");
  EXPECT_EQ(slurp(dir + "/people_2019.png"), "the user's");
  EXPECT_EQ(slurp(dir + "/people_000003.png"), "the user's too");
  run({"people_000000.png"}, "run 2");
  EXPECT_EQ(slurp(dir + "/people_000000.png"), "run 2");
  EXPECT_FALSE(fs::exists(dir + "/people_000001.png")) << "run 1's, recorded: removed";
  EXPECT_EQ(slurp(dir + "/people_2019.png"), "the user's");
  EXPECT_EQ(slurp(dir + "/people_000003.png"), "the user's too");
  // The record names this set's pictures only.
  EXPECT_EQ(slurp(dir + "/" + OutputSet::kNumberedRecord), "people_000000.png\n");
  // A record edited by hand cannot reach outside the folder.
  const std::string outside = kTmp + "/numbered-users-victim.png";
  std::ofstream(outside) << "keep";
  std::ofstream(dir + "/" + OutputSet::kNumberedRecord) << "../numbered-users-victim.png\n" << outside << "\n";
  run({}, "run 3");
  EXPECT_EQ(slurp(outside), "keep");
  EXPECT_EQ(slurp(dir + "/people_2019.png"), "the user's");
}

TEST(OutputFiles, AManifestNamingFilesOutsideItsFolderRemovesNoneOfThem) {
  const std::string dir = freshFolder("stale-outside");
  const std::string outside = kTmp + "/stale-outside-victim.txt";
  std::ofstream(outside) << "keep";
  fs::create_directories(dir + "/sub");
  std::ofstream(dir + "/sub/x.tum") << "keep";
  fs::create_directories(dir + "/a-folder");
  // A manifest edited by hand (or not lidarseg's): names that are not plain files of the folder.
  std::ofstream(dir + "/summary.json") << manifestOf({"../stale-outside-victim.txt", outside, "sub/x.tum", ".", "..",
                                                      ".lidarseg.lock", "a-folder", std::string("x\0y", 3)});
  publish(dir, {"lidarseg.tum"}, "run 2");
  EXPECT_EQ(slurp(outside), "keep");
  EXPECT_EQ(slurp(dir + "/sub/x.tum"), "keep");
  EXPECT_TRUE(fs::is_directory(dir + "/a-folder"));
  EXPECT_TRUE(fs::exists(dir + "/.lidarseg.lock"));
  EXPECT_EQ(filesListedIn(dir + "/summary.json"), (std::vector<std::string>{"lidarseg.tum", "summary.json"}));
}

TEST(OutputFiles, AManifestNamesOnlyTheToolsOwnFilesAndNeverTheRunsInput) {
  const std::string dir = freshFolder("stale-own-names");
  std::ofstream(dir + "/README.md") << "the user's";
  std::ofstream(dir + "/data.rawlog") << "the user's log";
  // A manifest copied from elsewhere (or edited by hand) naming files of the user's.
  std::ofstream(dir + "/summary.json") << manifestOf({"README.md", "data.rawlog", "icp.tum", "summary.json"});
  std::ofstream(dir + "/icp.tum") << "an older set's";
  publish(dir, {"lidarseg.tum"}, "run 2");
  EXPECT_EQ(slurp(dir + "/README.md"), "the user's");
  EXPECT_EQ(slurp(dir + "/data.rawlog"), "the user's log");
  EXPECT_FALSE(fs::exists(dir + "/icp.tum")) << "one of the tool's own names: removed";
  // A rawlog an earlier run wrote into the folder, read as this run's input: kept, though
  // its name is one the tool writes and the new set does not write it.
  publish(dir, {"lidarseg.tum", "run.rawlog"}, "run 3");
  EXPECT_EQ(slurp(dir + "/run.rawlog"), "run.rawlog of run 3");
  publish(dir, {"lidarseg.tum"}, "run 4", {dir + "/run.rawlog"});
  EXPECT_EQ(slurp(dir + "/run.rawlog"), "run.rawlog of run 3");
  // Run 4's manifest does not list it: kept, it left every set, and no later run removes it.
  EXPECT_EQ(filesListedIn(dir + "/summary.json"), (std::vector<std::string>{"lidarseg.tum", "summary.json"}));
  publish(dir, {"lidarseg.tum"}, "run 5");
  EXPECT_EQ(slurp(dir + "/run.rawlog"), "run.rawlog of run 3");
}

TEST(OutputFiles, ARunStoppedWhilePublishingLeavesARecordTheNextRunCleansUpBy) {
  const std::string dir = freshFolder("stale-interrupted");
  publish(dir, {"lidarseg.tum", "icp.tum"}, "run 1");
  fs::create_directories(dir + "/timing.csv/in-the-way");  // run 2 stops at its timing.csv
  EXPECT_THROW(publish(dir, {"lidarseg.tum", "icp-s2s.tum", "timing.csv"}, "run 2"), std::runtime_error);
  // Run 2 got as far as its scan-to-scan trajectory: no manifest says so, its record does.
  EXPECT_FALSE(fs::exists(dir + "/summary.json"));
  EXPECT_FALSE(fs::exists(dir + "/icp.tum")) << "run 1's, removed before run 2's renames";
  EXPECT_EQ(slurp(dir + "/icp-s2s.tum"), "icp-s2s.tum of run 2");
  const std::string record = slurp(dir + "/" + OutputSet::kPublishing);
  EXPECT_NE(record.find("icp-s2s.tum\n"), std::string::npos) << record;
  fs::remove_all(dir + "/timing.csv");
  publish(dir, {"lidarseg.tum"}, "run 3");
  EXPECT_FALSE(fs::exists(dir + "/icp-s2s.tum"));
  EXPECT_FALSE(fs::exists(dir + "/" + OutputSet::kPublishing));
  EXPECT_EQ(slurp(dir + "/lidarseg.tum"), "lidarseg.tum of run 3");
  EXPECT_EQ(filesListedIn(dir + "/summary.json"), (std::vector<std::string>{"lidarseg.tum", "summary.json"}));
}

TEST(OutputFiles, AManifestMustBeNamedAsOne) {
  const std::string dir = freshFolder("manifest-name");
  OutputSet set;
  EXPECT_THROW(set.addManifest(dir + "/results.json", manifestOf, kOwnNames), std::invalid_argument);
}

// A batch job inherits its runner's lock without close-on-exec (so that it survives the
// job's exec); once claimed, the job sets close-on-exec again, so that the programs it
// starts (gnuplot) do not keep the folder locked after the runner and the job died (review
// finding: a restart was refused while an orphaned gnuplot held the lock).
TEST(OutputFiles, AnInheritedFolderLockIsNotPassedOnToWhatTheJobStarts) {
  const std::string dir = freshFolder("inherited-lock");
  const int fd = ::open((dir + "/.lidarseg.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  ASSERT_EQ(::fcntl(fd, F_SETFD, 0), 0);  // as the runner leaves it for its job
  {
    OutputSet job;
    job.claimInheritedFolder(dir, fd);
    EXPECT_NE(::fcntl(fd, F_GETFD) & FD_CLOEXEC, 0);
  }
}


// Issue 16, the one check of a command line's paths (OutputSet::claimOutputs), shared by
// every tool: refusals are UsageErrors (exit 2), given before any folder is made.
namespace paths {

// The message of the UsageError `f` throws; "(no usage error)" otherwise.
template <typename F>
std::string usageErrorOf(F&& f) {
  try {
    f();
  } catch (const UsageError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("(another error) ") + e.what();
  }
  return "(no usage error)";
}

TEST(OutputFiles, SamePathComparesNormalisedPathsAndExistingFiles) {
  const std::string dir = freshFolder("same-path");
  std::ofstream(dir + "/log") << "x";
  EXPECT_TRUE(samePath(dir + "/log", dir + "/./sub/../log"));
  EXPECT_TRUE(samePath(dir + "/out/", dir + "/out"));  // neither exists; a trailing '/' is no other path
  EXPECT_TRUE(samePath(dir + "/out/a.csv", dir + "/out//a.csv"));
  fs::create_symlink(dir + "/log", dir + "/link");
  EXPECT_TRUE(samePath(dir + "/link", dir + "/log"));
  const std::string relative = fs::relative(dir + "/log").string();
  EXPECT_TRUE(samePath(relative, dir + "/log"));
  EXPECT_FALSE(samePath(dir + "/log", dir + "/log2"));
  EXPECT_FALSE(samePath("", ""));
}

TEST(OutputFiles, AFileAnOutputFolderWouldHoldThatIsAnInputIsRefusedBeforeAnythingIsMade) {
  const std::string dir = freshFolder("folder-file-is-input");
  const std::string input = dir + "/oz/timing.csv";
  fs::create_directories(dir + "/oz");
  std::ofstream(input) << "the log";
  OutputSet set;
  const std::string e = usageErrorOf(
      [&] { set.claimOutputs({}, {{dir + "/oz/", "-o", {"lidarseg.tum", "timing.csv"}}}, {dir + "/oz/../oz/timing.csv"}); });
  EXPECT_NE(e.find("-o '" + dir + "/oz/timing.csv' is the input"), std::string::npos) << e;
  EXPECT_NE(e.find("an output never overwrites its input"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(dir + "/oz/.lidarseg.lock"));  // no lock taken
  EXPECT_EQ(slurp(input), "the log");
}

TEST(OutputFiles, TwoOutputsOnOnePathAreRefusedNamingBothOptions) {
  const std::string dir = freshFolder("two-outputs");
  {
    OutputSet set;
    const std::string e = usageErrorOf([&] {
      set.claimOutputs({{dir + "/x.csv", "--features-out"}, {dir + "/./x.csv", "--write-rawlog"}}, {}, {});
    });
    EXPECT_NE(e.find("--features-out '" + dir + "/x.csv' and --write-rawlog"), std::string::npos) << e;
    EXPECT_NE(e.find("two outputs never share a file"), std::string::npos) << e;
  }
  {
    OutputSet set;  // a file output that a folder output also writes
    const std::string e = usageErrorOf([&] {
      set.claimOutputs({{dir + "/oz/summary.json", "--write-rawlog"}}, {{dir + "/oz", "-o", {"summary.json"}}}, {});
    });
    EXPECT_NE(e.find("--write-rawlog"), std::string::npos) << e;
    EXPECT_NE(e.find("-o '" + dir + "/oz/summary.json'"), std::string::npos) << e;
  }
  {
    OutputSet set;  // a folder output on the path of a file output (it failed after the whole run)
    const std::string e = usageErrorOf([&] {
      set.claimOutputs({{dir + "/po/people.csv", "--out"}}, {{dir + "/po/people.csv", "--draw"}}, {});
    });
    EXPECT_NE(e.find("--out '" + dir + "/po/people.csv' and --draw"), std::string::npos) << e;
  }
  {
    OutputSet set;  // a file output on the path of an output folder
    const std::string e =
        usageErrorOf([&] { set.claimOutputs({{dir + "/oz", "--features-out"}}, {{dir + "/oz/", "-o", {"a"}}}, {}); });
    EXPECT_NE(e.find("--features-out '" + dir + "/oz' and -o"), std::string::npos) << e;
  }
  EXPECT_TRUE(fs::is_empty(dir));  // nothing made by a refused command line
  OutputSet set;  // two options naming one folder (a report beside the CSV) are allowed
  set.claimOutputs({{dir + "/oz/people.csv", "--out"}}, {{dir + "/oz", "--report", {"people.md"}}, {dir + "/oz", "--draw"}},
                   {});
  EXPECT_TRUE(fs::is_directory(dir + "/oz"));
}

TEST(OutputFiles, AnOutputFolderThatIsAFileOrCannotBeMadeIsRefusedWithTheReason) {
  const std::string dir = freshFolder("folder-cannot-be-made");
  std::ofstream(dir + "/afile") << "x";
  {
    OutputSet set;
    const std::string e = usageErrorOf([&] { set.claimOutputs({}, {{dir + "/afile", "-o"}}, {}); });
    EXPECT_NE(e.find("-o '" + dir + "/afile': an output folder, but a file of that name exists"), std::string::npos) << e;
  }
  {
    OutputSet set;  // and an output file that is an existing folder
    fs::create_directories(dir + "/adir");
    const std::string e = usageErrorOf([&] { set.claimOutputs({{dir + "/adir", "--figure"}}, {}, {}); });
    EXPECT_NE(e.find("--figure '" + dir + "/adir': an output file, but a folder of that name exists"), std::string::npos)
        << e;
  }
  OutputSet set;  // a folder under a file: the reason, not the lock's "No such file"
  try {
    set.claimOutputs({}, {{dir + "/afile/x", "-o"}}, {});
    ADD_FAILURE() << "a folder under a file was made";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("cannot create the output folder '" + dir + "/afile/x': Not a directory"), std::string::npos) << m;
    EXPECT_EQ(m.find("lock"), std::string::npos) << m;
  }
  EXPECT_EQ(slurp(dir + "/afile"), "x");
}

// Issue 16: an output file named like a FIFO (or a device: as root, `--csv /dev/null`)
// was replaced by a regular file at the publish, and a lock left beside it. Refused before
// anything is made; the node stays.
TEST(OutputFiles, AnOutputFileThatIsAFifoOrADeviceIsRefusedAndKept) {
  const std::string dir = freshFolder("output-fifo");
  const std::string fifo = dir + "/pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  for (const std::string& path : {fifo, std::string("/dev/null")}) {
    OutputSet set;
    const std::string e = usageErrorOf([&] { set.claimOutputs({{path, "--csv"}}, {}, {}); });
    EXPECT_NE(e.find("--csv '" + path + "': an output file, but a device, FIFO or socket of that name exists"),
              std::string::npos)
        << e;
  }
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_FALSE(fs::exists(dir + "/.lidarseg.lock"));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

// Issue 16: a legal output name of 250 bytes had no legal temporary (name + ".tmp.PID.N"
// beyond 255 bytes), and the error named the temporary with no reason.
TEST(OutputFiles, AnOutputNameNearTheLimitGetsATemporaryThatFits) {
  const std::string dir = freshFolder("long-name");
  const std::string path = dir + "/" + std::string(246, 'f') + ".csv";  // 250 bytes
  OutputSet set;
  set.add(path, "a,b\n");
  set.commit();
  EXPECT_EQ(slurp(path), "a,b\n");
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.path().filename().string().rfind(".lidarseg", 0) != 0;
  EXPECT_EQ(files, 1u) << "a temporary was left";
  // A name beyond the limit: the error names the output and says why.
  const std::string bad = dir + "/" + std::string(300, 'g');
  try {
    OutputSet too_long;
    too_long.add(bad, "x");
    too_long.commit();
    ADD_FAILURE() << "a 300-byte name was written";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("cannot put '" + bad + "' in place: File name too long", 0), 0u) << m;
  }
  files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.path().filename().string().rfind(".lidarseg", 0) != 0;
  EXPECT_EQ(files, 1u) << "the failed set left a file";
}

// Issue 16: a set of streamed files is finished whole before any is put in place: on a full
// disk (here the file size limit) the simulator published its text files without the rawlog
// and left the failing file's temporary. finish() names the file and the reason and removes
// its temporary; the others are removed with their objects.
TEST(OutputFiles, PendingFilesAreFinishedBeforeAnyIsPublishedAndAFailureLeavesNone) {
  const std::string dir = freshFolder("pending-full");
  const int code = lidarseg::testing::inChildWithFileSizeLimit(64 * 1024, [&] {
    {
      PendingFile small(dir + "/small.csv"), big(dir + "/big.csv");
      small.out() << "a,b\n";
      big.out() << std::string(256 * 1024, 'x');
      try {
        small.finish();
        big.finish();
        return 10;  // no error
      } catch (const std::runtime_error& e) {
        if (std::string(e.what()) != "error while writing '" + dir + "/big.csv': " + std::strerror(EFBIG)) return 11;
      }
    }
    for (const auto& e : fs::directory_iterator(dir)) {
      if (e.path().filename().string().rfind(".lidarseg", 0) != 0) return 12;  // a file or temporary left
    }
    return 0;
  });
  EXPECT_EQ(code, 0) << "10: no error; 11: message; 12: a file left";
}

}  // namespace paths

}  // namespace
}  // namespace lidarseg::report
