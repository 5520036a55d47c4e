// Run directories (io/run_directory.h): output never destroys what skidsim
// did not create, and a process killed at any point of the swap leaves the
// old or the new complete result.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "io/atomic_file.h"
#include "io/run_directory.h"

namespace skidsim::io {
namespace {

namespace fs = std::filesystem;

class RunDirectory : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("skidsim_rundir_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }

  static std::string read(const fs::path& p) {
    std::ifstream in(p);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  // A complete run: the marker and both result files, with `tag` in each.
  static void write_run(const fs::path& dir, const std::string& tag) {
    std::ofstream(dir / "summary.json") << tag;
    std::ofstream(dir / "result.txt") << tag;
  }
  static bool holds_complete_run(const fs::path& dir, const std::string& tag) {
    return fs::is_regular_file(dir / kRunMarker) && read(dir / "summary.json") == tag && read(dir / "result.txt") == tag;
  }
  std::string refusal(const fs::path& out) const {
    try {
      StagedRunDirectory d(out.string(), "test");
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  int entries() const {
    int n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(root_)) ++n;
    return n;
  }

  fs::path root_;
};

TEST_F(RunDirectory, RefusesAFileALinkAndAForeignFolder) {
  std::ofstream(root_ / "thesis.pdf") << "years of work";
  const std::string file = refusal(root_ / "thesis.pdf");
  EXPECT_NE(file.find("not a folder"), std::string::npos) << file;
  EXPECT_EQ(read(root_ / "thesis.pdf"), "years of work");

  fs::create_directories(root_ / "papers");
  std::ofstream(root_ / "papers" / "draft.tex") << "chapter 1";
  const std::string folder = refusal(root_ / "papers");
  EXPECT_NE(folder.find("not a skidsim run directory"), std::string::npos) << folder;
  EXPECT_EQ(read(root_ / "papers" / "draft.tex"), "chapter 1");

  fs::create_directory_symlink(root_ / "papers", root_ / "link");
  EXPECT_NE(refusal(root_ / "link").find("symbolic link"), std::string::npos);
  EXPECT_EQ(entries(), 3) << "no staging folder left behind by a refusal";
}

TEST_F(RunDirectory, WritesIntoNewEmptyAndOwnFolders) {
  fs::create_directories(root_ / "empty");
  for (const char* name : {"new", "empty"}) {
    StagedRunDirectory d((root_ / name).string(), "test");
    write_run(d.staging(), name);
    d.commit();
    EXPECT_TRUE(holds_complete_run(root_ / name, name));
  }
  // A run directory is replaced whole: a file only the old run had goes.
  std::ofstream(root_ / "new" / "old_only.txt") << "x";
  StagedRunDirectory again((root_ / "new").string(), "test");
  write_run(again.staging(), "second");
  again.commit();
  EXPECT_TRUE(holds_complete_run(root_ / "new", "second"));
  EXPECT_FALSE(fs::exists(root_ / "new" / "old_only.txt"));
  EXPECT_EQ(entries(), 2) << "nothing beside the run directories";
}

TEST_F(RunDirectory, AFailedRunLeavesThePreviousResult) {
  {
    StagedRunDirectory d((root_ / "run").string(), "test");
    write_run(d.staging(), "first");
    d.commit();
  }
  {
    StagedRunDirectory d((root_ / "run").string(), "test");
    write_run(d.staging(), "second");
  }  // never committed (an exception, a refused input)
  EXPECT_TRUE(holds_complete_run(root_ / "run", "first"));
  EXPECT_EQ(entries(), 1);
}

// A child process builds a new result and is killed (SIGKILL: no clean-up
// of any kind) at one point of the swap. The target then holds the old or
// the new complete result; the next run removes what the kill left beside it.
TEST_F(RunDirectory, AKillAtEveryPointOfTheSwapLeavesOldOrNew) {
  const fs::path target = root_ / "run";
  for (const CommitPoint kill_at :
       {CommitPoint::kStaged, CommitPoint::kSynced, CommitPoint::kSwapped, CommitPoint::kOldRemoved}) {
    fs::remove_all(root_);
    fs::create_directories(root_);
    {
      StagedRunDirectory d(target.string(), "test");
      write_run(d.staging(), "old");
      d.commit();
    }
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      StagedRunDirectory d(target.string(), "test");
      write_run(d.staging(), "new");
      d.commit([kill_at](CommitPoint p) {
        if (p == kill_at) ::raise(SIGKILL);
      });
      ::_exit(0);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
    const bool is_old = holds_complete_run(target, "old"), is_new = holds_complete_run(target, "new");
    EXPECT_TRUE(is_old || is_new) << "killed at point " << static_cast<int>(kill_at);
    if (kill_at >= CommitPoint::kSwapped) {
      EXPECT_TRUE(is_new);
    }
    // The next run cleans up the killed one's staging or set-aside folder.
    StagedRunDirectory next(target.string(), "test");
    write_run(next.staging(), "next");
    next.commit();
    EXPECT_TRUE(holds_complete_run(target, "next"));
    EXPECT_EQ(entries(), 1) << "killed at point " << static_cast<int>(kill_at);
  }
}

// Where the file system cannot exchange names, a kill between the two
// renames leaves the old result set aside: the next run puts it back before
// anything else, so it is never lost.
TEST_F(RunDirectory, APreviousResultSetAsideByAKilledRunComesBack) {
  const fs::path target = root_ / "run";
  {
    StagedRunDirectory d(target.string(), "test");
    write_run(d.staging(), "old");
    d.commit();
  }
  const fs::path aside = root_ / "run.replaced-999999";  // no such process
  fs::rename(target, aside);
  fs::create_directories(root_ / "run.partial-999999");
  std::ofstream(root_ / "run.partial-999999" / kRunMarker) << "{}";
  StagedRunDirectory d(target.string(), "test");
  EXPECT_TRUE(holds_complete_run(target, "old")) << "restored before the new run starts";
  EXPECT_FALSE(fs::exists(root_ / "run.partial-999999"));
  // A folder that merely looks like ours (no marker) is never touched.
  fs::create_directories(root_ / "run.partial-999998");
  std::ofstream(root_ / "run.partial-999998" / "mine.txt") << "keep";
  StagedRunDirectory e(target.string(), "test");
  EXPECT_EQ(read(root_ / "run.partial-999998" / "mine.txt"), "keep");
}

}  // namespace
}  // namespace skidsim::io
