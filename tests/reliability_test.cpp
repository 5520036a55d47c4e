// The reliability suite: hostile input against the real skidsim binary.
//
// README "Bad input": bad input gets a clear message on stderr naming the
// file (and the line, field or byte where that applies) and exit code 2;
// never a signal, a hang, unbounded memory, a half-written result or lost
// data. Every case of the generated corpus (tests/hostile_corpus.*) runs the
// binary in a fresh folder, with a wall-clock limit (a hang is a failure, not
// a speed assertion) and a memory limit, and checks:
//   - it ended by itself, not by a signal, within the limit;
//   - exit 2 for bad input (0 also where a mutation may still be valid, then
//     with a complete result; 0 for the unmutated controls);
//   - a refusal says so on stderr, naming the file (its path) and, where the
//     family has one, the attribute, field, option, line or byte;
//   - the folder is as it was after a refusal: no run directory, staging
//     folder or stray file left, and a previous run directory untouched;
//     after success only the result changed, complete.
// Then signals at seeded points of a session and a pour: the run ends and
// leaves the previous result or a complete new one, never a mixture, and
// after SIGKILL the next run succeeds and clears the stale staging folder.
//
// Environment: SKIDSIM_RELIABILITY_TIMEOUT_S (per run, default 10: the
// median case takes 0.06 s and the slowest 2.4 s on a loaded 2-core machine),
// SKIDSIM_RELIABILITY_KEEP=1 (keep each case's folder),
// SKIDSIM_RELIABILITY_RESULTS=DIR (one JSON per case: what the binary did).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/hostile_corpus.h"

namespace skidsim::reliability {

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

double case_timeout_s() {
  const char* env = std::getenv("SKIDSIM_RELIABILITY_TIMEOUT_S");
  return env && std::atof(env) > 0 ? std::atof(env) : 10.0;
}

std::string signal_name(int s) {
  switch (s) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    case SIGQUIT: return "SIGQUIT";
    case SIGKILL: return "SIGKILL";
    case SIGSEGV: return "SIGSEGV";
    case SIGABRT: return "SIGABRT";
    case SIGBUS: return "SIGBUS";
    case SIGFPE: return "SIGFPE";
    case SIGILL: return "SIGILL";
    case SIGPIPE: return "SIGPIPE";
    default: return "signal " + std::to_string(s);
  }
}

// A fresh folder per case: ROOT/case is the working directory and holds the
// inputs; ROOT/proc.out and .err the binary's output.
struct Scratch {
  fs::path root, dir;
  Scratch() {
    std::string tmpl = (fs::temp_directory_path() / "skidsim-rel-XXXXXX").string();
    char* made = ::mkdtemp(tmpl.data());
    root = fs::path(made ? made : tmpl).lexically_normal();
    dir = root / "case";
    fs::create_directories(dir);
  }
  ~Scratch() {
    const char* keep = std::getenv("SKIDSIM_RELIABILITY_KEEP");
    if (keep && std::string(keep) == "1") return;
    std::error_code ec;
    fs::remove_all(root, ec);  // links are removed, never followed
  }
  ProcessOptions options() const {
    ProcessOptions o;
    o.cwd = dir.string();
    o.log_stem = (root / "proc").string();
    o.timeout_s = case_timeout_s();
    return o;
  }
};

// Every entry under a folder (links not followed): type, size, and for
// small regular files a digest of the content.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> out;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, fs::directory_options::none, ec), end; !ec && it != end;
       it.increment(ec)) {
    const fs::path& p = it->path();
    const std::string rel = fs::relative(p, dir, ec).string();
    const fs::file_status st = fs::symlink_status(p, ec);
    std::string v;
    if (fs::is_symlink(st)) {
      v = "link " + fs::read_symlink(p, ec).string();
    } else if (fs::is_directory(st)) {
      v = "dir";
    } else if (fs::is_regular_file(st)) {
      const auto size = fs::file_size(p, ec);
      v = "file " + std::to_string(size);
      if (size <= (4u << 20)) v += " " + std::to_string(std::hash<std::string>{}(read_file(p.string())));
    } else {
      v = "special";
    }
    out[rel] = v;
  }
  return out;
}

std::string describe_diff(const std::map<std::string, std::string>& before, const std::map<std::string, std::string>& after,
                          const std::function<bool(const std::string&)>& ignore) {
  std::ostringstream s;
  int n = 0;
  for (const auto& [k, v] : after) {
    if (ignore(k)) continue;
    const auto it = before.find(k);
    if (it == before.end()) {
      if (n++ < 6) s << " new '" << k << "';";
    } else if (it->second != v) {
      if (n++ < 6) s << " changed '" << k << "';";
    }
  }
  for (const auto& [k, v] : before) {
    if (ignore(k)) continue;
    if (!after.count(k) && n++ < 6) s << " gone '" << k << "';";
  }
  if (n > 6) s << " (" << n << " in all)";
  return s.str();
}

bool has_null(const json& j) {
  if (j.is_null()) return true;
  if (j.is_structured())
    for (const auto& v : j)
      if (has_null(v)) return true;
  return false;
}

json parse_json_file(const fs::path& p) { return json::parse(read_file(p.string()), nullptr, false); }

bool nonempty_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec) && fs::file_size(p, ec) > 0;
}

// What a complete result is, per command.
enum class Result { kNone, kCheckJson, kRunDir, kPourDir, kPushDir, kDigDir, kPng, kReviewDir, kBatchDir, kViewDir };

std::string incomplete(Result kind, const fs::path& p, const std::string& stdout_text) {
  const auto need = [&](std::initializer_list<const char*> files) -> std::string {
    for (const char* f : files)
      if (!nonempty_file(p / f)) return std::string("missing or empty ") + f;
    return "";
  };
  switch (kind) {
    case Result::kNone: return "";
    case Result::kCheckJson: {
      const json j = json::parse(stdout_text, nullptr, false);
      if (j.is_discarded()) return "stdout is not JSON";
      if (has_null(j)) return "stdout JSON holds null (a non-finite figure)";
      return "";
    }
    case Result::kRunDir: {
      if (const std::string m = need({"report.json", "report.html", "session.lcmlog"}); !m.empty()) return m;
      const json r = parse_json_file(p / "report.json");
      if (r.is_discarded() || !r.is_object()) return "report.json does not parse";
      if (!r.contains("end_reason") || !r["end_reason"].is_string()) return "report.json has no end_reason";
      return "";
    }
    case Result::kPourDir: {
      if (const std::string m = need({"summary.json", "terrain_surface.json", "terrain_surface.png",
                                      "terrain_material.json", "terrain_material.png"});
          !m.empty())
        return m;
      return parse_json_file(p / "summary.json").is_discarded() ? "summary.json does not parse" : "";
    }
    case Result::kPushDir: {
      if (const std::string m = need({"summary.json", "resistance.csv", "terrain_surface.json", "terrain_surface.png"});
          !m.empty())
        return m;
      return parse_json_file(p / "summary.json").is_discarded() ? "summary.json does not parse" : "";
    }
    case Result::kDigDir: {
      if (const std::string m = need({"summary.json", "phases.csv", "terrain_surface.json", "terrain_surface.png",
                                      "truck_material.json", "truck_material.png"});
          !m.empty())
        return m;
      return parse_json_file(p / "summary.json").is_discarded() ? "summary.json does not parse" : "";
    }
    case Result::kPng: {
      const std::string s = read_file(p.string());
      return s.size() > 8 && s.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0 ? "" : "not a PNG";
    }
    case Result::kReviewDir: return need({"review.html", "contact_sheet.png"});
    case Result::kViewDir: {
      if (const std::string m = need({"frames/frames.json", "frames/frame_000000.png"}); !m.empty()) return m;
      return parse_json_file(p / "frames" / "frames.json").is_discarded() ? "frames.json does not parse" : "";
    }
    case Result::kBatchDir: {
      std::error_code ec;
      for (const auto& e : fs::directory_iterator(p, ec)) {
        const std::string n = e.path().filename().string();
        if (n.rfind("batch", 0) == 0 && n.size() > 5 && n.substr(n.size() - 5) == ".json")
          return parse_json_file(e.path()).is_discarded() ? n + " does not parse" : "";
      }
      return "no batch*.json";
    }
  }
  return "";
}

// How a case runs: the command, the paths a refusal must name (any one),
// where the result goes (relative to the case folder) and what it is.
struct Invocation {
  std::vector<std::string> argv;
  std::vector<std::string> named;
  // The other input files of the case (a URDF's parameter file): a value
  // that may be valid can be refused where it is used, naming that file.
  std::vector<std::string> related;
  std::string result;  // "" none
  Result kind = Result::kNone;
};

std::string substitute(std::string s, const fs::path& dir) {
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"{SRC}", source_dir()}, {"{DIR}", dir.string()}})
    for (std::size_t k; (k = s.find(key)) != std::string::npos;) s.replace(k, key.size(), value);
  return s;
}

void place(const Case& c, const fs::path& path) {
  std::error_code ec;
  switch (c.stand) {
    case Stand::kBytes: write_file(path.string(), c.bytes()); break;
    case Stand::kSparse:
      write_file(path.string(), c.bytes());
      if (::truncate(path.c_str(), static_cast<off_t>(c.sparse_bytes)) != 0) ADD_FAILURE() << "truncate " << path;
      break;
    case Stand::kDirectory: fs::create_directory(path, ec); break;
    case Stand::kDevZero: fs::create_symlink("/dev/zero", path, ec); break;
    case Stand::kEmpty: write_file(path.string(), ""); break;
    case Stand::kFifo:
      if (::mkfifo(path.c_str(), 0644) != 0) ADD_FAILURE() << "mkfifo " << path;
      break;
    case Stand::kMissing: break;
    case Stand::kSymlinkLoop: fs::create_symlink(path.filename(), path, ec); break;
  }
}

void copy_tree(const fs::path& from, const fs::path& to) {
  fs::copy(from, to, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
}

void link_loader(const fs::path& dir, bool params, bool urdf) {
  const fs::path assets = fs::path(source_dir()) / "assets" / "loader";
  if (params) fs::copy_file(assets / "skidsteer.params.xml", dir / "skidsteer.params.xml");
  if (urdf) fs::copy_file(assets / "skidsteer.urdf", dir / "skidsteer.urdf");
}

Result result_of(const std::string& subcommand) {
  if (subcommand == "pour") return Result::kPourDir;
  if (subcommand == "push") return Result::kPushDir;
  if (subcommand == "dig") return Result::kDigDir;
  if (subcommand == "run") return Result::kRunDir;
  if (subcommand == "render") return Result::kPng;
  if (subcommand == "review") return Result::kReviewDir;
  if (subcommand == "batch") return Result::kBatchDir;
  if (subcommand == "view") return Result::kViewDir;
  return Result::kNone;
}

Invocation set_up(const Case& c, const fs::path& dir) {
  Invocation inv;
  const std::string bin = binary_path(), src = source_dir();
  const fs::path out = dir / "out";
  switch (c.format) {
    case Format::kExercise: {
      const std::string name = fs::path(c.companion.empty() ? c.base : c.companion).filename().string();
      for (const auto& e : fs::directory_iterator(fs::path(src) / "scenarios"))
        if (e.path().filename() != name) fs::create_symlink(e.path(), dir / e.path().filename());
      place(c, dir / name);
      inv.argv = {bin, "check", (dir / name).string(), "--json"};
      inv.named = {(dir / name).string()};
      inv.kind = Result::kCheckJson;
      break;
    }
    case Format::kScript: {
      const std::string name = fs::path(c.companion.empty() ? c.base : c.companion).filename().string();
      const std::string exercise = src + "/scenarios/" + name.substr(0, name.find('.')) + ".xml";
      place(c, dir / name);
      inv.argv = {bin, "run", exercise, "--script", (dir / name).string(), "--max-s", "0.3", "--out", out.string()};
      inv.named = {(dir / name).string()};
      inv.result = "out";
      inv.kind = Result::kRunDir;
      break;
    }
    case Format::kSoilTable: {
      place(c, dir / "soils.xml");
      inv.argv = {bin, "pour", "--soil-table", (dir / "soils.xml").string()};
      if (!c.soil_id.empty()) inv.argv.insert(inv.argv.end(), {"--soil", c.soil_id});
      inv.argv.insert(inv.argv.end(), {"--site-m", "1", "--cell-m", "0.05", "--pour-s", "0.3", "--rate-kg-s", "20",
                                       "--settle-s", "0.5", "--out", out.string()});
      inv.named = {(dir / "soils.xml").string()};
      inv.result = "out";
      inv.kind = Result::kPourDir;
      break;
    }
    case Format::kLoaderParams:
    case Format::kUrdf:
    case Format::kMesh: {
      const fs::path meshes = fs::path(src) / "assets" / "loader" / "meshes";
      link_loader(dir, c.format != Format::kLoaderParams, c.format != Format::kUrdf);
      if (c.format == Format::kMesh) {
        fs::create_directory(dir / "meshes");
        for (const auto& e : fs::directory_iterator(meshes))
          if (e.path().filename() != "chassis.obj") fs::create_symlink(e.path(), dir / "meshes" / e.path().filename());
        if (::mkfifo((dir / "meshes" / "zz_fifo.mtl").c_str(), 0644) != 0) ADD_FAILURE() << "mkfifo";
        place(c, dir / "meshes" / "chassis.obj");
        inv.named = {(dir / "meshes" / "chassis.obj").string()};
      } else {
        fs::create_symlink(meshes, dir / "meshes");
        const fs::path mutated = dir / (c.format == Format::kUrdf ? "skidsteer.urdf" : "skidsteer.params.xml");
        place(c, mutated);
        inv.named = {mutated.string()};
      }
      inv.related = {(dir / "skidsteer.params.xml").string(), (dir / "skidsteer.urdf").string()};
      inv.argv = {bin, "check", (dir / "skidsteer.params.xml").string(), "--json"};
      inv.kind = Result::kCheckJson;
      break;
    }
    case Format::kHeightmapJson:
    case Format::kHeightmapPng: {
      const Artifacts& a = artifacts();
      const fs::path json_path = dir / "terrain_material.json", png_path = dir / "terrain_material.png";
      if (c.format == Format::kHeightmapJson) {
        fs::copy_file(a.heightmap_png, png_path);
        place(c, json_path);
        inv.named = {json_path.string()};
        if (c.stand == Stand::kBytes) {  // an image field that changed may be named as the image
          const json m = json::parse(c.bytes(), nullptr, false);
          const std::string image = m.is_object() && m.contains("image") && m["image"].is_string() ? m["image"].get<std::string>() : "";
          if (!image.empty()) inv.named.push_back(image[0] == '/' ? image : (dir / image).string());
        }
      } else {
        fs::copy_file(a.heightmap_json, json_path);
        place(c, png_path);
        inv.named = {png_path.string()};
      }
      inv.argv = {bin, "pour", "--material-map", json_path.string(), "--pour-s", "0", "--settle-s", "0.3", "--out",
                  out.string()};
      inv.result = "out";
      inv.kind = Result::kPourDir;
      break;
    }
    case Format::kLcmLog: {
      place(c, dir / "session.lcmlog");
      inv.argv = {bin, "run", src + "/scenarios/grading.xml", "--replay", (dir / "session.lcmlog").string(), "--out",
                  out.string()};
      inv.named = {(dir / "session.lcmlog").string()};
      inv.result = "out";
      inv.kind = Result::kRunDir;
      break;
    }
    case Format::kCli: {
      bool needs_run = false;
      for (const std::string& a : c.args) needs_run = needs_run || a.rfind("{DIR}/run", 0) == 0;
      if (needs_run) copy_tree(artifacts().run_dir, dir / "run");
      if (!c.args.empty() && c.args.front() == "batch")
        write_file((dir / "list.txt").string(), src + "/scenarios/grading.xml --script " + src +
                                                    "/scenarios/grading.operator.xml --max-s 0.3\n");
      inv.argv = {bin};
      for (const std::string& a : c.args) inv.argv.push_back(substitute(a, dir));
      const std::string sub = c.args.empty() ? "" : c.args.front();
      inv.kind = result_of(sub);
      inv.result = sub == "render" ? "frame.png" : sub == "review" ? "run" : inv.kind == Result::kNone ? "" : "out";
      break;
    }
  }
  return inv;
}

// A previous result in the run directory, for half the cases (by name):
// a failed run must leave it exactly as it was.
bool with_previous(const std::string& name) { return std::hash<std::string>{}(name) % 2 == 1; }

void write_previous(const fs::path& out) {
  fs::create_directories(out);
  // A run directory skidsim wrote carries its marker (io/run_directory.h):
  // without it --out would rightly refuse the folder.
  write_file((out / ".skidsim-run").string(), "{\"skidsim_run_directory\": 1, \"command\": \"run\"}\n");
  write_file((out / "report.json").string(), "{\"previous\": true}\n");
  write_file((out / "summary.json").string(), "{\"previous\": true}\n");
  write_file((out / "previous.txt").string(), "a previous run's result\n");
}

bool names_any(const std::string& err, const std::vector<std::string>& paths) {
  for (const std::string& p : paths) {
    if (err.find(p) != std::string::npos) return true;
    std::error_code ec;
    const std::string canonical = fs::weakly_canonical(p, ec).string();
    if (!ec && !canonical.empty() && err.find(canonical) != std::string::npos) return true;
  }
  return false;
}

bool says_where(const std::string& err, const Case& c) {
  if (c.where.empty() && c.lines.empty()) return true;
  for (const std::string& w : c.where)
    if (!w.empty() && err.find(w) != std::string::npos) return true;
  for (int line : c.lines) {
    const std::string l = std::to_string(line);
    for (const std::string& form : {":" + l + ":", ":" + l + " ", "line " + l, "Line number=" + l, "line=" + l})
      if (err.find(form) != std::string::npos) return true;
  }
  return false;
}

// Library text where a message should be (an exception's what() passed on).
std::string library_text(const std::string& err) {
  for (const char* s : {"std::", "basic_string", "bad_alloc", "vector::", "filesystem error", "stoi", "stod",
                        "terminate called"})
    if (err.find(s) != std::string::npos) return s;
  return "";
}

std::string excerpt(const std::string& s, std::size_t n = 400) {
  std::string e = s.size() > n ? s.substr(0, n) + "..." : s;
  for (char& ch : e)
    if (static_cast<unsigned char>(ch) < 0x20 && ch != '\n') ch = '?';
  return e;
}

std::string command_line(const std::vector<std::string>& argv) {
  std::string s;
  for (const std::string& a : argv) {
    if (!s.empty()) s += ' ';
    s += a.find_first_of(" ;'\"") == std::string::npos && !a.empty() ? a : "'" + a + "'";
  }
  return s;
}

// With SKIDSIM_RELIABILITY_RESULTS=DIR, one case's record (what it was and
// what the binary did) as DIR/FILE.json, for scripts/reliability_report.py.
void write_record(const std::string& file, json j, const ProcessResult& r, const std::vector<std::string>& failures) {
  const char* dir = std::getenv("SKIDSIM_RELIABILITY_RESULTS");
  if (!dir) return;
  j["exit_code"] = r.exit_code;
  j["signal"] = r.signaled ? signal_name(r.signal) : "";
  j["timed_out"] = r.timed_out;
  j["wall_s"] = r.wall_s;
  j["max_rss_kb"] = r.max_rss_kb;
  j["stderr"] = excerpt(r.err, 600);
  j["failures"] = failures;
  std::error_code ec;
  fs::create_directories(dir, ec);
  write_file((fs::path(dir) / (file + ".json")).string(), j.dump(1, ' ', false, json::error_handler_t::replace));
}

void record(const Case& c, const Invocation& inv, const ProcessResult& r, const std::vector<std::string>& failures) {
  json j = {{"name", c.name},
            {"format", format_name(c.format)},
            {"family", c.family},
            {"expect", expect_name(c.expect)},
            {"base", c.base},
            {"what", c.what},
            {"command", command_line(inv.argv)}};
  write_record(c.name, j, r, failures);
}

class Hostile : public ::testing::TestWithParam<Case> {};

TEST_P(Hostile, Input) {
  const Case& c = GetParam();
  ASSERT_TRUE(artifacts().error.empty()) << artifacts().error;
  Scratch s;
  const Invocation inv = set_up(c, s.dir);
  const bool run_directory = inv.kind == Result::kRunDir || inv.kind == Result::kPourDir ||
                             inv.kind == Result::kPushDir || inv.kind == Result::kDigDir;
  if (run_directory && inv.result == "out" && with_previous(c.name)) write_previous(s.dir / "out");
  const auto before = snapshot(s.dir);
  const ProcessResult r = run_process(inv.argv, s.options());
  const auto after = snapshot(s.dir);

  std::vector<std::string> failures;
  const auto fail = [&](const std::string& m) { failures.push_back(m); };
  if (!r.started) fail("could not start the binary");
  if (r.timed_out) {
    fail("hang: still running after " + std::to_string(static_cast<int>(case_timeout_s())) + " s (killed)");
  } else if (r.signaled) {
    fail("killed by " + signal_name(r.signal));
  } else if (r.started) {
    const bool ok_code =
        !c.ok_codes.empty()             ? std::find(c.ok_codes.begin(), c.ok_codes.end(), r.exit_code) != c.ok_codes.end()
        : c.expect == Expect::kRefused  ? r.exit_code == 2
        : c.expect == Expect::kAccepted ? r.exit_code == 0
                                        : (r.exit_code == 0 || r.exit_code == 2);
    if (!ok_code)
      fail("exit " + std::to_string(r.exit_code) + ", expected " +
           (c.expect == Expect::kRefused ? "2" : c.expect == Expect::kAccepted ? "0" : "0 or 2"));
    if (r.exit_code != 0) {
      if (r.err.find_first_not_of(" \n\t") == std::string::npos) {
        fail("nothing on stderr");
      } else {
        std::vector<std::string> named = inv.named;
        if (c.expect != Expect::kRefused) named.insert(named.end(), inv.related.begin(), inv.related.end());
        if (!named.empty() && !names_any(r.err, named)) fail("stderr does not name the file " + inv.named.front());
        // Where: for bad input; a value that may be valid can be refused
        // for what it leads to, elsewhere.
        if (c.expect == Expect::kRefused && !says_where(r.err, c)) {
          std::string w;
          for (const std::string& x : c.where) w += (w.empty() ? "" : "/") + x;
          for (int l : c.lines) w += (w.empty() ? "line " : "/line ") + std::to_string(l);
          fail("stderr does not say where (" + w + ")");
        }
        if (c.byte_offset && r.err.find("byte") == std::string::npos) fail("stderr does not name the byte");
        if (const std::string lib = library_text(r.err); !lib.empty())
          fail("stderr is a library's text (" + lib + "), not a message");
      }
    }
  }
  // The folder: unchanged after anything but success; after success only
  // the result, complete.
  const std::string result = inv.result;
  const bool success = r.started && !r.timed_out && !r.signaled && r.exit_code == 0;
  const auto in_result = [&](const std::string& k) {
    return success && !result.empty() && (k == result || k.rfind(result + "/", 0) == 0);
  };
  if (const std::string d = describe_diff(before, after, in_result); !d.empty())
    fail(std::string(success ? "besides the result," : "left behind after a failure:") + d);
  if (success) {
    const fs::path where = result.empty() ? s.dir : s.dir / result;
    if (const std::string m = incomplete(inv.kind, where, r.out); !m.empty()) fail("exit 0 but the result is incomplete: " + m);
    if (run_directory && fs::exists(s.dir / "out" / "previous.txt"))
      fail("exit 0 but the previous run directory's files are still mixed in");
  }
  record(c, inv, r, failures);
  if (!failures.empty()) {
    std::ostringstream m;
    m << c.name << " [" << format_name(c.format) << "/" << c.family << ", expected " << expect_name(c.expect)
      << "]: " << c.what << "\n  base: " << c.base << "\n  command: " << command_line(inv.argv) << "\n  exit "
      << r.exit_code << (r.signaled ? ", " + signal_name(r.signal) : "") << (r.timed_out ? ", timed out" : "")
      << ", " << r.wall_s << " s, max RSS " << r.max_rss_kb / 1024 << " MiB\n  stderr: " << excerpt(r.err) << "\n";
    for (const std::string& f : failures) m << "  FAIL: " << f << "\n";
    ADD_FAILURE() << m.str();
  }
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) { return info.param.name; }

INSTANTIATE_TEST_SUITE_P(Corpus, Hostile, ::testing::ValuesIn(corpus()), case_name);

// ---------------------------------------------------------------------------
// Signals at seeded points.

struct SignalCase {
  std::string name;
  std::string job;  // "run" or "pour"
  int signal = SIGINT;
  double delay_s = 0.0;
  bool previous = false;
};

void PrintTo(const SignalCase& c, std::ostream* os) { *os << c.name; }

// Seeded delays: the same points every time the suite runs.
double seeded_delay_s(std::uint32_t seed, double max_s) {
  std::uint64_t x = seed + 0x9e3779b97f4a7c15ull;  // splitmix64
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  x ^= x >> 31;
  return max_s * static_cast<double>(x >> 11) / static_cast<double>(1ull << 53);
}

std::vector<SignalCase> signal_cases() {
  std::vector<SignalCase> out;
  std::uint32_t seed = 1;
  for (const char* job : {"run", "pour"}) {
    const int seeds = std::string(job) == "run" ? 4 : 3;
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT})
      for (int k = 0; k < seeds; ++k, ++seed) {
        SignalCase c;
        c.job = job;
        c.signal = sig;
        c.delay_s = seeded_delay_s(seed, 0.45);
        c.previous = seed % 2 == 0;
        c.name = std::string(job) + "_" + signal_name(sig) + "_seed" + std::to_string(seed) + "_at_" +
                 std::to_string(static_cast<int>(c.delay_s * 1000)) + "ms" + (c.previous ? "_over_previous" : "");
        out.push_back(c);
      }
    for (int k = 0; k < (std::string(job) == "run" ? 6 : 4); ++k, ++seed) {
      SignalCase c;
      c.job = job;
      c.signal = SIGKILL;
      c.delay_s = seeded_delay_s(seed, 0.5);
      c.previous = true;
      c.name = std::string(job) + "_SIGKILL_seed" + std::to_string(seed) + "_at_" +
               std::to_string(static_cast<int>(c.delay_s * 1000)) + "ms_over_previous";
      out.push_back(c);
    }
  }
  return out;
}

std::vector<std::string> job_argv(const std::string& job, const fs::path& out) {
  const std::string src = source_dir();
  if (job == "run")
    return {binary_path(), "run", src + "/scenarios/grading.xml", "--script", src + "/scenarios/grading.operator.xml",
            "--out", out.string()};
  return {binary_path(), "pour", "--pour-s", "25", "--out", out.string()};  // about 0.6 s
}

std::vector<std::string> staging_left(const fs::path& dir) {
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.rfind("out.", 0) == 0 || (n != "out" && n.rfind("out", 0) == 0)) left.push_back(n);
  }
  return left;
}

class Signals : public ::testing::TestWithParam<SignalCase> {};

TEST_P(Signals, LeaveOldOrCompleteNew) {
  const SignalCase& c = GetParam();
  ASSERT_TRUE(artifacts().error.empty()) << artifacts().error;
  Scratch s;
  const fs::path out = s.dir / "out";
  const Result kind = c.job == "run" ? Result::kRunDir : Result::kPourDir;
  if (c.previous) {
    copy_tree(c.job == "run" ? artifacts().run_dir : artifacts().pour_dir, out);
    write_file((out / "previous.txt").string(), "a previous run's result\n");
  }
  const std::vector<std::string> argv = job_argv(c.job, out);
  const Child child = start_process(argv, s.options());
  const timespec nap{static_cast<time_t>(c.delay_s), static_cast<long>((c.delay_s - static_cast<double>(static_cast<time_t>(c.delay_s))) * 1e9)};
  ::nanosleep(&nap, nullptr);
  ::kill(child.pid, c.signal);
  const ProcessResult r = finish_process(child);

  std::vector<std::string> failures;
  const auto fail = [&](const std::string& m) { failures.push_back(m); };
  if (r.timed_out) fail("hang: still running " + std::to_string(static_cast<int>(case_timeout_s())) + " s after " +
                        signal_name(c.signal));
  if (r.signaled && r.signal != c.signal) fail("killed by " + signal_name(r.signal) + " (sent " + signal_name(c.signal) + ")");
  const bool exists = fs::exists(out);
  const bool old = exists && fs::exists(out / "previous.txt");
  const std::string bad = exists ? incomplete(kind, out, "") : "";
  if (c.signal == SIGKILL) {
    if (!exists) fail("after SIGKILL the run directory is gone (the previous result lost)");
    else if (!bad.empty()) fail("after SIGKILL the run directory is incomplete: " + bad);
  } else {
    if (exists && !bad.empty()) fail("the run directory is incomplete: " + bad);
    if (c.previous && !exists) fail("the previous result is gone and no new one was written");
    if (exists && !old && kind == Result::kRunDir && bad.empty()) {
      const json report = parse_json_file(out / "report.json");
      const std::string reason = report.value("end_reason", "");
      if (reason != "interrupted" && reason != "tasks_done" && reason != "script_done")
        fail("a new report with end_reason '" + reason + "' (expected interrupted, or the session's own end)");
    }
    if (const auto left = staging_left(s.dir); !left.empty()) fail("left behind: " + left.front());
  }
  // After SIGKILL the next run must succeed and clear what the killed one left.
  if (c.signal == SIGKILL && !r.timed_out) {
    const ProcessResult again = run_process(argv, s.options());
    if (again.timed_out || again.signaled || again.exit_code != 0) {
      fail("the next run after SIGKILL failed: exit " + std::to_string(again.exit_code) +
           (again.signaled ? " " + signal_name(again.signal) : "") + (again.timed_out ? " (timed out)" : "") + ": " +
           excerpt(again.err, 300));
    } else {
      if (const std::string m = incomplete(kind, out, ""); !m.empty()) fail("the next run's result is incomplete: " + m);
      if (fs::exists(out / "previous.txt")) fail("the next run's result is mixed with the previous one");
      if (const auto left = staging_left(s.dir); !left.empty())
        fail("the next run left the killed run's staging behind: " + left.front());
    }
  }
  {
    json j = {{"name", "signal_" + c.name},
              {"format", "signal"},
              {"family", c.signal == SIGKILL ? "sigkill" : "signal"},
              {"expect", "old or complete new"},
              {"what", signal_name(c.signal) + " after " + std::to_string(static_cast<int>(c.delay_s * 1000)) + " ms" +
                           (c.previous ? ", a previous result in the run directory" : "")},
              {"command", command_line(argv) + "  # " + signal_name(c.signal) + " after " +
                              std::to_string(static_cast<int>(c.delay_s * 1000)) + " ms"}};
    write_record("signal_" + c.name, j, r, failures);
  }
  if (!failures.empty()) {
    std::ostringstream m;
    m << c.name << ": " << signal_name(c.signal) << " after " << c.delay_s << " s\n  command: " << command_line(argv)
      << "\n  exit " << r.exit_code << (r.signaled ? ", " + signal_name(r.signal) : "") << ", " << r.wall_s
      << " s\n  stderr: " << excerpt(r.err) << "\n";
    for (const std::string& f : failures) m << "  FAIL: " << f << "\n";
    ADD_FAILURE() << m.str();
  }
}

std::string signal_case_name(const ::testing::TestParamInfo<SignalCase>& info) { return info.param.name; }

INSTANTIATE_TEST_SUITE_P(Seeded, Signals, ::testing::ValuesIn(signal_cases()), signal_case_name);

// ---------------------------------------------------------------------------
// The corpus's size, per format and family (the README quotes it).

TEST(CorpusCounts, PerFormatAndFamily) {
  EXPECT_TRUE(artifacts().error.empty()) << artifacts().error;
  std::map<std::string, int> per_format;
  std::map<std::string, std::map<std::string, int>> per_family;
  std::map<std::string, int> per_expect;
  for (const Case& c : corpus()) {
    ++per_format[format_name(c.format)];
    ++per_family[format_name(c.format)][c.family];
    ++per_expect[expect_name(c.expect)];
  }
  const std::size_t signals = signal_cases().size();
  std::printf("reliability corpus: %zu input cases + %zu signal cases\n", corpus().size(), signals);
  for (Format f : all_formats()) {
    const std::string name = format_name(f);
    std::printf("  %-15s %4d:", name.c_str(), per_format[name]);
    for (const auto& [family, n] : per_family[name]) std::printf(" %s %d,", family.c_str(), n);
    std::printf("\n");
    EXPECT_GE(per_format[name], 10) << name << ": the corpus lost this format (an artifact missing?)";
  }
  std::printf("  expected: refused %d, either %d, accepted (controls) %d\n", per_expect["refused"],
              per_expect["either"], per_expect["accepted"]);
  EXPECT_GE(corpus().size(), 500u);
}

}  // namespace
}  // namespace skidsim::reliability
