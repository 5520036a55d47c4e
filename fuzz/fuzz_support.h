// Shared by the libFuzzer harnesses (scripts/fuzz.sh): a private working
// folder per process holding copies of what the inputs may reference (the
// shipped scenarios and operator scripts beside an exercise, the loader's URDF and meshes
// beside its parameters), and the rule every parser must keep: load, or
// throw io::InputError naming the file. Anything else (another exception,
// a crash, a sanitizer report) escapes to libFuzzer as a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>

#include "io/atomic_file.h"
#include "io/loader_files.h"

namespace skidsim::fuzz {

namespace fs = std::filesystem;

// The folder, made on first use and removed at exit: in /dev/shm when there
// is one (an input is written per run).
inline const fs::path& work_dir() {
  static const fs::path dir = [] {
    const fs::path base = fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
    std::string pattern = (base / "skidsim_fuzz_XXXXXX").string();
    if (!::mkdtemp(pattern.data())) std::abort();
    const fs::path d = pattern;
    const fs::path source = SKIDSIM_SOURCE_DIR;
    for (const auto& e : fs::directory_iterator(source / "scenarios"))  // the scripts exercises may name
      if (e.path().extension() == ".xml") fs::copy_file(e.path(), d / e.path().filename());
    fs::copy(fs::path(io::default_loader_path()).parent_path(), d / "loader", fs::copy_options::recursive);
    std::atexit([] { std::error_code ec; fs::remove_all(work_dir(), ec); });
    return d;
  }();
  return dir;
}

inline std::string write_input(const fs::path& path, const std::uint8_t* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) std::abort();
  return path.string();
}

// "PATH:LINE: ..." where PATH is an existing file (a loader's parameters
// may name any URDF).
inline bool names_a_file(const std::string& msg) {
  for (std::size_t colon = msg.find(':'); colon != std::string::npos; colon = msg.find(':', colon + 1)) {
    std::size_t end = colon + 1;
    while (end < msg.size() && msg[end] >= '0' && msg[end] <= '9') ++end;
    std::error_code ec;
    if (end > colon + 1 && end < msg.size() && msg[end] == ':' && fs::is_regular_file(msg.substr(0, colon), ec))
      return true;
  }
  return false;
}

// Runs `parse`: returning or io::InputError naming one of `files` is fine
// (an empty name: any existing file, as "PATH:LINE:"); an InputError naming
// none of them aborts (a finding); any other exception escapes.
template <class Parse>
void expect_load_or_input_error(Parse&& parse, std::initializer_list<std::string> files) {
  try {
    parse();
  } catch (const io::InputError& e) {
    const std::string msg = e.what();
    for (const std::string& f : files)
      if (f.empty() ? names_a_file(msg) : msg.find(f) != std::string::npos) return;
    std::fprintf(stderr, "InputError naming none of the input files: %s\n", msg.c_str());
    std::abort();
  }
}

}  // namespace skidsim::fuzz
