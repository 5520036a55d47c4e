// The hostile-input corpus of the reliability suite (tests/reliability_test.cpp):
// cases generated at test time, by deterministic mutation families, from the
// shipped files (scenarios, operator scripts, soil table, loader parameters,
// URDF and meshes) and from files the real binary writes (a height map of a
// small `skidsim pour`, the session log of a short `skidsim run`), plus the
// command line's numeric options. Each case says what stands at the mutated
// file's path and what the binary must do with it (README, "Bad input":
// exit 2 with a message naming the file, and the line, field or byte where
// that applies; never a signal, a hang or a half-written result).
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace skidsim::reliability {

// The binary and the source tree under test (set by CMake).
std::string binary_path();
std::string source_dir();

enum class Format {
  kExercise,      // scenarios/*.xml, checked with `skidsim check FILE --json`
  kScript,        // scenarios/*.operator.xml, played by `skidsim run EXERCISE --script FILE`
  kSoilTable,     // assets/soils.xml, read by `skidsim pour --soil-table FILE`
  kLoaderParams,  // assets/loader/skidsteer.params.xml, `skidsim check FILE --json`
  kUrdf,          // assets/loader/skidsteer.urdf, beside a copy of the parameters
  kMesh,          // assets/loader/meshes/*.obj, beside copies of both
  kHeightmapJson, // a height map's metadata, `skidsim pour --material-map FILE`
  kHeightmapPng,  // its 16-bit PNG
  kLcmLog,        // a session log, `skidsim run grading.xml --replay FILE`
  kCli,           // numeric and named options of every subcommand
};
const char* format_name(Format f);
const std::vector<Format>& all_formats();

enum class Expect {
  kRefused,   // exit 2 with a message naming the file (and where)
  kEither,    // refused as above, or exit 0 with a complete result
  kAccepted,  // exit 0 with a complete result (the unmutated controls)
};
const char* expect_name(Expect e);

// What stands at the mutated file's path.
enum class Stand {
  kBytes,        // a regular file holding bytes()
  kSparse,       // bytes() followed by a hole up to sparse_bytes
  kDirectory,    // an empty directory
  kDevZero,      // a symbolic link to /dev/zero
  kEmpty,        // an empty regular file
  kFifo,         // a named pipe nobody writes to
  kMissing,      // nothing
  kSymlinkLoop,  // a symbolic link to itself
};

struct Case {
  std::string name;  // unique; letters, digits and '_'
  Format format = Format::kCli;
  std::string family;  // e.g. "number", "truncate", "replace"
  Expect expect = Expect::kRefused;
  std::string base;  // what it was made from (a shipped file, relative to the source tree, or an artifact)
  std::string what;  // one line: what was done
  Stand stand = Stand::kBytes;
  std::function<std::string()> bytes;  // the mutated file (kBytes; kSparse: its start)
  std::uint64_t sparse_bytes = 0;
  // A refusal must say where besides naming the file: one of these names
  // (attribute, field, option) or one of these line numbers; both empty:
  // the file is enough.
  std::vector<std::string> where;
  std::vector<int> lines;
  bool byte_offset = false;  // a refusal must name the byte ("byte")
  std::vector<int> ok_codes;  // exit codes allowed instead of those of `expect` (empty: by `expect`)
  std::string soil_id;       // kSoilTable: the soil whose entry was mutated (pour uses it)
  std::string companion;     // kExercise: other files of the folder; kScript: its exercise
  // kCli: the arguments after `skidsim`; "{SRC}" is the source tree and
  // "{DIR}" the case's folder.
  std::vector<std::string> args;
};

// Files the real binary writes, made once per build of the binary and
// cached (tests/CMakeLists.txt: SKIDSIM_RELIABILITY_CACHE).
struct Artifacts {
  std::string pour_dir;        // skidsim pour, 1 m site: a complete run directory
  std::string heightmap_json;  // its terrain_material.json
  std::string heightmap_png;   // and .png
  std::string run_dir;         // skidsim run grading --max-s 1: a complete run directory
  std::string log;             // its session.lcmlog
  std::string other_log;       // the same from driving_course (another exercise)
  std::string error;           // why they could not be made ("" when they were)
};
const Artifacts& artifacts();

// Every case, in a fixed order.
const std::vector<Case>& corpus();

// Running a process: its own process group, a memory limit (RLIMIT_AS),
// no core files, stdin from /dev/null, stdout and stderr to files; killed
// with its group past the timeout.
struct ProcessOptions {
  std::string cwd = ".";
  std::string log_stem;  // stdout goes to log_stem + ".out", stderr to ".err"
  double timeout_s = 60.0;
  std::uint64_t memory_limit_bytes = 4ull << 30;
};
struct ProcessResult {
  bool started = false;
  bool timed_out = false;
  bool signaled = false;
  int signal = 0;
  int exit_code = -1;
  double wall_s = 0.0;
  long max_rss_kb = 0;
  std::string out, err;
};
struct Child {
  pid_t pid = -1;
  ProcessOptions options;
  double start_s = 0.0;
};
Child start_process(const std::vector<std::string>& argv, const ProcessOptions& options);
ProcessResult finish_process(const Child& child);  // waits, up to the timeout from the start
ProcessResult run_process(const std::vector<std::string>& argv, const ProcessOptions& options);
double monotonic_s();

// The whole of a small file ("" when it cannot be read).
std::string read_file(const std::string& path);
void write_file(const std::string& path, const std::string& bytes);

}  // namespace skidsim::reliability
