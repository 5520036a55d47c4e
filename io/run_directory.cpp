#include "io/run_directory.h"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

#include "io/atomic_file.h"

namespace skidsim::io {

namespace fs = std::filesystem;

namespace {

// "runs/x/" and "runs/x" name the same directory; the staging folder must
// sit beside it, not inside it.
fs::path run_directory_path(const std::string& out_dir) {
  fs::path p = fs::path(out_dir).lexically_normal();
  if (!p.empty() && !p.has_filename()) p = p.parent_path();
  const std::string name = p.filename().string();
  if (name.empty() || name == "." || name == "..")
    throw InputError("--out \"" + out_dir + "\": expected a directory name (not empty, '.' or '..')");
  return p;
}

bool has_marker(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / kRunMarker, ec);
}

// Names of the sibling folders a run of `target` by process `pid` uses.
std::string staging_name(const fs::path& target, long pid) { return target.string() + ".partial-" + std::to_string(pid); }
std::string set_aside_name(const fs::path& target, long pid) { return target.string() + ".replaced-" + std::to_string(pid); }

// The pid in "NAME.partial-PID" / "NAME.replaced-PID", or -1.
long sibling_pid(const std::string& file_name, const std::string& prefix) {
  if (file_name.compare(0, prefix.size(), prefix) != 0) return -1;
  const std::string digits = file_name.substr(prefix.size());
  if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stol(digits);
}

bool process_alive(long pid) { return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM); }

void fsync_path(const fs::path& p, int flags) {
  const int fd = ::open(p.c_str(), flags | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("cannot open " + p.string() + " to flush it: " + std::strerror(errno));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0) throw std::runtime_error("cannot flush " + p.string() + " to disk: " + std::strerror(err));
}

// Every file and folder of the staging tree on disk before it is put in place.
void flush_tree(const fs::path& root) {
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(root)) {
    if (e.is_symlink()) continue;
    if (e.is_regular_file()) fsync_path(e.path(), O_RDONLY);
    else if (e.is_directory()) fsync_path(e.path(), O_RDONLY | O_DIRECTORY);
  }
  fsync_path(root, O_RDONLY | O_DIRECTORY);
}

fs::path parent_or_dot(const fs::path& p) { return p.has_parent_path() ? p.parent_path() : fs::path("."); }

// Sibling folders of `target` left by runs that were killed: stale staging
// folders go; a previous result set aside by a killed non-exchanging commit
// comes back if the target is missing (else it is the older one and goes).
// Only folders holding our marker are touched.
void clean_up_after_killed_runs(const fs::path& target) {
  const fs::path parent = parent_or_dot(target);
  std::error_code ec;
  if (!fs::is_directory(parent, ec)) return;
  const std::string base = target.filename().string();
  for (const fs::directory_entry& e : fs::directory_iterator(parent, ec)) {
    const std::string name = e.path().filename().string();
    const long staged = sibling_pid(name, base + ".partial-");
    const long aside = sibling_pid(name, base + ".replaced-");
    const long pid = staged >= 0 ? staged : aside;
    if (pid < 0 || process_alive(pid) || !e.is_directory(ec) || e.is_symlink(ec) || !has_marker(e.path())) continue;
    if (aside >= 0 && !fs::exists(fs::symlink_status(target, ec))) {
      fs::rename(e.path(), target, ec);
      if (!ec) continue;
    }
    fs::remove_all(e.path(), ec);
  }
}

void write_marker(const fs::path& dir, const std::string& command) {
  const fs::path marker = dir / kRunMarker;
  std::ofstream out(marker, std::ios::binary);
  out << "{\"skidsim_run_directory\": 1, \"command\": \"" << command << "\"}\n";
  out.flush();
  if (!out) throw std::runtime_error("cannot write " + marker.string());
}

}  // namespace

void check_run_directory_target(const std::string& out_dir) {
  const fs::path p = run_directory_path(out_dir);
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(p, ec);
  if (!fs::exists(st)) return;
  const std::string name = "--out \"" + out_dir + "\"";
  if (fs::is_symlink(st))
    throw InputError(name + ": is a symbolic link; give the folder it points to, or another name (nothing was written)");
  if (!fs::is_directory(st))
    throw InputError(name + ": exists and is not a folder; refusing to replace it (nothing was written)");
  if (has_marker(p)) return;
  if (fs::directory_iterator(p, ec) != fs::directory_iterator() || ec)
    throw InputError(name + ": a folder that holds files but is not a skidsim run directory (no " +
                     std::string(kRunMarker) + "); refusing to replace it: give a new or empty folder");
}

StagedRunDirectory::StagedRunDirectory(const std::string& out_dir, const std::string& command)
    : out_dir_(run_directory_path(out_dir)), staging_(staging_name(out_dir_, ::getpid())) {
  clean_up_after_killed_runs(out_dir_);
  check_run_directory_target(out_dir);
  fs::remove_all(staging_);
  fs::create_directories(staging_);
  write_marker(staging_, command);
}

StagedRunDirectory::~StagedRunDirectory() {
  std::error_code ignored;
  if (!committed_) fs::remove_all(staging_, ignored);
}

void StagedRunDirectory::commit(const std::function<void(CommitPoint)>& at) {
  const auto point = [&at](CommitPoint p) {
    if (at) at(p);
  };
  check_run_directory_target(out_dir_.string());  // still ours: nothing replaced it while we ran
  point(CommitPoint::kStaged);
  flush_tree(staging_);
  point(CommitPoint::kSynced);
  const fs::path parent = parent_or_dot(out_dir_);
  std::error_code ec;
  const bool target_exists = fs::exists(fs::symlink_status(out_dir_, ec));
  fs::path old;  // where the previous result is after the swap
  if (!target_exists) {
    fs::rename(staging_, out_dir_);
  } else if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, out_dir_.c_str(), RENAME_EXCHANGE) == 0) {
    old = staging_;  // one atomic step: the target is the new result, the staging name holds the old
  } else {
    if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP)
      throw std::runtime_error("cannot put " + staging_.string() + " in place of " + out_dir_.string() + ": " +
                               std::strerror(errno));
    // No exchange on this file system: the old result is set aside under a
    // name that the next run of this target restores if we die in between.
    old = set_aside_name(out_dir_, ::getpid());
    fs::rename(out_dir_, old);
    try {
      fs::rename(staging_, out_dir_);
    } catch (...) {
      fs::rename(old, out_dir_);
      throw;
    }
  }
  committed_ = true;
  fsync_path(parent, O_RDONLY | O_DIRECTORY);
  point(CommitPoint::kSwapped);
  if (!old.empty()) fs::remove_all(old, ec);
  point(CommitPoint::kOldRemoved);
}

}  // namespace skidsim::io
