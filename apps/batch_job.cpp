#include "apps/batch_job.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <cmath>
#include <type_traits>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_file.h"
#include "io/json_file.h"

namespace skidsim::apps {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Entry {
  int line = 0;
  std::vector<std::string> args;  // for `skidsim run`
  std::string name;               // NNN_exercise: its run directory and log
  int exit_code = -1;
  double wall_s = 0.0;
};

std::vector<Entry> read_list(const std::string& path) {
  // A checked file (io/input_file.h: regular, at most kMaxJsonBytes), valid
  // UTF-8 without NUL bytes: its words become arguments and go on into
  // batch.json, which must be valid text.
  const std::string all = io::read_input_file(path, io::kMaxJsonBytes, "batch list");
  const io::Utf8Error bad = io::find_invalid_utf8(all);
  if (bad.offset >= 0)
    throw io::InputError(path + ":" + std::to_string(bad.line) + ": invalid UTF-8 at byte " + std::to_string(bad.offset));
  if (const std::size_t nul = all.find('\0'); nul != std::string::npos)
    throw io::InputError(path + ":" + std::to_string(1 + std::count(all.begin(), all.begin() + static_cast<long>(nul), '\n')) +
                         ": a NUL byte at byte " + std::to_string(nul) + " (not a text file)");
  std::istringstream in(all);
  std::vector<Entry> entries;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    const std::size_t hash = text.find('#');
    if (hash != std::string::npos) text.resize(hash);
    std::istringstream words(text);
    Entry e;
    e.line = line;
    for (std::string w; words >> w;) e.args.push_back(w);
    if (e.args.empty()) continue;
    const auto where = path + ":" + std::to_string(line) + ": ";
    if (!fs::is_regular_file(e.args.front())) throw io::InputError(where + "'" + e.args.front() + "': no such exercise file");
    bool operated = false;
    for (const std::string& w : e.args) {
      if (w == "--out" || w == "--lcm" || w.rfind("--out=", 0) == 0 || w.rfind("--lcm=", 0) == 0)
        throw io::InputError(where + w + ": the batch sets each session's run directory and keeps it off the network");
      operated = operated || w == "--script" || w == "--replay";
    }
    if (!operated) throw io::InputError(where + "a batch session needs --script or --replay (no one is at the controls)");
    char number[16];
    std::snprintf(number, sizeof number, "%03zu_", entries.size() + 1);
    e.name = number + fs::path(e.args.front()).stem().string();
    entries.push_back(e);
  }
  if (entries.empty()) throw io::InputError(path + ": no sessions in the list");
  return entries;
}

// A field of a session's report of the type expected, else `fallback`.
template <typename T>
T field_or(const json& object, const char* key, const T& fallback) {
  if (!object.is_object() || !object.contains(key)) return fallback;
  const json& v = object.at(key);
  if constexpr (std::is_same_v<T, bool>) return v.is_boolean() ? v.get<bool>() : fallback;
  else return v.is_string() ? v.get<std::string>() : fallback;
}
double finite_or(const json& object, const char* key) {
  if (!object.is_object() || !object.contains(key) || !object.at(key).is_number()) return 0.0;
  const double v = object.at(key).get<double>();
  return std::isfinite(v) ? v : 0.0;
}

// `skidsim run ARGS --out DIR`, its output into LOG; returns the pid.
pid_t start(const std::string& self, const Entry& e, const fs::path& out) {
  std::vector<std::string> args = {self, "run"};
  args.insert(args.end(), e.args.begin(), e.args.end());
  args.push_back("--out");
  args.push_back((out / e.name).string());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string log = (out / (e.name + ".log")).string();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int failed = posix_spawn(&pid, self.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (failed != 0) throw std::runtime_error("cannot start " + self + ": " + std::strerror(failed));
  return pid;
}

}  // namespace

int run_batch(const BatchJob& job) {
  std::vector<Entry> entries = read_list(job.list_path);
  const int n = static_cast<int>(entries.size());
  if (job.index < 0 || job.index > n)
    throw io::InputError("--index " + std::to_string(job.index) + ": the list has entries 1 to " + std::to_string(n));
  if (job.jobs < 0 || job.jobs > 256) throw io::InputError("--jobs: expected 1 to 256 (0: the machine's cores)");
  std::vector<int> todo;
  for (int k = 0; k < n; ++k)
    if (job.index == 0 || job.index == k + 1) todo.push_back(k);
  const int jobs = job.jobs > 0 ? job.jobs : std::max(1u, std::thread::hardware_concurrency());
  const fs::path out = job.out_dir;
  fs::create_directories(out);
  const std::string self = fs::read_symlink("/proc/self/exe").string();

  using Clock = std::chrono::steady_clock;
  std::map<pid_t, std::pair<int, Clock::time_point>> running;
  std::size_t next = 0;
  const auto started = Clock::now();
  while (next < todo.size() || !running.empty()) {
    while (next < todo.size() && static_cast<int>(running.size()) < jobs) {
      const int k = todo[next++];
      running[start(self, entries[static_cast<std::size_t>(k)], out)] = {k, Clock::now()};
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("waiting for the sessions: ") + std::strerror(errno));
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    Entry& e = entries[static_cast<std::size_t>(it->second.first)];
    e.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    e.wall_s = std::chrono::duration<double>(Clock::now() - it->second.second).count();
    std::cerr << "batch: " << e.name << " exit " << e.exit_code << " (" << e.wall_s << " s)\n";
    running.erase(it);
  }

  // The summary: each session's outcome from its report.
  json sessions = json::array();
  bool all_ran = true;
  std::printf("%-4s %-28s %4s %-6s %9s %9s %8s\n", "#", "session", "exit", "passed", "score", "sim s", "wall s");
  for (const int k : todo) {
    const Entry& e = entries[static_cast<std::size_t>(k)];
    all_ran = all_ran && e.exit_code == 0;
    json s = {{"entry", k + 1}, {"line", e.line}, {"args", e.args}, {"run_dir", e.name}, {"log", e.name + ".log"},
              {"exit_code", e.exit_code}, {"wall_s", e.wall_s}};
    // The session's report, if it wrote one: read as a checked file and
    // taken only where each field has its type and a finite value (a
    // session that died part-way is summarised as not passed, not trusted).
    json r;
    try {
      r = io::read_json_file((out / e.name / "report.json").string(), "report");
    } catch (const std::exception&) {
      r = json();
    }
    const json& result = r.is_object() && r.contains("result") ? r["result"] : json();
    const json& performance = r.is_object() && r.contains("performance") ? r["performance"] : json();
    s["passed"] = field_or(result, "passed", false);
    s["score"] = finite_or(result, "score");
    s["simulated_s"] = finite_or(performance, "simulated_s");
    s["final_state_hash"] = field_or(r, "final_state_hash", std::string());
    std::printf("%-4d %-28s %4d %-6s %9.2f %9.2f %8.2f\n", k + 1, e.name.c_str(), e.exit_code,
                s["passed"].get<bool>() ? "yes" : "no", s["score"].get<double>(), s["simulated_s"].get<double>(), e.wall_s);
    sessions.push_back(s);
  }
  const double wall_s = std::chrono::duration<double>(Clock::now() - started).count();
  const std::string summary = job.index > 0 ? "batch_" + std::to_string(job.index) + ".json" : "batch.json";
  io::write_text_atomically((out / summary).string(),
                            json{{"list", job.list_path}, {"jobs", jobs}, {"wall_s", wall_s}, {"sessions", sessions}}.dump(2));
  std::printf("%zu session(s) in %.1f s on %d job(s): %s\n", todo.size(), wall_s, jobs, (out / summary).string().c_str());
  return all_ran ? 0 : 1;
}

}  // namespace skidsim::apps
