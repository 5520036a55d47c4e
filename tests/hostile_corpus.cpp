// The hostile-input corpus: mutation families over the shipped files and the
// binary's own outputs (see hostile_corpus.h).
#include "tests/hostile_corpus.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>

namespace skidsim::reliability {

namespace fs = std::filesystem;
using nlohmann::json;

std::string binary_path() { return SKIDSIM_BINARY; }
std::string source_dir() { return SKIDSIM_SOURCE_DIR; }

const char* format_name(Format f) {
  switch (f) {
    case Format::kExercise: return "exercise";
    case Format::kScript: return "script";
    case Format::kSoilTable: return "soil_table";
    case Format::kLoaderParams: return "loader_params";
    case Format::kUrdf: return "urdf";
    case Format::kMesh: return "mesh";
    case Format::kHeightmapJson: return "heightmap_json";
    case Format::kHeightmapPng: return "heightmap_png";
    case Format::kLcmLog: return "lcm_log";
    case Format::kCli: return "cli";
  }
  return "?";
}

const std::vector<Format>& all_formats() {
  static const std::vector<Format> formats = {Format::kExercise,      Format::kScript,        Format::kSoilTable,
                                              Format::kLoaderParams,  Format::kUrdf,          Format::kMesh,
                                              Format::kHeightmapJson, Format::kHeightmapPng,  Format::kLcmLog,
                                              Format::kCli};
  return formats;
}

const char* expect_name(Expect e) {
  switch (e) {
    case Expect::kRefused: return "refused";
    case Expect::kEither: return "either";
    case Expect::kAccepted: return "accepted";
  }
  return "?";
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// ---------------------------------------------------------------------------
// Processes

double monotonic_s() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

Child start_process(const std::vector<std::string>& argv, const ProcessOptions& options) {
  Child child;
  child.options = options;
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const std::string out_path = options.log_stem + ".out", err_path = options.log_stem + ".err";
  child.start_s = monotonic_s();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    rlimit as{static_cast<rlim_t>(options.memory_limit_bytes), static_cast<rlim_t>(options.memory_limit_bytes)};
    ::setrlimit(RLIMIT_AS, &as);
    rlimit core{0, 0};
    ::setrlimit(RLIMIT_CORE, &core);
    for (int s : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGCHLD}) ::signal(s, SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    if (::chdir(options.cwd.c_str()) != 0) ::_exit(126);
    const int in = ::open("/dev/null", O_RDONLY);
    const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (in < 0 || out < 0 || err < 0) ::_exit(126);
    ::dup2(in, 0);
    ::dup2(out, 1);
    ::dup2(err, 2);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  if (pid > 0) ::setpgid(pid, pid);  // both sides, so that a kill of the group never misses
  child.pid = pid;
  return child;
}

ProcessResult finish_process(const Child& child) {
  ProcessResult r;
  if (child.pid <= 0) return r;
  r.started = true;
  int status = 0;
  rusage usage{};
  const double deadline = child.start_s + child.options.timeout_s;
  for (;;) {
    const pid_t done = ::wait4(child.pid, &status, WNOHANG, &usage);
    if (done == child.pid) break;
    if (monotonic_s() > deadline) {
      r.timed_out = true;
      ::kill(-child.pid, SIGKILL);
      ::kill(child.pid, SIGKILL);
      ::wait4(child.pid, &status, 0, &usage);
      break;
    }
    const timespec nap{0, 2'000'000};
    ::nanosleep(&nap, nullptr);
  }
  ::kill(-child.pid, SIGKILL);  // whatever the process left running in its group
  r.wall_s = monotonic_s() - child.start_s;
  r.max_rss_kb = usage.ru_maxrss;
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) {
    r.signaled = true;
    r.signal = WTERMSIG(status);
  }
  r.out = read_file(child.options.log_stem + ".out");
  r.err = read_file(child.options.log_stem + ".err");
  return r;
}

ProcessResult run_process(const std::vector<std::string>& argv, const ProcessOptions& options) {
  return finish_process(start_process(argv, options));
}

// ---------------------------------------------------------------------------
// Artifacts: a small pour and two short sessions, made by the binary under
// test once per build of it (the cache's stamp is the binary's size and
// modification time), under a lock so that parallel tests share them.

namespace {

std::string binary_stamp() {
  struct stat st{};
  if (::stat(binary_path().c_str(), &st) != 0) return "";
  return std::to_string(st.st_size) + " " + std::to_string(st.st_mtim.tv_sec) + "." +
         std::to_string(st.st_mtim.tv_nsec);
}

bool make_run_dir(const std::vector<std::string>& args, const fs::path& cache, const std::string& name,
                  std::string& error) {
  std::vector<std::string> argv = {binary_path()};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.push_back("--out");
  argv.push_back((cache / name).string());
  ProcessOptions o;
  o.cwd = cache.string();
  o.log_stem = (cache / (name + "_log")).string();
  o.timeout_s = 120;
  const ProcessResult r = run_process(argv, o);
  if (r.exit_code != 0) {
    error += "could not make " + name + " (exit " + std::to_string(r.exit_code) + "): " + r.err + "\n";
    return false;
  }
  return true;
}

}  // namespace

const Artifacts& artifacts() {
  static const Artifacts made = [] {
    Artifacts a;
    const fs::path cache = SKIDSIM_RELIABILITY_CACHE;
    std::error_code ec;
    fs::create_directories(cache, ec);
    const int lock = ::open((cache / ".lock").c_str(), O_RDWR | O_CREAT, 0644);
    if (lock >= 0) ::flock(lock, LOCK_EX);
    const std::string stamp = binary_stamp();
    const std::string src = source_dir();
    if (read_file((cache / "stamp").string()) != stamp || stamp.empty()) {
      fs::remove(cache / "stamp", ec);
      for (const char* d : {"pour", "run_grading", "run_driving"}) fs::remove_all(cache / d, ec);
      bool ok = make_run_dir({"pour", "--site-m", "1", "--cell-m", "0.05", "--pour-s", "0.5", "--rate-kg-s", "20",
                              "--hopper-m", "0.1", "--settle-s", "1"},
                             cache, "pour", a.error);
      ok = make_run_dir({"run", src + "/scenarios/grading.xml", "--script", src + "/scenarios/grading.operator.xml",
                         "--max-s", "1"},
                        cache, "run_grading", a.error) && ok;
      ok = make_run_dir({"run", src + "/scenarios/driving_course.xml", "--script",
                         src + "/scenarios/driving_course.operator.xml", "--max-s", "1"},
                        cache, "run_driving", a.error) && ok;
      if (ok) write_file((cache / "stamp").string(), stamp);
    }
    if (lock >= 0) ::close(lock);
    a.pour_dir = (cache / "pour").string();
    a.heightmap_json = (cache / "pour" / "terrain_material.json").string();
    a.heightmap_png = (cache / "pour" / "terrain_material.png").string();
    a.run_dir = (cache / "run_grading").string();
    a.log = (cache / "run_grading" / "session.lcmlog").string();
    a.other_log = (cache / "run_driving" / "session.lcmlog").string();
    for (const std::string& f : {a.heightmap_json, a.heightmap_png, a.log, a.other_log})
      if (!fs::is_regular_file(f)) a.error += "missing artifact " + f + "\n";
    return a;
  }();
  return made;
}

// ---------------------------------------------------------------------------
// A small XML lexer that keeps byte offsets, so mutations splice the file's
// own text (its lines, comments and layout stay as they were).

namespace {

struct XmlAttr {
  std::string name, value;
  std::size_t name_begin = 0, value_begin = 0, value_end = 0;
  int line = 0;
};

struct XmlElement {
  std::string name;
  std::size_t begin = 0;        // '<'
  std::size_t tag_end = 0;      // after the start tag's '>'
  std::size_t end = 0;          // after the end tag's '>' (== tag_end when self-closing)
  std::size_t close_begin = 0;  // the end tag's '<' (== begin when self-closing)
  bool self_closing = false;
  int line = 0;
  int parent = -1;
  std::vector<XmlAttr> attrs;
};

struct XmlDoc {
  std::vector<XmlElement> elements;  // in document order; [0] is the root
  std::size_t comment_begin = std::string::npos;  // the first comment's "<!--"
};

XmlDoc lex_xml(const std::string& t) {
  XmlDoc doc;
  std::vector<int> line_at(t.size() + 1, 1);
  for (std::size_t i = 0, line = 1; i <= t.size(); ++i) {
    line_at[i] = static_cast<int>(line);
    if (i < t.size() && t[i] == '\n') ++line;
  }
  std::vector<int> stack;
  std::size_t i = 0;
  const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  while (i < t.size()) {
    if (t[i] != '<') {
      ++i;
      continue;
    }
    if (t.compare(i, 4, "<!--") == 0) {
      if (doc.comment_begin == std::string::npos) doc.comment_begin = i;
      const std::size_t j = t.find("-->", i + 4);
      i = j == std::string::npos ? t.size() : j + 3;
    } else if (t.compare(i, 2, "<?") == 0) {
      const std::size_t j = t.find("?>", i + 2);
      i = j == std::string::npos ? t.size() : j + 2;
    } else if (t.compare(i, 9, "<![CDATA[") == 0) {
      const std::size_t j = t.find("]]>", i + 9);
      i = j == std::string::npos ? t.size() : j + 3;
    } else if (t.compare(i, 2, "<!") == 0) {
      const std::size_t j = t.find('>', i);
      i = j == std::string::npos ? t.size() : j + 1;
    } else if (t.compare(i, 2, "</") == 0) {
      const std::size_t j = t.find('>', i);
      if (!stack.empty()) {
        XmlElement& e = doc.elements[static_cast<std::size_t>(stack.back())];
        e.close_begin = i;
        e.end = j == std::string::npos ? t.size() : j + 1;
        stack.pop_back();
      }
      i = j == std::string::npos ? t.size() : j + 1;
    } else {
      XmlElement e;
      e.begin = i;
      e.line = line_at[i];
      e.parent = stack.empty() ? -1 : stack.back();
      std::size_t p = i + 1;
      while (p < t.size() && !is_space(t[p]) && t[p] != '/' && t[p] != '>') ++p;
      e.name = t.substr(i + 1, p - i - 1);
      for (;;) {
        while (p < t.size() && is_space(t[p])) ++p;
        if (p >= t.size()) break;
        if (t[p] == '/') {
          e.self_closing = true;
          p = t.find('>', p);
          p = p == std::string::npos ? t.size() : p + 1;
          break;
        }
        if (t[p] == '>') {
          ++p;
          break;
        }
        XmlAttr a;
        a.name_begin = p;
        a.line = line_at[p];
        while (p < t.size() && t[p] != '=' && !is_space(t[p])) ++p;
        a.name = t.substr(a.name_begin, p - a.name_begin);
        while (p < t.size() && t[p] != '"' && t[p] != '\'') ++p;
        if (p >= t.size()) break;
        const char quote = t[p];
        a.value_begin = p + 1;
        a.value_end = t.find(quote, a.value_begin);
        if (a.value_end == std::string::npos) a.value_end = t.size();
        a.value = t.substr(a.value_begin, a.value_end - a.value_begin);
        p = a.value_end + 1;
        e.attrs.push_back(a);
      }
      e.tag_end = p;
      if (e.self_closing) {
        e.end = p;
        e.close_begin = e.begin;
      }
      doc.elements.push_back(e);
      if (!e.self_closing) stack.push_back(static_cast<int>(doc.elements.size() - 1));
      i = p;
    }
  }
  return doc;
}

// The numbers of an attribute value ("20 12", "30 10.2; 20 10.2"): their
// spans, when the value is nothing but numbers and separators.
struct Span {
  std::size_t begin, end;
};
std::vector<Span> number_tokens(const std::string& v) {
  std::vector<Span> out;
  std::size_t i = 0;
  while (i < v.size()) {
    const char c = v[i];
    if (c == ' ' || c == '\t' || c == '\n' || c == ';' || c == ',') {
      ++i;
      continue;
    }
    const char* start = v.c_str() + i;
    char* end = nullptr;
    const double x = std::strtod(start, &end);
    if (end == start || !std::isfinite(x)) return {};
    const std::size_t len = static_cast<std::size_t>(end - start);
    // "true", "lcm" and the like are not numbers; "1e-3" and "-0.5" are.
    if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.')) return {};
    out.push_back({i, i + len});
    i += len;
  }
  return out;
}

std::string splice(const std::string& t, std::size_t begin, std::size_t end, const std::string& with) {
  return t.substr(0, begin) + with + t.substr(end);
}

std::string sanitize(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  while (out.find("__") != std::string::npos) out.erase(out.find("__"), 1);
  while (!out.empty() && out.back() == '_') out.pop_back();
  while (!out.empty() && out.front() == '_') out.erase(0, 1);
  return out;
}

std::string stem_of(const std::string& rel) {
  std::string s = fs::path(rel).filename().string();
  for (const char* ext : {".operator.xml", ".params.xml", ".xml", ".urdf", ".obj", ".json", ".png", ".lcmlog"})
    if (s.size() > std::strlen(ext) && s.compare(s.size() - std::strlen(ext), std::strlen(ext), ext) == 0) {
      s.resize(s.size() - std::strlen(ext));
      break;
    }
  return s;
}

using Text = std::shared_ptr<const std::string>;

struct Builder {
  std::vector<Case> cases;
  std::set<std::string> names;

  Case& add(Case c) {
    c.name = sanitize(c.name);
    std::string name = c.name;
    for (int k = 2; names.count(name); ++k) name = c.name + "_" + std::to_string(k);
    c.name = name;
    names.insert(name);
    cases.push_back(std::move(c));
    return cases.back();
  }
};

Case make(Format f, const std::string& family, const std::string& base, const std::string& detail, Expect expect,
          const std::string& what) {
  Case c;
  c.format = f;
  c.family = family;
  c.base = base;
  c.expect = expect;
  c.what = what;
  c.name = std::string(format_name(f)) + "_" + family + "_" + detail;
  return c;
}

// Families every input file has, whatever its format: the file replaced by
// something that is not a regular file of that format.
void add_replacements(Builder& b, Format f, const std::string& base, const Text& text, bool sparse_needs_start,
                      Expect huge_expect = Expect::kRefused) {
  struct R {
    const char* id;
    Stand stand;
    const char* what;
  };
  const R rs[] = {{"directory", Stand::kDirectory, "the file replaced by an empty directory"},
                  {"dev_zero", Stand::kDevZero, "the file replaced by a link to /dev/zero"},
                  {"empty", Stand::kEmpty, "the file replaced by an empty file"},
                  {"fifo", Stand::kFifo, "the file replaced by a FIFO no one writes to"},
                  {"missing", Stand::kMissing, "the file removed"},
                  {"symlink_loop", Stand::kSymlinkLoop, "the file replaced by a link to itself"}};
  for (const R& r : rs) {
    Case c = make(f, "replace", base, stem_of(base) + "_" + r.id, Expect::kRefused, r.what);
    c.stand = r.stand;
    b.add(c);
  }
  Case c = make(f, "huge_file", base, stem_of(base) + "_100MB", huge_expect,
                sparse_needs_start ? "the file's first bytes, then a hole to 100 MB (NUL bytes)"
                                   : "the whole file, then a hole to 100 MB (NUL bytes)");
  c.stand = Stand::kSparse;
  c.sparse_bytes = 100ull << 20;
  const Text t = text;
  const bool head = sparse_needs_start;
  c.bytes = [t, head] { return head ? t->substr(0, std::min<std::size_t>(t->size(), 64)) : *t; };
  b.add(c);
}

// ---------------------------------------------------------------------------
// XML formats

struct XmlFile {
  std::string rel;  // relative to the source tree
  Text text;
  XmlDoc doc;
};

struct NumberValue {
  const char* id;
  std::string text;
  Expect expect;
  bool per_attribute;  // else once per element (its first number)
};

// Values that strtod takes and that may pass a range check meant for
// another attribute (a huge, a negative huge, a denormal; nan and hex,
// which parse but are no decimal number) go into every numeric attribute:
// each has its own range and its own check. The rest (inf, -inf and what is
// no number at all) go once into each element's first number: they probe
// the element's number reader, which its attributes share.
const std::vector<NumberValue>& number_values() {
  static const std::vector<NumberValue> values = [] {
    std::string digits;
    for (int k = 0; k < 1000; ++k) digits += "1234567890";  // 10 000 digits: past any double
    return std::vector<NumberValue>{
        {"huge", "1e308", Expect::kEither, true},          {"neg_huge", "-1e308", Expect::kEither, true},
        {"nan", "nan", Expect::kRefused, true},            {"denormal", "1e-320", Expect::kEither, true},
        {"hex", "0x10", Expect::kRefused, true},           {"inf", "inf", Expect::kRefused, false},
        {"neg_inf", "-inf", Expect::kRefused, false},      {"empty", "", Expect::kRefused, false},
        {"bad_exponent", "1e", Expect::kRefused, false},   {"blank", "  ", Expect::kRefused, false},
        {"digits10k", digits, Expect::kRefused, false},
    };
  }();
  return values;
}

std::string element_key(const XmlDoc& d, const XmlElement& e) {
  return (e.parent >= 0 ? d.elements[static_cast<std::size_t>(e.parent)].name : std::string("")) + "/" + e.name;
}

// The line of the root's child that holds element `index` (a URDF's link or joint).
int top_line(const XmlDoc& d, int index) {
  int k = index;
  while (k >= 0 && d.elements[static_cast<std::size_t>(k)].parent > 0) k = d.elements[static_cast<std::size_t>(k)].parent;
  return k >= 0 ? d.elements[static_cast<std::size_t>(k)].line : 0;
}

std::string enclosing_soil(const XmlDoc& d, int index) {
  for (int k = index; k >= 0; k = d.elements[static_cast<std::size_t>(k)].parent) {
    const XmlElement& e = d.elements[static_cast<std::size_t>(k)];
    if (e.name == "soil")
      for (const XmlAttr& a : e.attrs)
        if (a.name == "id") return a.value;
  }
  return "";
}

// strict: skidsim's own formats, which refuse unknown elements and
// attributes and elements where they do not belong; URDF is extensible
// (urdfdom ignores what it does not know), so there those may pass.
void add_xml_cases(Builder& b, Format f, const std::vector<XmlFile>& files, const XmlFile& primary, bool strict) {
  const Expect unknown_expect = strict ? Expect::kRefused : Expect::kEither;
  // Which element may hold which, as the shipped files use them.
  std::set<std::pair<std::string, std::string>> holds;
  for (const XmlFile& x : files)
    for (const XmlElement& e : x.doc.elements)
      if (e.parent >= 0) holds.insert({x.doc.elements[static_cast<std::size_t>(e.parent)].name, e.name});

  // The unmutated files: the controls.
  for (const XmlFile& x : files) {
    Case c = make(f, "control", x.rel, stem_of(x.rel), Expect::kAccepted, "the shipped file as it is");
    const Text t = x.text;
    c.bytes = [t] { return *t; };
    c.companion = x.rel;
    b.add(c);
  }

  std::set<std::string> seen_attr, seen_elem, seen_misplaced, seen_number_elem;
  for (const XmlFile& x : files) {
    const Text t = x.text;
    const XmlDoc& d = x.doc;
    const std::string stem = stem_of(x.rel);
    for (std::size_t ei = 0; ei < d.elements.size(); ++ei) {
      const XmlElement& e = d.elements[ei];
      const std::string ekey = element_key(d, e);
      const std::string soil = f == Format::kSoilTable ? enclosing_soil(d, static_cast<int>(ei)) : "";
      const XmlAttr* current = nullptr;  // the attribute being mutated, if any
      const auto base_case = [&](const std::string& family, const std::string& detail, Expect expect,
                                 const std::string& what) {
        Case c = make(f, family, x.rel, stem + "_" + detail, expect, what);
        // A mutated soil id cannot be asked for by its old name.
        c.soil_id = current && e.name == "soil" && current->name == "id" ? "" : soil;
        c.companion = x.rel;
        return c;
      };
      // Attributes: numbers, removal, other text.
      for (const XmlAttr& a : e.attrs) {
        const std::string akey = ekey + "@" + a.name;
        if (!seen_attr.insert(akey).second) continue;
        current = &a;
        const std::string where =
            (e.parent > 0 ? d.elements[static_cast<std::size_t>(e.parent)].name + "_" : std::string()) + e.name + "_" +
            a.name;
        const std::vector<Span> numbers = number_tokens(a.value);
        if (!numbers.empty()) {
          const std::size_t vb = a.value_begin + numbers[0].begin, ve = a.value_begin + numbers[0].end;
          const bool first_number = seen_number_elem.insert(ekey).second;
          for (const NumberValue& v : number_values()) {
            if (!v.per_attribute && !first_number) continue;
            Case c = base_case("number", where + "_" + v.id, v.expect,
                               "<" + e.name + "> " + a.name + ": first number replaced by \"" +
                                   (v.text.size() > 20 ? v.text.substr(0, 10) + "...(" + std::to_string(v.text.size()) +
                                                             " digits)"
                                                       : v.text) +
                                   "\"");
            const NumberValue* value = &v;  // static: the closure stays small
            c.bytes = [t, vb, ve, value] { return splice(*t, vb, ve, value->text); };
            c.where = {a.name};
            c.lines = {e.line, a.line};
            if (!strict) {
              // urdfdom keeps no lines: the message gives the link's or
              // joint's, and names the element.
              c.where.push_back(e.name);
              c.lines.push_back(top_line(d, static_cast<int>(ei)));
            }
            b.add(c);
          }
          if (numbers.size() > 1) {
            const std::size_t last_b = a.value_begin + numbers[numbers.size() - 2].end;
            const std::size_t last_e = a.value_begin + numbers.back().end;
            Case s = base_case("arity", where + "_short", Expect::kRefused,
                               "<" + e.name + "> " + a.name + ": its last number removed");
            s.bytes = [t, last_b, last_e] { return splice(*t, last_b, last_e, ""); };
            s.where = {a.name};
            s.lines = {e.line, a.line};
            if (!strict) {
              s.where.push_back(e.name);
              s.lines.push_back(top_line(d, static_cast<int>(ei)));
            }
            b.add(s);
            Case l = base_case("arity", where + "_long", Expect::kRefused,
                               "<" + e.name + "> " + a.name + ": one number more");
            l.bytes = [t, last_e] { return splice(*t, last_e, last_e, " 1"); };
            l.where = {a.name};
            l.lines = {e.line, a.line};
            if (!strict) {
              l.where.push_back(e.name);
              l.lines.push_back(top_line(d, static_cast<int>(ei)));
            }
            b.add(l);
          }
        } else {
          Case c = base_case("text_value", where + "_bogus", Expect::kEither,
                             "<" + e.name + "> " + a.name + " = \"zz_bogus\"");
          const std::size_t vb = a.value_begin, ve = a.value_end;
          c.bytes = [t, vb, ve] { return splice(*t, vb, ve, "zz_bogus"); };
          c.where = {a.name};
          c.lines = {e.line, a.line};
          b.add(c);
        }
        Case r = base_case("remove_attr", where, Expect::kEither, "<" + e.name + "> without its " + a.name);
        std::size_t rb = a.name_begin;
        while (rb > 0 && ((*t)[rb - 1] == ' ' || (*t)[rb - 1] == '\n' || (*t)[rb - 1] == '\t')) --rb;
        const std::size_t re = a.value_end + 1;
        r.bytes = [t, rb, re] { return splice(*t, rb, re, ""); };
        r.where = {a.name, e.name};
        r.lines = {e.line, a.line};
        b.add(r);
      }
      current = nullptr;
      // Elements: unknown attribute, unknown child, duplicate, misplaced.
      if (seen_elem.insert(ekey).second) {
        const std::size_t attr_at = e.self_closing ? (*t).rfind('/', e.tag_end - 1) : e.tag_end - 1;
        Case ua = base_case("unknown_attr", e.name, unknown_expect, "<" + e.name + "> with zz_unknown=\"1\"");
        ua.bytes = [t, attr_at] { return splice(*t, attr_at, attr_at, " zz_unknown=\"1\""); };
        ua.where = {"zz_unknown"};
        ua.lines = {e.line};
        b.add(ua);

        Case uc = base_case("unknown_element", e.name, unknown_expect, "<zz_unknown/> inside <" + e.name + ">");
        if (e.self_closing) {
          const std::size_t slash = attr_at;
          const std::string close = "><zz_unknown/></" + e.name + ">";
          const std::size_t tag_end = e.tag_end;
          uc.bytes = [t, slash, tag_end, close] { return splice(*t, slash, tag_end, close); };
        } else {
          const std::size_t at = e.tag_end;
          uc.bytes = [t, at] { return splice(*t, at, at, "<zz_unknown/>"); };
        }
        uc.where = {"zz_unknown"};
        b.add(uc);

        if (e.parent >= 0) {
          Case du = base_case("duplicate", e.name, Expect::kEither, "<" + e.name + "> twice, one after the other");
          const std::size_t eb = e.begin, ee = e.end;
          du.bytes = [t, eb, ee] { return splice(*t, ee, ee, "\n" + t->substr(eb, ee - eb)); };
          du.where = {e.name};
          b.add(du);
        }
      }
      // Misplaced: a copy of the element inside a sibling (or itself) that
      // never holds one.
      if (e.parent >= 0) {
        std::vector<const XmlElement*> hosts;
        const XmlElement* next = nullptr;
        const XmlElement* prev = nullptr;
        for (std::size_t k = 0; k < d.elements.size(); ++k) {
          const XmlElement& s = d.elements[k];
          if (k == ei || s.parent != e.parent) continue;
          if (k > ei && !next) next = &s;
          if (k < ei) prev = &s;
        }
        hosts.push_back(next ? next : prev);
        hosts.push_back(&e);
        for (const XmlElement* h : hosts) {
          if (!h || holds.count({h->name, e.name})) continue;
          if (!seen_misplaced.insert(h->name + ">" + e.name).second) continue;
          Case m = base_case("misplaced", e.name + "_in_" + h->name, unknown_expect,
                             "a copy of <" + e.name + "> inside <" + h->name + ">");
          const std::string copy = t->substr(e.begin, e.end - e.begin);
          if (h->self_closing) {
            const std::size_t slash = (*t).rfind('/', h->tag_end - 1), tag_end = h->tag_end;
            const std::string close = ">" + copy + "</" + h->name + ">";
            m.bytes = [t, slash, tag_end, close] { return splice(*t, slash, tag_end, close); };
          } else {
            const std::size_t at = h->tag_end;
            m.bytes = [t, at, copy] { return splice(*t, at, at, copy); };
          }
          m.where = {e.name, h->name};
          b.add(m);
        }
      }
    }
    // Truncation at several points inside the root element.
    const XmlElement& root = d.elements.front();
    const std::size_t inside_end = root.close_begin > root.begin ? root.close_begin : t->size();
    const std::vector<std::pair<std::string, std::size_t>> cuts = {
        {"in_root_tag", root.begin + 2},
        {"after_root_tag", root.tag_end},
        {"at_25pct", root.begin + (inside_end - root.begin) / 4},
        {"at_50pct", root.begin + (inside_end - root.begin) / 2},
        {"at_90pct", root.begin + (inside_end - root.begin) * 9 / 10},
        {"in_end_tag", inside_end + 2},
    };
    for (const auto& [id, at] : cuts) {
      if (x.rel != primary.rel && id != "at_50pct" && id != "in_end_tag") continue;
      Case c = make(f, "truncate", x.rel, stem + "_" + id, Expect::kRefused,
                    "cut after byte " + std::to_string(at) + " of " + std::to_string(t->size()));
      c.companion = x.rel;
      c.bytes = [t, at = at] { return t->substr(0, at); };
      b.add(c);
    }
  }

  // One file of the format for the families that do not depend on its content.
  const Text t = primary.text;
  const XmlDoc& d = primary.doc;
  const XmlElement& root = d.elements.front();
  const std::string stem = stem_of(primary.rel);
  const auto one = [&](const std::string& family, const std::string& detail, Expect expect, const std::string& what,
                       std::function<std::string()> bytes) -> Case& {
    Case c = make(f, family, primary.rel, stem + "_" + detail, expect, what);
    c.companion = primary.rel;
    c.bytes = std::move(bytes);
    return b.add(c);
  };
  // A text attribute to damage: the first one that is not a number.
  const XmlAttr* text_attr = nullptr;
  for (const XmlElement& e : d.elements) {
    for (const XmlAttr& a : e.attrs)
      if (number_tokens(a.value).empty() && !a.value.empty()) {
        text_attr = &a;
        break;
      }
    if (text_attr) break;
  }
  const std::vector<std::pair<const char*, std::string>> bad_utf8 = {
      {"ff", "\xff"},           {"lone_continuation", "\x80"}, {"overlong_slash", "\xc0\xaf"},
      {"surrogate", "\xed\xa0\x80"}, {"cut_sequence", "\xe2\x82"}, {"past_10ffff", "\xf4\x90\x80\x80"}};
  if (text_attr) {
    const std::size_t at = text_attr->value_begin + std::min<std::size_t>(1, text_attr->value.size());
    for (const auto& [id, bytes] : bad_utf8) {
      const std::string with = bytes;
      Case& c = one("invalid_utf8", std::string("in_") + text_attr->name + "_" + id, Expect::kRefused,
                    "bytes " + std::string(id) + " inside attribute " + text_attr->name,
                    [t, at, with] { return splice(*t, at, at, with); });
      c.lines = {text_attr->line};
    }
  }
  if (d.elements.size() > 1) {
    const XmlElement& e = d.elements[1];
    const std::size_t at = e.begin + 2;
    Case& c = one("invalid_utf8", "in_element_name", Expect::kRefused, "byte 0xff inside <" + e.name + ">'s name",
                  [t, at] { return splice(*t, at, at, "\xff"); });
    c.lines = {e.line};
  }
  if (d.comment_begin != std::string::npos) {
    const std::size_t at = d.comment_begin + 5;
    one("invalid_utf8", "in_comment", Expect::kRefused, "byte 0xfe inside a comment",
        [t, at] { return splice(*t, at, at, "\xfe"); });
  }
  // NUL bytes.
  if (text_attr) {
    const std::size_t at = text_attr->value_begin + 1;
    one("nul_byte", "in_attribute", Expect::kRefused, "a NUL inside attribute " + text_attr->name,
        [t, at] { return splice(*t, at, at, std::string(1, '\0')); });
  }
  {
    const std::size_t at = root.tag_end;
    one("nul_byte", "after_root_tag", Expect::kRefused, "a NUL between elements",
        [t, at] { return splice(*t, at, at, std::string(1, '\0')); });
    one("nul_byte", "after_root", Expect::kRefused, "a NUL and text after the document",
        [t] { return *t + std::string(1, '\0') + "<zz_after/>"; });
  }
  if (d.comment_begin != std::string::npos) {
    const std::size_t at = d.comment_begin + 5;
    one("nul_byte", "in_comment", Expect::kRefused, "a NUL inside a comment",
        [t, at] { return splice(*t, at, at, std::string(1, '\0')); });
  }
  // Deep nesting inside the root.
  for (int depth : {10000, 100000}) {
    const std::size_t at = root.tag_end;
    one("deep_nesting", std::to_string(depth), Expect::kRefused,
        std::to_string(depth) + " nested unknown elements inside the root", [t, at, depth] {
          std::string nest;
          nest.reserve(static_cast<std::size_t>(depth) * 7);
          for (int k = 0; k < depth; ++k) nest += "<n>";
          for (int k = 0; k < depth; ++k) nest += "</n>";
          return splice(*t, at, at, nest);
        });
  }
  if (d.elements.size() > 1) {
    // The first child nested in itself 10 000 deep: known names, wrong place.
    const XmlElement& e = d.elements[1];
    const std::string open = t->substr(e.begin, (e.self_closing ? (*t).rfind('/', e.tag_end - 1) : e.tag_end - 1) -
                                                     e.begin) + ">";
    const std::string close = "</" + e.name + ">";
    const std::size_t at = root.tag_end;
    one("deep_nesting", "10000_" + e.name, strict ? Expect::kRefused : Expect::kEither,
        "<" + e.name + "> nested in itself 10000 deep", [t, at, open, close] {
          std::string nest;
          for (int k = 0; k < 10000; ++k) nest += open;
          for (int k = 0; k < 10000; ++k) nest += close;
          return splice(*t, at, at, nest);
        });
  }
  // Whole-document damage.
  {
    const std::string name = root.name;
    const std::size_t nb = root.begin + 1, ne = root.begin + 1 + name.size();
    const std::size_t cb = root.close_begin + 2, ce = root.close_begin + 2 + name.size();
    Case& c = one("wrong_root", "renamed", Expect::kRefused, "the root element renamed zz_root", [t, nb, ne, cb, ce] {
      std::string s = splice(*t, cb, ce, "zz_root");
      return splice(s, nb, ne, "zz_root");
    });
    c.lines = {root.line};
    if (d.elements.size() > 1) {
      const XmlElement& e = d.elements[1];
      const std::string copy = t->substr(e.begin, e.end - e.begin);
      one("after_root", "second_element", Expect::kRefused, "a copy of <" + e.name + "> after the root element",
          [t, copy] { return *t + copy + "\n"; });
    }
    one("after_root", "text", Expect::kRefused, "text after the root element", [t] { return *t + "zz trailing text\n"; });
    one("encoding", "utf16le", Expect::kRefused, "the file in UTF-16LE with a byte-order mark", [t] {
      std::string s = "\xff\xfe";
      for (char ch : *t) {
        s += ch;
        s += '\0';
      }
      return s;
    });
    one("encoding", "utf8_bom", Expect::kEither, "a UTF-8 byte-order mark first", [t] { return "\xef\xbb\xbf" + *t; });
    one("encoding", "crlf", Expect::kEither, "CR LF line ends", [t] {
      std::string s;
      for (char ch : *t) {
        if (ch == '\n') s += '\r';
        s += ch;
      }
      return s;
    });
    one("not_xml", "json", Expect::kRefused, "JSON instead of XML", [] { return std::string("{\"exercise\": 1}\n"); });
    one("not_xml", "whitespace", Expect::kRefused, "only blank lines", [] { return std::string("\n\n   \n"); });
    one("not_xml", "declaration_only", Expect::kRefused, "only the XML declaration",
        [] { return std::string("<?xml version=\"1.0\"?>\n"); });
    // Nine levels of ten references each (10^9 "lol"s if expanded), and a
    // reference to the top one in a text attribute: expanding it must not
    // be tried (tinyxml2 keeps unknown entities as text).
    const std::size_t ref_at = text_attr ? text_attr->value_begin : std::string::npos;
    one("entity", "billion_laughs", Expect::kEither, "a DOCTYPE with nested entities, &lol9; in a text attribute",
        [t, ref_at] {
          std::string dtd = "<!DOCTYPE lolz [<!ENTITY lol0 \"lol\">";
          for (int k = 1; k < 10; ++k) {
            dtd += "<!ENTITY lol" + std::to_string(k) + " \"";
            for (int j = 0; j < 10; ++j) dtd += "&lol" + std::to_string(k - 1) + ";";
            dtd += "\">";
          }
          dtd += "]>\n";
          std::string s = ref_at == std::string::npos ? *t : splice(*t, ref_at, ref_at, "&lol9;");
          const std::size_t decl = s.find("?>");
          const std::size_t at = s.find('<', decl == std::string::npos ? 0 : decl);
          return splice(s, at, at, dtd);
        });
  }
  add_replacements(b, f, primary.rel, t, false);
}

XmlFile read_xml(const std::string& rel) {
  XmlFile x;
  x.rel = rel;
  x.text = std::make_shared<const std::string>(read_file(source_dir() + "/" + rel));
  x.doc = lex_xml(*x.text);
  return x;
}

// ---------------------------------------------------------------------------
// Meshes (OBJ text)

void add_mesh_cases(Builder& b) {
  const std::string rel = "assets/loader/meshes/chassis.obj";
  const Text t = std::make_shared<const std::string>(read_file(source_dir() + "/" + rel));
  const auto add = [&](const std::string& family, const std::string& detail, Expect expect, const std::string& what,
                       std::function<std::string()> bytes) {
    Case c = make(Format::kMesh, family, rel, "chassis_" + detail, expect, what);
    c.bytes = std::move(bytes);
    b.add(c);
  };
  add("control", "as_shipped", Expect::kAccepted, "the shipped mesh as it is", [t] { return *t; });
  // The first vertex line and the first face line.
  const std::size_t v = t->find("\nv ") + 1, f = t->find("\nf ") + 1;
  const std::size_t v_end = t->find('\n', v), f_end = t->find('\n', f);
  for (const auto& [id, value, expect] : std::vector<std::tuple<const char*, const char*, Expect>>{
           {"nan", "nan", Expect::kRefused},
           {"inf", "inf", Expect::kRefused},
           {"huge", "1e308", Expect::kRefused},  // a float overflows: not a finite vertex
           {"neg_huge", "-1e308", Expect::kRefused},
           {"text", "abc", Expect::kEither},
           {"denormal", "1e-320", Expect::kEither}}) {
    const std::string line = std::string("v ") + value + " 0 0";
    add("vertex", id, expect, std::string("a vertex at x = ") + value,
        [t, v, v_end, line] { return splice(*t, v, v_end, line); });
  }
  for (const auto& [id, face] : std::vector<std::pair<const char*, const char*>>{
           {"index_past_end", "f 1 2 99999999"},
           {"index_zero", "f 0 0 0"},
           {"index_negative_past_start", "f -99999999 1 2"},
           {"index_overflow", "f 1 2 99999999999999999999"},
           {"two_indices", "f 1 2"}}) {
    const std::string line = face;
    // Two indices make a line, which OBJ allows (and the loader skips).
    add("face", id, std::string(id) == "two_indices" ? Expect::kEither : Expect::kRefused, std::string("the first face replaced by \"") + face + "\"",
        [t, f, f_end, line] { return splice(*t, f, f_end, line); });
  }
  for (int pct : {10, 50, 90}) {
    const std::size_t at = t->size() * static_cast<std::size_t>(pct) / 100;
    add("truncate", std::to_string(pct) + "pct", Expect::kEither,
        "cut after byte " + std::to_string(at) + " (an OBJ has no end mark)", [t, at] { return t->substr(0, at); });
  }
  add("truncate", "mid_face_line", Expect::kEither, "cut inside the first face line",
      [t, f] { return t->substr(0, f + 4); });
  add("no_faces", "vertices_only", Expect::kRefused, "vertices and no faces", [t, f] { return t->substr(0, f); });
  add("garbage", "binary_4k", Expect::kRefused, "4 KiB of pseudo-random bytes", [] {
    std::string s(4096, '\0');
    std::uint32_t x = 12345;
    for (char& c : s) {
      x = x * 1664525u + 1013904223u;
      c = static_cast<char>(x >> 24);
    }
    return s;
  });
  add("garbage", "xml", Expect::kRefused, "an XML file named .obj", [] { return std::string("<robot name=\"x\"/>\n"); });
  add("nul_byte", "in_vertex", Expect::kEither, "a NUL inside the first vertex line",
      [t, v] { return splice(*t, v + 2, v + 2, std::string(1, '\0')); });
  add("invalid_utf8", "in_comment", Expect::kEither, "byte 0xff in a comment", [t] { return "# \xff\xfe\n" + *t; });
  add("material_library", "fifo", Expect::kEither, "mtllib naming a FIFO beside it (must not wait on it)",
      [t] { return "mtllib zz_fifo.mtl\n" + *t; });
  add("material_library", "dev_zero", Expect::kEither, "mtllib /dev/zero", [t] { return "mtllib /dev/zero\n" + *t; });
  add("material_library", "missing", Expect::kEither, "mtllib naming a missing file",
      [t] { return "mtllib zz_missing.mtl\n" + *t; });
  add("huge_count", "million_faces_one_line", Expect::kEither, "a face with 1 000 000 indices", [t] {
    std::string line = "f";
    for (int k = 0; k < 1000000; ++k) line += " 1";
    return *t + line + "\n";
  });
  // A mesh's cap is 256 MiB, and OBJ has no end mark: 100 MB (NUL bytes
  // after the mesh) may be read, as long as it ends and stays bounded.
  add_replacements(b, Format::kMesh, rel, t, false, Expect::kEither);
}

// ---------------------------------------------------------------------------
// Height maps: the JSON metadata and the PNG

void add_heightmap_cases(Builder& b, const Artifacts& a) {
  const std::string json_text = read_file(a.heightmap_json);
  const std::string png_text = read_file(a.heightmap_png);
  if (json_text.empty() || png_text.size() < 64) return;
  const Text jt = std::make_shared<const std::string>(json_text);
  const json meta = json::parse(json_text, nullptr, false);
  if (!meta.is_object()) return;
  const std::string jbase = "pour/terrain_material.json";
  const auto jadd = [&](const std::string& family, const std::string& detail, Expect expect, const std::string& what,
                        std::function<std::string()> bytes, std::vector<std::string> where = {}) -> Case& {
    Case c = make(Format::kHeightmapJson, family, jbase, detail, expect, what);
    c.bytes = std::move(bytes);
    c.where = std::move(where);
    return b.add(c);
  };
  jadd("control", "as_written", Expect::kAccepted, "the metadata as skidsim pour wrote it", [jt] { return *jt; });
  const std::set<std::string> required = {"format", "version",    "image",      "quantity",        "nx",
                                          "ny",     "cell_size_m", "origin_m", "z_offset_m", "vertical_scale_m"};
  const std::set<std::string> integers = {"version", "nx", "ny"};
  for (const auto& [key, value] : meta.items()) {
    const bool req = required.count(key) > 0;
    const auto with = [meta, key = key](json v) {
      json m = meta;
      m[key] = std::move(v);
      return m.dump(2) + "\n";
    };
    struct V {
      const char* id;
      json value;
      Expect expect;
    };
    std::vector<V> values = {
        {"huge", 1e308, req ? Expect::kRefused : Expect::kEither},
        {"neg_huge", -1e308, req ? Expect::kRefused : Expect::kEither},
        {"negative", -1, req && key != "z_offset_m" ? Expect::kRefused : Expect::kEither},
        {"zero", 0, req && key != "z_offset_m" ? Expect::kRefused : Expect::kEither},
        {"string", "zz", req ? Expect::kRefused : Expect::kEither},
        {"null", nullptr, req ? Expect::kRefused : Expect::kEither},
        {"array", json::array(), req ? Expect::kRefused : Expect::kEither},
        {"object", json::object(), req ? Expect::kRefused : Expect::kEither},
        {"bool", true, req ? Expect::kRefused : Expect::kEither},
    };
    if (integers.count(key)) {
      values.push_back({"fraction", value.get<double>() + 0.5, Expect::kRefused});
      values.push_back({"plus_one", value.get<int>() + 1, Expect::kRefused});
      values.push_back({"int_overflow", 4294967297.0, Expect::kRefused});
    }
    for (const V& v : values) {
      // Fields only for people to read: a few values are enough.
      if (!req && std::string(v.id) != "huge" && std::string(v.id) != "null") continue;
      const std::string bytes = with(v.value);
      std::vector<std::string> where = {key};
      if (key == "z_offset_m" || key == "vertical_scale_m") where.push_back("at cell");
      jadd("field", key + "_" + v.id, v.expect, "field " + key + " = " + v.value.dump(),
           [bytes] { return bytes; }, where);
    }
    json m = meta;
    m.erase(key);
    const std::string bytes = m.dump(2) + "\n";
    jadd("field", key + "_missing", req ? Expect::kRefused : Expect::kEither, "field " + key + " removed",
         [bytes] { return bytes; }, {key});
  }
  // Fields with meaning beyond their type.
  const auto set = [&](const std::string& family, const std::string& detail, const std::string& key, json v,
                       Expect expect) {
    json m = meta;
    m[key] = v;
    const std::string bytes = m.dump(2) + "\n";
    // A column out of range may be named by its cell (README: "naming the file").
    std::vector<std::string> where = {key};
    if (key == "z_offset_m" || key == "vertical_scale_m") where.push_back("at cell");
    jadd(family, detail, expect, "field " + key + " = " + v.dump(), [bytes] { return bytes; },
         family == "image" ? std::vector<std::string>{} : where);
  };
  set("field", "quantity_surface", "quantity", "surface", Expect::kRefused);  // --material-map reads a material map
  set("field", "quantity_base", "quantity", "base", Expect::kRefused);
  set("field", "format_other", "format", "skidsim-heightmap-v2", Expect::kRefused);
  set("field", "version_2", "version", 2, Expect::kRefused);
  set("field", "origin_huge", "origin_m", json::array({1e308, 0.0}), Expect::kRefused);
  set("field", "origin_one", "origin_m", json::array({0.0}), Expect::kRefused);
  set("field", "origin_three", "origin_m", json::array({0.0, 0.0, 0.0}), Expect::kRefused);
  set("field", "origin_strings", "origin_m", json::array({"a", "b"}), Expect::kRefused);
  set("field", "cell_tiny", "cell_size_m", 1e-300, Expect::kRefused);
  set("field", "scale_huge_column", "vertical_scale_m", 1.0, Expect::kRefused);  // 65 km of material
  set("field", "z_offset_deep", "z_offset_m", -1e6, Expect::kRefused);
  // The image field's own families: naming the image (or the metadata) is enough.
  set("image", "dev_zero", "image", "/dev/zero", Expect::kRefused);
  set("image", "root_dir", "image", "/", Expect::kRefused);
  set("image", "empty", "image", "", Expect::kRefused);
  set("image", "itself", "image", "terrain_material.json", Expect::kRefused);
  set("image", "parent", "image", "..", Expect::kRefused);
  set("image", "missing", "image", "zz_missing.png", Expect::kRefused);
  // Whole-document damage.
  jadd("json_syntax", "nan_literal", Expect::kRefused, "z_offset_m: NaN (not JSON)", [jt] {
    std::string s = *jt;
    const std::size_t k = s.find("\"z_offset_m\":");
    const std::size_t vb = s.find_first_not_of(' ', k + 13), ve = s.find_first_of(",\n}", vb);
    return splice(s, vb, ve, "NaN");
  });
  for (int pct : {1, 25, 50, 75, 99}) {
    const std::size_t at = jt->size() * static_cast<std::size_t>(pct) / 100;
    jadd("truncate", "at_" + std::to_string(pct) + "pct", Expect::kRefused, "cut after byte " + std::to_string(at),
         [jt, at] { return jt->substr(0, at); });
  }
  jadd("invalid_utf8", "in_string", Expect::kRefused, "byte 0xff inside a string value", [jt] {
    std::string s = *jt;
    const std::size_t k = s.find("\"row_order\"");
    return splice(s, k + 15, k + 15, "\xff");
  });
  jadd("nul_byte", "in_string", Expect::kRefused, "a NUL inside a string value", [jt] {
    std::string s = *jt;
    const std::size_t k = s.find("\"row_order\"");
    return splice(s, k + 15, k + 15, std::string(1, '\0'));
  });
  jadd("nul_byte", "after_document", Expect::kRefused, "a NUL after the document",
       [jt] { return *jt + std::string(1, '\0'); });
  jadd("trailing", "second_document", Expect::kRefused, "a second JSON document after the first",
       [jt] { return *jt + "{}\n"; });
  jadd("duplicate_key", "nx", Expect::kEither, "nx given twice (the second 1)", [jt] {
    std::string s = *jt;
    return splice(s, 1, 1, "\n  \"nx\": 7,");
  });
  for (int depth : {10000, 100000}) {
    jadd("deep_nesting", std::to_string(depth), Expect::kEither,
         "an unknown field holding " + std::to_string(depth) + " nested arrays", [jt, depth] {
           std::string nest(static_cast<std::size_t>(depth), '[');
           nest += std::string(static_cast<std::size_t>(depth), ']');
           return splice(*jt, 1, 1, "\n  \"zz_deep\": " + nest + ",");
         });
  }
  for (const auto& [id, doc] : std::vector<std::pair<const char*, const char*>>{
           {"array", "[]\n"}, {"number", "1\n"}, {"string", "\"skidsim-heightmap\"\n"}, {"null", "null\n"}}) {
    const std::string s = doc;
    jadd("not_object", id, Expect::kRefused, std::string("the document is ") + id, [s] { return s; });
  }
  add_replacements(b, Format::kHeightmapJson, jbase, jt, false);

  // The PNG.
  const Text pt = std::make_shared<const std::string>(png_text);
  const std::string pbase = "pour/terrain_material.png";
  const auto padd = [&](const std::string& family, const std::string& detail, Expect expect, const std::string& what,
                        std::function<std::string()> bytes) {
    Case c = make(Format::kHeightmapPng, family, pbase, detail, expect, what);
    c.bytes = std::move(bytes);
    b.add(c);
  };
  padd("control", "as_written", Expect::kAccepted, "the PNG as skidsim pour wrote it", [pt] { return *pt; });
  // Chunks: offsets of each.
  struct Chunk {
    std::size_t at, length;
    std::string type;
  };
  std::vector<Chunk> chunks;
  for (std::size_t p = 8; p + 12 <= pt->size();) {
    const auto u32 = [&](std::size_t k) {
      return (static_cast<std::uint32_t>(static_cast<unsigned char>((*pt)[k])) << 24) |
             (static_cast<std::uint32_t>(static_cast<unsigned char>((*pt)[k + 1])) << 16) |
             (static_cast<std::uint32_t>(static_cast<unsigned char>((*pt)[k + 2])) << 8) |
             static_cast<std::uint32_t>(static_cast<unsigned char>((*pt)[k + 3]));
    };
    const std::size_t len = u32(p);
    chunks.push_back({p, len, pt->substr(p + 4, 4)});
    p += 12 + len;
  }
  std::size_t idat = 0;
  for (const Chunk& c : chunks)
    if (c.type == "IDAT") {
      idat = c.at;
      break;
    }
  const std::size_t idat_len = idat ? static_cast<std::size_t>(std::find_if(chunks.begin(), chunks.end(), [&](const Chunk& c) {
                                                                  return c.at == idat;
                                                                })->length)
                                    : 0;
  for (const auto& [id, at] : std::vector<std::pair<std::string, std::size_t>>{
           {"in_signature", 4},
           {"after_signature", 8},
           {"in_ihdr", 16},
           {"before_ihdr_crc", 29},
           {"after_ihdr", 33},
           {"in_idat_header", idat + 4},
           {"mid_idat", idat + 8 + idat_len / 2},
           {"before_idat_crc", idat + 8 + idat_len},
           {"no_iend", pt->size() - 12},
           {"last_byte", pt->size() - 1}}) {
    padd("truncate", id, Expect::kRefused, "cut after byte " + std::to_string(at) + " of " + std::to_string(pt->size()),
         [pt, at = at] { return pt->substr(0, at); });
  }
  // IHDR rewritten, with its CRC made right so that the reader gets as far as the values.
  const auto crc32 = [](const std::string& s, std::size_t begin, std::size_t end) {
    std::uint32_t c = 0xffffffffu;
    for (std::size_t k = begin; k < end; ++k) {
      c ^= static_cast<unsigned char>(s[k]);
      for (int j = 0; j < 8; ++j) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
  };
  const auto put32 = [](std::string& s, std::size_t at, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) s[at + static_cast<std::size_t>(k)] = static_cast<char>((v >> (24 - 8 * k)) & 0xff);
  };
  const auto ihdr = [pt, crc32, put32](std::uint32_t w, std::uint32_t h, int depth, int colour, int compression,
                                       int filter, int interlace, bool fix_crc) {
    std::string s = *pt;
    if (w) put32(s, 16, w);
    if (h) put32(s, 20, h);
    if (depth >= 0) s[24] = static_cast<char>(depth);
    if (colour >= 0) s[25] = static_cast<char>(colour);
    if (compression >= 0) s[26] = static_cast<char>(compression);
    if (filter >= 0) s[27] = static_cast<char>(filter);
    if (interlace >= 0) s[28] = static_cast<char>(interlace);
    if (fix_crc) put32(s, 29, crc32(s, 12, 29));
    return s;
  };
  struct H {
    const char* id;
    std::uint32_t w, h;
    int depth, colour, compression, filter, interlace;
    bool fix;
  };
  for (const H& h : std::vector<H>{{"claims_100000x100000", 100000, 100000, -1, -1, -1, -1, -1, true},
                                   {"claims_100000x1", 100000, 1, -1, -1, -1, -1, -1, true},
                                   {"claims_1x100000", 1, 100000, -1, -1, -1, -1, -1, true},
                                   {"claims_2147483647_wide", 2147483647u, 1, -1, -1, -1, -1, -1, true},
                                   {"claims_4294967295_wide", 4294967295u, 4294967295u, -1, -1, -1, -1, -1, true},
                                   {"claims_21x21", 21, 21, -1, -1, -1, -1, -1, true},
                                   {"bit_depth_8", 0, 0, 8, -1, -1, -1, -1, true},
                                   {"bit_depth_1", 0, 0, 1, -1, -1, -1, -1, true},
                                   {"bit_depth_7", 0, 0, 7, -1, -1, -1, -1, true},
                                   {"colour_rgb", 0, 0, -1, 2, -1, -1, -1, true},
                                   {"colour_palette_no_plte", 0, 0, 8, 3, -1, -1, -1, true},
                                   {"colour_grey_alpha", 0, 0, -1, 4, -1, -1, -1, true},
                                   {"colour_rgba", 0, 0, -1, 6, -1, -1, -1, true},
                                   {"compression_1", 0, 0, -1, -1, 1, -1, -1, true},
                                   {"filter_1", 0, 0, -1, -1, -1, 1, -1, true},
                                   {"interlace_adam7_data_not", 0, 0, -1, -1, -1, -1, 1, true},
                                   {"bad_crc", 100000, 100000, -1, -1, -1, -1, -1, false}}) {
    padd("header", h.id, Expect::kRefused,
         std::string("IHDR rewritten: ") + h.id + (h.fix ? " (CRC recomputed)" : " (CRC left wrong)"),
         [ihdr, h] { return ihdr(h.w, h.h, h.depth, h.colour, h.compression, h.filter, h.interlace, h.fix); });
  }
  if (idat) {
    const std::size_t data = idat + 8, len = idat_len;
    padd("idat", "flipped_bytes_crc_fixed", Expect::kRefused, "bytes in the middle of IDAT flipped, CRC recomputed",
         [pt, data, len, crc32, put32] {
           std::string s = *pt;
           for (std::size_t k = data + len / 2; k < std::min(data + len, data + len / 2 + 8); ++k)
             s[k] = static_cast<char>(~s[k]);
           put32(s, data + len, crc32(s, data - 4, data + len));
           return s;
         });
    padd("idat", "flipped_bytes", Expect::kRefused, "bytes in the middle of IDAT flipped (CRC wrong)", [pt, data, len] {
      std::string s = *pt;
      s[data + len / 2] = static_cast<char>(~s[data + len / 2]);
      return s;
    });
    padd("idat", "removed", Expect::kRefused, "the IDAT chunk removed", [pt, idat, len] {
      return pt->substr(0, idat) + pt->substr(idat + 12 + len);
    });
    padd("idat", "length_2gib", Expect::kRefused, "IDAT's length field 0x7fffffff", [pt, idat, put32] {
      std::string s = *pt;
      put32(s, idat, 0x7fffffffu);
      return s;
    });
  }
  padd("trailing", "after_iend", Expect::kEither, "bytes after IEND", [pt] { return *pt + "zz trailing bytes"; });
  padd("garbage", "json_named_png", Expect::kRefused, "the metadata's JSON under the PNG's name",
       [jt] { return *jt; });
  padd("garbage", "signature_only", Expect::kRefused, "the 8-byte signature alone", [pt] { return pt->substr(0, 8); });
  add_replacements(b, Format::kHeightmapPng, pbase, pt, true);
}

// ---------------------------------------------------------------------------
// LCM session logs

struct LogEvent {
  std::size_t at, size;  // offset, bytes including the 28-byte header
  std::string channel;
  std::size_t data_at, data_len;
};

std::uint32_t be32(const std::string& s, std::size_t k) {
  return (static_cast<std::uint32_t>(static_cast<unsigned char>(s[k])) << 24) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[k + 1])) << 16) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[k + 2])) << 8) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[k + 3]));
}

std::vector<LogEvent> index_log(const std::string& s) {
  std::vector<LogEvent> events;
  for (std::size_t p = 0; p + 28 <= s.size();) {
    if (be32(s, p) != 0xEDA1DA01u) break;
    const std::size_t cl = be32(s, p + 20), dl = be32(s, p + 24);
    if (p + 28 + cl + dl > s.size()) break;
    events.push_back({p, 28 + cl + dl, s.substr(p + 28, cl), p + 28 + cl, dl});
    p += 28 + cl + dl;
  }
  return events;
}

void add_log_cases(Builder& b, const Artifacts& a) {
  const std::string log = read_file(a.log);
  const std::vector<LogEvent> ev = index_log(log);
  if (ev.size() < 20) return;
  const Text t = std::make_shared<const std::string>(log);
  const std::string base = "run_grading/session.lcmlog";
  const auto add = [&](const std::string& family, const std::string& detail, Expect expect, const std::string& what,
                       bool byte, std::function<std::string()> bytes) -> Case& {
    Case c = make(Format::kLcmLog, family, base, detail, expect, what);
    c.bytes = std::move(bytes);
    c.byte_offset = byte;
    return b.add(c);
  };
  add("control", "as_written", Expect::kAccepted, "the grading session's log as written", false, [t] { return *t; });
  // Every offset within the first event.
  const LogEvent& first = ev.front();
  for (std::size_t k = 0; k < first.size; ++k) {
    char id[48];
    std::snprintf(id, sizeof id, "event0_at_%03zu", k);
    add("truncate", id, Expect::kRefused,
        "cut after byte " + std::to_string(k) + " (first event: " + first.channel + ", " + std::to_string(first.size) +
            " bytes)",
        k > 0, [t, k] { return t->substr(0, k); });
  }
  // Inside later events, and exactly between events (whole events lost, the
  // session's "end" among them).
  const std::size_t mid = ev.size() / 2, last = ev.size() - 1;
  for (const auto& [id, at] : std::vector<std::pair<std::string, std::size_t>>{
           {"event1_header", ev[1].at + 10},
           {"event2_channel", ev[2].at + 30},
           {"event3_data", ev[3].data_at + ev[3].data_len / 2},
           {"mid_event_header", ev[mid].at + 27},
           {"mid_event_data", ev[mid].data_at + 3},
           {"last_event_data", ev[last].data_at + ev[last].data_len / 2},
           {"last_byte", t->size() - 1}}) {
    add("truncate", id, Expect::kRefused, "cut after byte " + std::to_string(at), true,
        [t, at = at] { return t->substr(0, at); });
  }
  for (const auto& [id, at] : std::vector<std::pair<std::string, std::size_t>>{
           {"after_event1", ev[1].at}, {"after_event3", ev[3].at}, {"after_mid_event", ev[mid].at},
           {"before_end_event", ev[last].at}}) {
    add("truncate_boundary", id, Expect::kRefused,
        "cut between events after byte " + std::to_string(at) + " (the rest of the session, and its end event, lost)",
        false, [t, at = at] { return t->substr(0, at); });
  }
  // Length fields and sync words.
  const auto put32 = [](std::string& s, std::size_t at, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) s[at + static_cast<std::size_t>(k)] = static_cast<char>((v >> (24 - 8 * k)) & 0xff);
  };
  struct F {
    const char* id;
    std::size_t event;
    std::size_t field;  // 0 sync, 20 channel length, 24 data length
    std::uint32_t value;
  };
  for (const F& f : std::vector<F>{{"event0_channel_len_7fffffff", 0, 20, 0x7fffffffu},
                                   {"event0_data_len_7fffffff", 0, 24, 0x7fffffffu},
                                   {"mid_channel_len_7fffffff", mid, 20, 0x7fffffffu},
                                   {"mid_data_len_7fffffff", mid, 24, 0x7fffffffu},
                                   {"event0_data_len_ffffffff", 0, 24, 0xffffffffu},
                                   {"event0_data_len_0", 0, 24, 0u},
                                   {"event0_channel_len_0", 0, 20, 0u},
                                   {"event0_data_len_plus_1", 0, 24, static_cast<std::uint32_t>(ev[0].data_len + 1)},
                                   {"event0_data_len_minus_1", 0, 24, static_cast<std::uint32_t>(ev[0].data_len - 1)},
                                   {"event0_bad_sync", 0, 0, 0xEDA1DA02u},
                                   {"event3_bad_sync", 3, 0, 0xDEADBEEFu},
                                   {"mid_bad_sync", mid, 0, 0x00000000u},
                                   {"last_bad_sync", last, 0, 0xEDA1DA00u}}) {
    const std::size_t at = ev[f.event].at + f.field;
    const std::uint32_t value = f.value;
    add(f.field == 0 ? "sync_word" : "length_field", f.id, Expect::kRefused,
        std::string("event ") + std::to_string(f.event) + (f.field == 0 ? " sync word" : f.field == 20 ? " channel length" : " data length") +
            " set to " + std::to_string(value),
        true, [t, at, value, put32] {
          std::string s = *t;
          put32(s, at, value);
          return s;
        });
  }
  // Payloads of the applied controls (control_t: fingerprint, then
  // sender_id, seq, sender_time_us, sim_step, drive_left, drive_right, lift,
  // tilt, throttle at 8-byte steps, parking_brake).
  std::vector<std::size_t> applied;
  for (std::size_t k = 0; k < ev.size(); ++k)
    if (ev[k].channel == "SKIDSIM_CONTROL_APPLIED") applied.push_back(k);
  if (applied.size() >= 4) {
    const auto patch = [t](std::size_t at, std::string bytes) {
      return [t, at, bytes] {
        std::string s = *t;
        s.replace(at, bytes.size(), bytes);
        return s;
      };
    };
    const auto be_double = [](double v) {
      std::uint64_t u;
      std::memcpy(&u, &v, 8);
      std::string s(8, '\0');
      for (int k = 0; k < 8; ++k) s[static_cast<std::size_t>(k)] = static_cast<char>((u >> (56 - 8 * k)) & 0xff);
      return s;
    };
    const LogEvent& c1 = ev[applied[1]];
    add("payload", "applied_fingerprint", Expect::kRefused, "an applied control's type fingerprint changed", false,
        patch(c1.data_at, std::string(8, '\x5a')));
    add("payload", "applied_drive_nan", Expect::kRefused, "an applied control's drive_left NaN", false,
        patch(c1.data_at + 40, be_double(std::nan(""))));
    add("payload", "applied_throttle_2", Expect::kRefused, "an applied control's throttle 2", false,
        patch(c1.data_at + 72, be_double(2.0)));
    add("payload", "applied_lift_huge", Expect::kRefused, "an applied control's lift 1e308", false,
        patch(c1.data_at + 56, be_double(1e308)));
    add("payload", "applied_sim_step_odd", Expect::kRefused, "an applied control's sim_step not on a tick", false,
        patch(c1.data_at + 32, std::string("\0\0\0\0\0\0\0\x03", 8)));
    add("payload", "applied_short", Expect::kRefused, "an applied control one byte short (lengths consistent)", false,
        [t, c1, put32] {
          std::string s = *t;
          put32(s, c1.at + 24, static_cast<std::uint32_t>(c1.data_len - 1));
          s.erase(c1.data_at + c1.data_len - 1, 1);
          return s;
        });
    const LogEvent& c2 = ev[applied[2]];
    const LogEvent& c3 = ev[applied[3]];
    add("order", "applied_swapped", Expect::kRefused, "two applied controls swapped", false, [t, c2, c3] {
      // c2 and c3 may have an event between them; swap just their bytes.
      std::string s = t->substr(0, c2.at) + t->substr(c3.at, c3.size) + t->substr(c2.at + c2.size, c3.at - c2.at - c2.size) +
                      t->substr(c2.at, c2.size) + t->substr(c3.at + c3.size);
      return s;
    });
    add("order", "applied_repeated", Expect::kRefused, "an applied control written twice", false,
        [t, c2] { return t->substr(0, c2.at + c2.size) + t->substr(c2.at, c2.size) + t->substr(c2.at + c2.size); });
    add("order", "applied_dropped", Expect::kRefused, "an applied control removed", false,
        [t, c2] { return t->substr(0, c2.at) + t->substr(c2.at + c2.size); });
    add("order", "no_applied_controls", Expect::kRefused, "every applied control removed", false, [t, ev] {
      std::string s;
      for (const LogEvent& e : ev)
        if (e.channel != "SKIDSIM_CONTROL_APPLIED") s += t->substr(e.at, e.size);
      return s;
    });
    add("order", "event_channel_renamed", Expect::kEither, "a state event's channel renamed (unknown channel)", false,
        [t, ev] {
          std::string s = *t;
          for (const LogEvent& e : ev)
            if (e.channel == "SKIDSIM_STATE") {
              s[e.at + 28] = 'Z';
              break;
            }
          return s;
        });
  }
  add("other_session", "twice", Expect::kRefused, "the log followed by itself", false, [t] { return *t + *t; });
  {
    const std::string other = read_file(a.other_log);
    add("other_session", "driving_course_log", Expect::kRefused,
        "the log of a driving_course session replayed against grading", false, [other] { return other; });
  }
  add("garbage", "random_4k", Expect::kRefused, "4 KiB of pseudo-random bytes", true, [] {
    std::string s(4096, '\0');
    std::uint32_t x = 777;
    for (char& c : s) {
      x = x * 1664525u + 1013904223u;
      c = static_cast<char>(x >> 24);
    }
    return s;
  });
  add("garbage", "xml", Expect::kRefused, "the exercise's XML instead of a log", true,
      [] { return read_file(source_dir() + "/scenarios/grading.xml"); });
  add("garbage", "sync_words_only", Expect::kRefused, "1000 sync words and nothing else", true, [] {
    std::string s;
    for (int k = 0; k < 1000; ++k) s += std::string("\xED\xA1\xDA\x01", 4);
    return s;
  });
  add_replacements(b, Format::kLcmLog, base, t, false);
}

// ---------------------------------------------------------------------------
// The command line

void add_cli_cases(Builder& b) {
  struct Command {
    std::string id;
    std::vector<std::string> args;  // with every option the cases change, as "--opt", "value" pairs
    std::vector<std::string> numeric;
    std::vector<std::string> integer;  // of those, the ones that take whole numbers
  };
  const std::string ex = "{SRC}/scenarios/grading.xml", script = "{SRC}/scenarios/grading.operator.xml";
  const std::vector<Command> commands = {
      {"pour",
       {"pour", "--site-m", "1", "--cell-m", "0.05", "--layer-m", "0", "--rate-kg-s", "20", "--pour-s", "0.5",
        "--hopper-m", "0.1", "--settle-s", "1", "--out", "{DIR}/out"},
       {"--site-m", "--cell-m", "--layer-m", "--rate-kg-s", "--pour-s", "--hopper-m", "--settle-s"},
       {}},
      {"push",
       {"push", "--cells-per-m", "10", "--layer-m", "0.4", "--depth-m", "0.2", "--width-m", "1", "--speed-m-s", "1",
        "--distance-m", "0.5", "--out", "{DIR}/out"},
       {"--cells-per-m", "--layer-m", "--depth-m", "--width-m", "--speed-m-s", "--distance-m"},
       {}},
      {"dig", {"dig", "--cells-per-m", "10", "--bank-m", "0.5", "--out", "{DIR}/out"}, {"--cells-per-m", "--bank-m"}, {}},
      {"run", {"run", ex, "--script", script, "--max-s", "0.5", "--out", "{DIR}/out"}, {"--max-s"}, {}},
      {"run_record",
       {"run", ex, "--script", script, "--max-s", "0.3", "--record", "--fps", "4", "--frame-width", "64",
        "--frame-height", "36", "--out", "{DIR}/out"},
       {"--fps", "--frame-width", "--frame-height"},
       {"--frame-width", "--frame-height"}},
      {"render",
       {"render", ex, "--width", "64", "--height", "36", "--script", script, "--at-s", "0.2", "--out",
        "{DIR}/frame.png"},
       {"--width", "--height", "--at-s"},
       {"--width", "--height"}},
      {"review", {"review", "{DIR}/run", "--fps", "2", "--width", "64", "--height", "36"}, {"--fps", "--width", "--height"},
       {"--width", "--height"}},
      {"batch", {"batch", "{DIR}/list.txt", "--jobs", "1", "--index", "1", "--out", "{DIR}/out"}, {"--jobs", "--index"},
       {"--jobs", "--index"}},
      {"view", {"view", "{DIR}/run", "--fps", "2", "--width", "64", "--height", "36", "--out", "{DIR}/out"},
       {"--fps", "--width", "--height"},
       {"--width", "--height"}},
      {"operator", {"operator", script, "--lcm", "memq://", "--session", "corpus", "--idle-s", "0.3"}, {"--idle-s"}, {}},
  };
  struct V {
    const char* id;
    const char* text;
    Expect expect;
  };
  const std::vector<V> values = {{"zero", "0", Expect::kEither},     {"negative", "-1", Expect::kRefused},
                                 {"huge", "1e308", Expect::kEither}, {"nan", "nan", Expect::kRefused},
                                 {"inf", "inf", Expect::kRefused},   {"text", "abc", Expect::kRefused}};
  for (const Command& c : commands) {
    // `skidsim operator` with no simulator stops after --idle-s with exit 1:
    // no control for it; its values in range may end so.
    const bool is_operator = c.id == "operator";
    if (!is_operator) {
      Case control = make(Format::kCli, "control", c.id, c.id, Expect::kAccepted, "the command as it is");
      control.args = c.args;
      b.add(control);
    }
    for (const std::string& opt : c.numeric) {
      for (const V& v : values) {
        Case k = make(Format::kCli, "number", c.id, c.id + opt + "_" + v.id, v.expect, opt + "=" + v.text);
        std::vector<std::string> args;
        for (std::size_t i = 0; i < c.args.size(); ++i) {
          if (c.args[i] == opt && i + 1 < c.args.size()) {
            args.push_back(opt + "=" + v.text);
            ++i;
          } else {
            args.push_back(c.args[i]);
          }
        }
        k.args = args;
        k.where = {opt};
        if (is_operator && v.expect == Expect::kEither) k.ok_codes = {0, 1, 2};
        b.add(k);
      }
      if (std::find(c.integer.begin(), c.integer.end(), opt) != c.integer.end()) {
        for (const V& v : std::vector<V>{{"fraction", "1.5", Expect::kEither}, {"int_overflow", "4294967297", Expect::kRefused}}) {
          Case k = make(Format::kCli, "number", c.id, c.id + opt + "_" + v.id, v.expect, opt + "=" + v.text);
          std::vector<std::string> args;
          for (std::size_t i = 0; i < c.args.size(); ++i) {
            if (c.args[i] == opt && i + 1 < c.args.size()) {
              args.push_back(opt + "=" + v.text);
              ++i;
            } else {
              args.push_back(c.args[i]);
            }
          }
          k.args = args;
          k.where = {opt};
          b.add(k);
        }
      }
    }
  }
  // Named options and positionals.
  struct N {
    std::string id;
    std::vector<std::string> args;
    std::string where;
  };
  for (const N& n : std::vector<N>{
           {"pour_soil_unknown", {"pour", "--site-m", "1", "--soil", "zz_unknown", "--out", "{DIR}/out"}, "zz_unknown"},
           {"pour_out_empty", {"pour", "--site-m", "1", "--out="}, "--out"},
           {"pour_out_dot", {"pour", "--site-m", "1", "--out", "."}, "--out"},
           {"pour_out_dotdot", {"pour", "--site-m", "1", "--out", ".."}, "--out"},
           {"pour_out_slash", {"pour", "--site-m", "1", "--out", "/"}, "--out"},
           {"pour_unknown_option", {"pour", "--zz-unknown", "1", "--out", "{DIR}/out"}, "--zz-unknown"},
           {"run_mode_bogus", {"run", ex, "--script", script, "--mode", "zz", "--out", "{DIR}/out"}, "--mode"},
           {"run_camera_bogus",
            {"run", ex, "--script", script, "--max-s", "0.2", "--record", "--camera", "zz", "--out", "{DIR}/out"},
            "zz"},
           {"run_backend_bogus",
            {"run", ex, "--script", script, "--max-s", "0.2", "--record", "--render-backend", "zz", "--out",
             "{DIR}/out"},
            "zz"},
           {"run_no_exercise", {"run", "--script", script, "--out", "{DIR}/out"}, "exercise"},
           {"run_script_and_replay",
            {"run", ex, "--script", script, "--replay", "{DIR}/run/session.lcmlog", "--out", "{DIR}/out"},
            "--replay"},
           {"run_lockstep_with_script", {"run", ex, "--script", script, "--mode", "lockstep", "--out", "{DIR}/out"},
            "lockstep"},
           {"run_lcm_bogus_url", {"run", ex, "--script", script, "--max-s", "0.2", "--lcm", "zz://nowhere", "--out", "{DIR}/out"},
            "zz://nowhere"},
           {"render_camera_bogus", {"render", ex, "--camera", "zz", "--width", "64", "--height", "36", "--out", "{DIR}/frame.png"},
            "zz"},
           {"review_not_a_run", {"review", "{DIR}"}, "report.json"},
           {"check_loader_is_exercise", {"check", "--loader", ex}, "grading.xml"},
           {"soils_table_is_exercise", {"soils", "--table", ex}, "grading.xml"},
           {"unknown_subcommand", {"zz-unknown"}, "zz-unknown"},
           {"no_subcommand", {}, "subcommand"},
       }) {
    Case k = make(Format::kCli, "named", n.id, n.id, Expect::kRefused, "skidsim " + [&] {
      std::string s;
      for (const std::string& a : n.args) s += a + " ";
      return s;
    }());
    k.args = n.args;
    k.where = {n.where};
    b.add(k);
  }
}

}  // namespace

const std::vector<Case>& corpus() {
  static const std::vector<Case> all = [] {
    Builder b;
    std::vector<XmlFile> exercises, scripts;
    for (const auto& entry : fs::directory_iterator(source_dir() + "/scenarios")) {
      const std::string name = entry.path().filename().string();
      if (name.size() > 4 && name.compare(name.size() - 4, 4, ".xml") == 0)
        (name.find(".operator.xml") != std::string::npos ? scripts : exercises).push_back(read_xml("scenarios/" + name));
    }
    const auto by_name = [](const XmlFile& x, const XmlFile& y) { return x.rel < y.rel; };
    std::sort(exercises.begin(), exercises.end(), by_name);
    std::sort(scripts.begin(), scripts.end(), by_name);
    const auto pick = [](const std::vector<XmlFile>& v, const std::string& rel) -> const XmlFile& {
      for (const XmlFile& x : v)
        if (x.rel == rel) return x;
      return v.front();
    };
    add_xml_cases(b, Format::kExercise, exercises, pick(exercises, "scenarios/grading.xml"), true);
    add_xml_cases(b, Format::kScript, scripts, pick(scripts, "scenarios/grading.operator.xml"), true);
    const std::vector<XmlFile> soils = {read_xml("assets/soils.xml")};
    add_xml_cases(b, Format::kSoilTable, soils, soils.front(), true);
    const std::vector<XmlFile> params = {read_xml("assets/loader/skidsteer.params.xml")};
    add_xml_cases(b, Format::kLoaderParams, params, params.front(), true);
    const std::vector<XmlFile> urdf = {read_xml("assets/loader/skidsteer.urdf")};
    add_xml_cases(b, Format::kUrdf, urdf, urdf.front(), false);
    add_mesh_cases(b);
    const Artifacts& a = artifacts();
    add_heightmap_cases(b, a);
    add_log_cases(b, a);
    add_cli_cases(b);
    return std::move(b.cases);
  }();
  return all;
}

}  // namespace skidsim::reliability
