// Run directories: every job writes into a staging folder beside its target,
// which replaces the target only once complete, so that a crash, a kill or a
// full disk at any instant leaves on disk either the previous complete result
// or the new complete one, never a mixture and never nothing.
//
// Output never destroys what skidsim did not create: each run directory holds
// a marker file (kRunMarker); --out naming an existing file, a symbolic link
// or a non-empty folder without the marker is refused before any work starts.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace skidsim::io {

// The file that makes a folder a skidsim run directory (JSON: the command
// that wrote it and the format version).
constexpr const char* kRunMarker = ".skidsim-run";

// The points of commit() in order, for fault injection in tests: a process
// killed at any of them must leave the old or the new result.
enum class CommitPoint { kStaged, kSynced, kSwapped, kOldRemoved };

class StagedRunDirectory {
 public:
  // Refuses (InputError) an --out that is not ours to replace; removes stale
  // staging folders of that target left by killed runs; recovers a previous
  // result a killed run left set aside; makes the staging folder with its
  // marker. `command` names the job ("run", "pour", ...) in the marker.
  StagedRunDirectory(const std::string& out_dir, const std::string& command);
  ~StagedRunDirectory();  // removes the staging folder unless committed
  StagedRunDirectory(const StagedRunDirectory&) = delete;
  StagedRunDirectory& operator=(const StagedRunDirectory&) = delete;

  // Where the files go until commit().
  const std::filesystem::path& staging() const { return staging_; }
  const std::filesystem::path& target() const { return out_dir_; }
  // Flushes the staged files to disk, then puts them in place of the target
  // in one atomic exchange of names (renameat2 RENAME_EXCHANGE; where the
  // file system cannot exchange, the old result is set aside under a name
  // the next run recovers from), then removes the old result. `at`, when
  // given, is called at each point (tests kill the process there).
  void commit(const std::function<void(CommitPoint)>& at = {});

 private:
  std::filesystem::path out_dir_, staging_;
  bool committed_ = false;
};

// Throws InputError unless `out_dir` may be written as a run directory: it
// does not exist, is an empty folder, or a folder holding kRunMarker.
void check_run_directory_target(const std::string& out_dir);

}  // namespace skidsim::io
