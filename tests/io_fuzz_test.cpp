// The parsers under random mutation (the issue: "a corpus of bad exercises,
// scripts, messages and truncated logs: each gets its clear error; none
// crashes"). The shipped files are the seeds: exercises, operator scripts,
// the loader's parameters and URDF, the soil table. Each mutant (byte flips,
// truncation, lines deleted or duplicated, attribute values replaced by
// "nan", "inf", "1e400", "", "abc"..., elements duplicated or renamed,
// attributes renamed or dropped, junk inserted) must either load or throw
// io::InputError naming the file, with a line inside it; any other
// exception is a failure (a crash ends the binary; the mutant is then left
// in the temporary directory printed at the start). LCM: random bytes,
// truncated and garbled control_t through the bridge are counted, never
// applied unchecked; truncated LCM logs read back only whole events.
//
// Deterministic: a fixed seed (SKIDSIM_FUZZ_SEED overrides it), no clock.
// SKIDSIM_FUZZ_ITERATIONS=K runs K times as many mutants (default 1).
// Longer runs with sanitizers: scripts/fuzz.sh (libFuzzer, fuzz/).
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <typeinfo>
#include <fcntl.h>
#include <unistd.h>
#include <vector>

#include "io/atomic_file.h"
#include "io/control_input.h"
#include "io/exercise.h"
#include "io/lcm_bridge.h"
#include "io/lcm_log.h"
#include "io/loader_files.h"
#include "io/operator_script.h"
#include "io/soil_table.h"

namespace skidsim::io {
namespace {

namespace fs = std::filesystem;

std::uint64_t fuzz_seed() {
  const char* s = std::getenv("SKIDSIM_FUZZ_SEED");
  return s ? std::strtoull(s, nullptr, 10) : 0x5eed5c1d51e0ULL;
}

// Base counts are scaled by SKIDSIM_FUZZ_ITERATIONS (a factor, at least 1).
int iterations(int base) {
  const char* s = std::getenv("SKIDSIM_FUZZ_ITERATIONS");
  const long k = s ? std::strtol(s, nullptr, 10) : 1;
  return base * static_cast<int>(std::max(1L, k));
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
}

fs::path source_dir() { return fs::path(default_loader_path()).parent_path().parent_path().parent_path(); }

// The shipped exercises (or their operator scripts), in name order.
std::vector<fs::path> shipped(const char* folder, bool scripts) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(source_dir() / folder)) {
    const std::string name = e.path().filename().string();
    const bool script = name.size() > 13 && name.compare(name.size() - 13, 13, ".operator.xml") == 0;
    if (e.path().extension() == ".xml" && script == scripts) out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// ---------------------------------------------------------------------------
// Mutations of an XML text.

class Mutator {
 public:
  explicit Mutator(std::mt19937_64& rng) : rng_(rng) {}

  // One to three random mutations of `seed`.
  std::string mutate(std::string s) {
    const int n = pick(100) < 60 ? 1 : (pick(100) < 65 ? 2 : 3);
    for (int k = 0; k < n; ++k) mutate_once(s);
    return s;
  }

 private:
  struct Span {
    size_t name_at, name_len, value_at, value_len;
  };

  size_t pick(size_t n) { return n == 0 ? 0 : std::uniform_int_distribution<size_t>(0, n - 1)(rng_); }
  template <class T>
  const T& one_of(const std::vector<T>& v) {
    return v[pick(v.size())];
  }

  // The attributes (name="value") of the text.
  static std::vector<Span> attributes(const std::string& s) {
    std::vector<Span> out;
    for (size_t eq = s.find("=\""); eq != std::string::npos; eq = s.find("=\"", eq + 1)) {
      size_t b = eq;
      while (b > 0 && (std::isalnum(static_cast<unsigned char>(s[b - 1])) || s[b - 1] == '_' || s[b - 1] == ':')) --b;
      const size_t end = s.find('"', eq + 2);
      if (b == eq || end == std::string::npos) continue;
      out.push_back({b, eq - b, eq + 2, end - (eq + 2)});
    }
    return out;
  }
  // Positions of '<' opening an element (a letter follows).
  static std::vector<size_t> element_starts(const std::string& s) {
    std::vector<size_t> out;
    for (size_t i = 0; i + 1 < s.size(); ++i)
      if (s[i] == '<' && std::isalpha(static_cast<unsigned char>(s[i + 1]))) out.push_back(i);
    return out;
  }
  static std::string name_at(const std::string& s, size_t at) {
    size_t e = at;
    while (e < s.size() && (std::isalnum(static_cast<unsigned char>(s[e])) || s[e] == '_' || s[e] == ':' || s[e] == '-'))
      ++e;
    return s.substr(at, e - at);
  }
  static std::vector<size_t> line_starts(const std::string& s) {
    std::vector<size_t> out{0};
    for (size_t i = 0; i < s.size(); ++i)
      if (s[i] == '\n' && i + 1 < s.size()) out.push_back(i + 1);
    return out;
  }

  std::string number_token() {
    static const std::vector<std::string> tokens = {
        "nan", "NaN", "-nan", "inf", "-inf", "infinity", "-1e309", "1e309", "1e400", "-1e400", "", " ", "abc",
        "1e308", "-1e308", "1.7976931348623157e308", "4.9e-324", "1e-320", "0", "-0", "0x10", "0x1p3", "1e",
        "--1", "+-1", "1..2", ".", "-", "+", "1 2", "1 2 3", "1 2 3 4 5", "9223372036854775808",
        "-9223372036854775809", "2147483648", "-2147483649", "4294967296", "99999999999999999999", "-1",
        "-1000000", "1000000", "1e7", "1e12", "-1e12", "3abc", "33deg", "1,5", "\t1\n", "&#49;", "1&#x20;2"};
    switch (pick(4)) {
      case 0: return std::to_string(std::uniform_int_distribution<long long>(-1000000000000LL, 1000000000000LL)(rng_));
      case 1: {
        std::ostringstream o;
        o << (pick(2) ? "-" : "") << std::uniform_real_distribution<double>(0, 10)(rng_) << "e"
          << static_cast<int>(pick(700)) - 350;
        return o.str();
      }
      default: return one_of(tokens);
    }
  }

  void mutate_once(std::string& s) {
    static const std::vector<std::string> junk = {
        "&", "&amp;", "&#0;", "&#x110000;", "&bogus;", "<", ">", "\"", "'", "<!--", "-->", "]]>", "<![CDATA[",
        "<?xml version=\"1.0\"?>", "\xff\xfe", "\xc3", "\xef\xbb\xbf", std::string(1, '\0'), "<a>", "</a>", "<a/>",
        "/>", "=", "\n\n\n", "<!DOCTYPE x [<!ENTITY e \"e\">]>"};
    std::vector<Span> attrs = attributes(s);
    switch (pick(12)) {
      case 0:  // byte flip
        if (!s.empty()) {
          const size_t at = pick(s.size());
          switch (pick(3)) {
            case 0: s[at] = static_cast<char>(s[at] ^ (1 << pick(8))); break;
            case 1: s[at] = static_cast<char>(pick(256)); break;
            default: s[at] = "<>\"&/= \n\t!?-"[pick(13)];
          }
        }
        break;
      case 1:  // truncation
        s.resize(pick(s.size() + 1));
        break;
      case 2:
      case 3: {  // delete or duplicate a line
        const std::vector<size_t> starts = line_starts(s);
        const size_t l = pick(starts.size());
        const size_t b = starts[l];
        size_t e = s.find('\n', b);
        e = e == std::string::npos ? s.size() : e + 1;
        if (pick(2)) s.erase(b, e - b);
        else s.insert(e, s.substr(b, e - b) + (e == s.size() ? "\n" : ""));
        break;
      }
      case 4:
      case 5:
      case 6: {  // an attribute value: a bad number, or one of its numbers replaced
        if (attrs.empty()) break;
        std::vector<Span> numeric;
        for (const Span& a : attrs)
          if (a.value_len > 0 && std::strchr("0123456789-+.", s[a.value_at])) numeric.push_back(a);
        const Span a = !numeric.empty() && pick(5) ? one_of(numeric) : one_of(attrs);
        std::string value = s.substr(a.value_at, a.value_len);
        std::vector<size_t> word_starts;
        for (size_t i = 0; i < value.size(); ++i)
          if (value[i] != ' ' && (i == 0 || value[i - 1] == ' ')) word_starts.push_back(i);
        if (word_starts.size() > 1 && pick(2)) {
          const size_t w = one_of(word_starts);
          size_t we = value.find(' ', w);
          we = we == std::string::npos ? value.size() : we;
          value.replace(w, we - w, number_token());
        } else {
          value = number_token();
        }
        s.replace(a.value_at, a.value_len, value);
        break;
      }
      case 7: {  // swap in another attribute's value
        if (attrs.size() < 2) break;
        const Span a = one_of(attrs), b = one_of(attrs);
        s.replace(a.value_at, a.value_len, s.substr(b.value_at, b.value_len));
        break;
      }
      case 8: {  // rename or drop an attribute, or repeat it
        if (attrs.empty()) break;
        const Span a = one_of(attrs);
        switch (pick(4)) {
          case 0: s.insert(a.name_at + a.name_len, "_x"); break;
          case 1: {  // another attribute's name (of this element: a repeated attribute)
            const Span b = one_of(attrs);
            s.replace(a.name_at, a.name_len, s.substr(b.name_at, b.name_len));
            break;
          }
          case 2: {  // the whole attribute twice
            const size_t e = a.value_at + a.value_len + 1;
            s.insert(e, " " + s.substr(a.name_at, e - a.name_at));
            break;
          }
          default: s.erase(a.name_at, a.value_at + a.value_len + 1 - a.name_at); break;
        }
        break;
      }
      case 9: {  // duplicate an element
        const std::vector<size_t> starts = element_starts(s);
        if (starts.empty()) break;
        const size_t b = one_of(starts);
        const std::string name = name_at(s, b + 1);
        const size_t gt = s.find('>', b);
        if (gt == std::string::npos) break;
        size_t e = gt + 1;
        if (s[gt - 1] != '/') {
          const size_t close = s.find("</" + name + ">", gt);
          if (close != std::string::npos) e = close + name.size() + 3;
        }
        s.insert(e, "\n" + s.substr(b, e - b));
        break;
      }
      case 10: {  // rename an element (its end tag too)
        const std::vector<size_t> starts = element_starts(s);
        if (starts.empty()) break;
        const size_t b = one_of(starts);
        const std::string name = name_at(s, b + 1);
        std::string to;
        switch (pick(3)) {
          case 0: to = name + "x"; break;
          case 1: to = name_at(s, one_of(starts) + 1); break;
          default: to = pick(2) ? "bogus" : "";
        }
        const size_t gt = s.find('>', b);
        if (gt != std::string::npos && s[gt - 1] != '/' && pick(4)) {
          const size_t close = s.find("</" + name + ">", gt);
          if (close != std::string::npos) s.replace(close + 2, name.size(), to);
        }
        s.replace(b + 1, name.size(), to);
        break;
      }
      default:  // insert junk
        s.insert(pick(s.size() + 1), one_of(junk));
        break;
    }
  }

  std::mt19937_64& rng_;
};

// ---------------------------------------------------------------------------
// The check: a parse either succeeds or throws InputError naming one of the
// family's files (and a line within it, where it gives one).

struct Tally {
  int loaded = 0, rejected = 0, failures = 0;
};

class ParserFuzz : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("skidsim_fuzz_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // The exercise's neighbours (scripts, a loader folder) and the loader's
    // (URDF, meshes): mutants are written beside them, so references resolve.
    for (const fs::path& script : shipped("scenarios", true)) fs::copy_file(script, dir_ / script.filename());
    fs::copy(fs::path(default_loader_path()).parent_path(), dir_ / "loader", fs::copy_options::recursive);
    std::printf("[ fuzz     ] seed %llu, x%d, mutants in %s\n", static_cast<unsigned long long>(fuzz_seed()),
                iterations(1), dir_.c_str());
  }
  // (A failing mutant is kept in skidsim_fuzz_failures/; after a crash the
  // folder stays, the mutant that crashed in it.)
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  // Lines of a file, for the plausibility of a line number (tinyxml2 may
  // point just past the last newline).
  static long line_count(const std::string& text) { return std::count(text.begin(), text.end(), '\n') + 1; }

  // Runs `parse` on the mutant (already written to files[0]; the other
  // files are those its errors may name, such as the URDF of a loader).
  template <class Parse>
  void check(Parse&& parse, const std::vector<std::string>& files, const std::string& label, Tally& tally) {
    std::string failure;
    try {
      parse();
      ++tally.loaded;
      return;
    } catch (const InputError& e) {
      ++tally.rejected;
      const std::string msg = e.what();
      if (std::getenv("SKIDSIM_FUZZ_VERBOSE")) std::printf("%s\n", msg.c_str());
      bool named = false;
      for (const std::string& f : files) {
        const size_t at = msg.find(f + ":");
        if (at == std::string::npos) continue;
        named = true;
        const char* p = msg.c_str() + at + f.size() + 1;
        char* end = nullptr;
        const long line = std::strtol(p, &end, 10);
        if (end != p && *end == ':') {
          const long lines = line_count(read_text(f));
          if (line < 0 || line > lines)
            failure = "line " + std::to_string(line) + " of a " + std::to_string(lines) + "-line file: " + msg;
        }
        break;
      }
      if (!named) failure = "the message names none of the files: " + msg;
    } catch (const std::exception& e) {
      failure = std::string("not an InputError but ") + typeid(e).name() + ": " + e.what();
    } catch (...) {
      failure = "a non-standard exception";
    }
    if (failure.empty()) return;
    if (++tally.failures > 20) return;  // enough to act on
    const fs::path kept = fs::temp_directory_path() / "skidsim_fuzz_failures";
    fs::create_directories(kept);
    const fs::path copy = kept / (label + fs::path(files[0]).extension().string());
    fs::copy_file(files[0], copy, fs::copy_options::overwrite_existing);
    ADD_FAILURE() << label << " (kept as " << copy.string() << "): " << failure;
  }

  // `count` mutants of the seeds, each written to `mutant_path` and parsed.
  template <class Parse>
  Tally fuzz(const std::string& family, const std::vector<std::string>& seeds, const std::string& mutant_path,
             const std::vector<std::string>& files, int count, std::uint64_t salt, Parse&& parse) {
    std::mt19937_64 rng(fuzz_seed() ^ salt);
    Mutator mutator(rng);
    Tally tally;
    for (int i = 0; i < count; ++i) {
      const std::string& seed = seeds[static_cast<size_t>(i) % seeds.size()];
      write_text(mutant_path, mutator.mutate(seed));
      check(parse, files, family + "_" + std::to_string(i), tally);
    }
    std::printf("[ fuzz     ] %s: %d mutants, %d loaded, %d rejected with InputError, %d failures\n", family.c_str(),
                count, tally.loaded, tally.rejected, tally.failures);
    return tally;
  }

  static fs::path dir_;
};

fs::path ParserFuzz::dir_;

TEST_F(ParserFuzz, ExercisesLoadOrNameFileAndLine) {
  std::vector<std::string> seeds;
  for (const fs::path& p : shipped("scenarios", false)) seeds.push_back(read_text(p));
  // One more names its files: the loader's parameters and a script.
  const std::string pile = read_text(source_dir() / "scenarios" / "pile_to_zone.xml");
  seeds.push_back(replaced(
      replaced(pile, "<machine position", "<machine loader=\"loader/skidsteer.params.xml\" position"),
      "<operator source=\"lcm\" channel=\"SKIDSIM_CONTROL\" watchdog_ms=\"200\"/>",
      "<operator source=\"script\" script=\"pile_to_zone.operator.xml\"/>"));
  const std::string mutant = (dir_ / "mutant.xml").string();
  for (const std::string& seed : seeds) {
    write_text(mutant, seed);
    EXPECT_NO_THROW(load_exercise(mutant)) << "the seeds are valid";
  }
  const Tally t = fuzz("exercise", seeds, mutant, {mutant}, iterations(4000), 1, [&] { load_exercise(mutant); });
  EXPECT_GT(t.rejected, 0);
}

TEST_F(ParserFuzz, OperatorScriptsLoadOrNameFileAndLine) {
  std::vector<std::string> seeds;
  for (const fs::path& p : shipped("scenarios", true)) seeds.push_back(read_text(p));
  const std::string mutant = (dir_ / "mutant.operator.xml").string();
  for (const std::string& seed : seeds) {
    write_text(mutant, seed);
    EXPECT_NO_THROW(load_operator_script(mutant)) << "the seeds are valid";
  }
  const Tally t = fuzz("operator_script", seeds, mutant, {mutant}, iterations(3000), 2,
                       [&] { load_operator_script(mutant); });
  EXPECT_GT(t.rejected, 0);
}

TEST_F(ParserFuzz, SoilTablesLoadOrNameFileAndLine) {
  const std::string seed = read_text(default_soil_table_path());
  const std::string mutant = (dir_ / "mutant.soils.xml").string();
  const Tally t = fuzz("soil_table", {seed}, mutant, {mutant}, iterations(2000), 3,
                       [&] { load_soil_table(mutant); });
  EXPECT_GT(t.rejected, 0);
}

TEST_F(ParserFuzz, LoaderParametersLoadOrNameFileAndLine) {
  const std::string seed = read_text(default_loader_path());
  const std::string mutant = (dir_ / "loader" / "mutant.params.xml").string();
  const std::string urdf = (dir_ / "loader" / "skidsteer.urdf").string();
  const Tally t = fuzz("loader_params", {seed}, mutant, {mutant, urdf}, iterations(500), 4,
                       [&] { load_loader(mutant); });
  EXPECT_GT(t.rejected, 0);
}

TEST_F(ParserFuzz, LoaderUrdfLoadsOrNamesFileAndLine) {
  const std::string seed = read_text(fs::path(default_loader_path()).parent_path() / "skidsteer.urdf");
  const std::string params = (dir_ / "loader" / "mutant_urdf.params.xml").string();
  const std::string mutant = (dir_ / "loader" / "mutant.urdf").string();
  write_text(params, replaced(read_text(default_loader_path()), "urdf=\"skidsteer.urdf\"", "urdf=\"mutant.urdf\""));
  const Tally t = fuzz("loader_urdf", {seed}, mutant, {mutant, params}, iterations(500), 5,
                       [&] { load_loader(params); });
  EXPECT_GT(t.rejected, 0);
}

// ---------------------------------------------------------------------------
// LCM: control messages through the bridge, and logs.

skidsim_lcm::control_t valid_command(std::int64_t seq) {
  skidsim_lcm::control_t c{};
  c.sender_id = 7;
  c.seq = seq;
  c.sender_time_us = 1000 * seq;
  c.sim_step = 5 * seq;
  c.drive_left = 0.5;
  c.drive_right = -0.25;
  c.lift = 0.1;
  c.tilt = -0.2;
  c.throttle = 0.9;
  c.parking_brake = false;
  return c;
}

std::vector<std::uint8_t> encoded(const skidsim_lcm::control_t& c) {
  std::vector<std::uint8_t> bytes(static_cast<size_t>(c.getEncodedSize()));
  c.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

TEST(ControlFuzz, RandomTruncatedAndGarbledBytesAreCountedNeverApplied) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  ControlInput input(0.2);
  LcmBridge bridge(lcm, LcmChannels{}, &input);
  std::mt19937_64 rng(fuzz_seed() ^ 6);
  const auto byte = [&] { return static_cast<std::uint8_t>(std::uniform_int_distribution<int>(0, 255)(rng)); };
  const std::vector<std::uint8_t> valid = encoded(valid_command(1));
  const size_t size = valid.size();  // 8 bytes of fingerprint, then the fields
  double now = 0.0;
  std::int64_t sent = 0, expect_malformed = 0;

  // Publishes `bytes` and checks the one message was counted the way `malformed` says.
  const auto send = [&](const std::vector<std::uint8_t>& bytes, bool malformed) {
    const ControlStats before = input.stats();
    const std::uint8_t dummy = 0;
    lcm.publish(LcmChannels{}.control, bytes.empty() ? &dummy : bytes.data(), static_cast<unsigned>(bytes.size()));
    now += 0.01;
    ASSERT_EQ(bridge.poll(now), 1);
    ++sent;
    const ControlStats& s = input.stats();
    const std::int64_t counted = (s.malformed - before.malformed) + (s.accepted - before.accepted) +
                                 (s.rejected_nan - before.rejected_nan) + (s.rejected_stale - before.rejected_stale);
    ASSERT_EQ(counted, 1) << "each message is counted once";
    if (malformed) {
      ++expect_malformed;
      ASSERT_EQ(s.malformed - before.malformed, 1) << "bytes that cannot decode are malformed (" << bytes.size() << " bytes)";
    }
    const vehicle::LoaderControls c = input.controls(now);
    for (double v : {c.drive_left, c.drive_right, c.lift, c.tilt}) ASSERT_TRUE(std::isfinite(v) && std::abs(v) <= 1.0) << v;
    ASSERT_TRUE(std::isfinite(c.throttle) && c.throttle >= 0.0 && c.throttle <= 1.0) << c.throttle;
  };

  // Every truncation of a valid message, and random bytes of every length.
  for (size_t n = 0; n < size; ++n) send(std::vector<std::uint8_t>(valid.begin(), valid.begin() + static_cast<long>(n)), true);
  for (int i = 0; i < iterations(3000); ++i) {
    std::vector<std::uint8_t> bytes(std::uniform_int_distribution<size_t>(0, 2 * size)(rng));
    for (auto& b : bytes) b = byte();
    // A random fingerprint matches with probability 2^-64: malformed.
    send(bytes, true);
  }
  // The right fingerprint, random fields (NaN, huge, negative...): decoded if
  // long enough, then accepted (clamped), or rejected as NaN or stale.
  for (int i = 0; i < iterations(3000); ++i) {
    std::vector<std::uint8_t> bytes(std::uniform_int_distribution<size_t>(8, 2 * size)(rng));
    std::copy(valid.begin(), valid.begin() + 8, bytes.begin());
    for (size_t k = 8; k < bytes.size(); ++k) bytes[k] = byte();
    if (i % 8 == 0 && bytes.size() >= size) {  // a lever NaN or infinite (big-endian IEEE 754)
      const size_t field = 8 + 4 * 8 + 8 * (rng() % 5);
      const std::uint8_t top[] = {0x7f, 0xff};
      bytes[field] = top[rng() % 2];
      bytes[field + 1] = static_cast<std::uint8_t>(0xf0 | (rng() % 16));
    }
    send(bytes, bytes.size() < size);
  }
  // A valid message with a few bytes garbled: malformed if the fingerprint was hit.
  for (int i = 0; i < iterations(3000); ++i) {
    std::vector<std::uint8_t> bytes = encoded(valid_command(2 + i));
    bool hit_fingerprint = false;
    for (int k = 0, n = 1 + static_cast<int>(rng() % 4); k < n; ++k) {
      const size_t at = rng() % bytes.size();
      const std::uint8_t b = byte();
      hit_fingerprint = hit_fingerprint || (at < 8 && b != bytes[at]);
      bytes[at] = b;
    }
    send(bytes, hit_fingerprint);
  }
  const ControlStats& s = input.stats();
  EXPECT_EQ(s.malformed + s.accepted + s.rejected_nan + s.rejected_stale, sent);
  EXPECT_GE(s.malformed, expect_malformed);
  EXPECT_GT(s.accepted, 0);
  EXPECT_GT(s.rejected_nan, 0);
  std::printf("[ fuzz     ] control_t: %lld messages: %lld malformed, %lld accepted (%lld clamped), %lld NaN, %lld stale\n",
              static_cast<long long>(sent), static_cast<long long>(s.malformed), static_cast<long long>(s.accepted),
              static_cast<long long>(s.clamped), static_cast<long long>(s.rejected_nan),
              static_cast<long long>(s.rejected_stale));
}

// Sends stderr to /dev/null while it lives.
class QuietStderr {
 public:
  QuietStderr() : saved_(::dup(2)) {
    std::fflush(stderr);
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) {
      ::dup2(null, 2);
      ::close(null);
    }
  }
  ~QuietStderr() {
    std::fflush(stderr);
    if (saved_ >= 0) {
      ::dup2(saved_, 2);
      ::close(saved_);
    }
  }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  int saved_;
};

struct LoggedEvent {
  std::string channel;
  std::int64_t timestamp;
  std::vector<std::uint8_t> data;
};

// Every event lcm::LogFile reads from `path` (never more than `limit`).
std::vector<LoggedEvent> read_log(const std::string& path, size_t limit = 1000) {
  std::vector<LoggedEvent> out;
  lcm::LogFile log(path, "r");
  if (!log.good()) return out;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    const auto* d = static_cast<const std::uint8_t*>(e->data);
    out.push_back({e->channel, e->timestamp, std::vector<std::uint8_t>(d, d + e->datalen)});
    if (out.size() >= limit) break;
  }
  return out;
}

TEST(LcmLogFuzz, TruncatedAndGarbledLogsReadOnlyWholeEvents) {
  const fs::path dir = fs::temp_directory_path() / ("skidsim_fuzz_log_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string full = (dir / "session.lcmlog").string();
  // A session's applied controls (one per tick), and a state message between.
  std::vector<LoggedEvent> written;
  std::vector<std::int64_t> ends;  // byte offset where each event ends
  {
    lcm::LogFile log(full, "w");
    ASSERT_TRUE(log.good());
    for (int k = 0; k < 8; ++k) {
      LoggedEvent ev;
      if (k % 3 == 2) {
        ev = {"SKIDSIM_STATE", 10000 * k, std::vector<std::uint8_t>(40, static_cast<std::uint8_t>(k))};
      } else {
        skidsim_lcm::control_t c = valid_command(k);
        c.sim_step = 5 * k;
        ev = {"SKIDSIM_CONTROL_APPLIED", 10000 * k, encoded(c)};
      }
      lcm::LogEvent e;
      e.eventnum = k;
      e.timestamp = ev.timestamp;
      e.channel = ev.channel;
      e.datalen = static_cast<std::int32_t>(ev.data.size());
      e.data = ev.data.data();
      ASSERT_EQ(log.writeEvent(&e), 0);
      std::fflush(log.getFilePtr());
      ends.push_back(static_cast<std::int64_t>(std::ftell(log.getFilePtr())));
      written.push_back(ev);
    }
  }
  const std::string bytes = read_text(full);
  ASSERT_EQ(static_cast<std::int64_t>(bytes.size()), ends.back());
  const auto same = [](const LoggedEvent& a, const LoggedEvent& b) {
    return a.channel == b.channel && a.timestamp == b.timestamp && a.data == b.data;
  };
  {
    const std::vector<LoggedEvent> back = read_log(full);
    ASSERT_EQ(back.size(), written.size());
    for (size_t k = 0; k < back.size(); ++k) EXPECT_TRUE(same(back[k], written[k])) << k;
  }
  // Cut at every byte: exactly the events that end before the cut come back, intact.
  const std::string cut = (dir / "cut.lcmlog").string();
  for (size_t at = 0; at < bytes.size(); ++at) {
    write_text(cut, bytes.substr(0, at));
    const std::vector<LoggedEvent> back = read_log(cut);
    const size_t whole = static_cast<size_t>(std::count_if(ends.begin(), ends.end(), [&](std::int64_t e) {
      return e <= static_cast<std::int64_t>(at);
    }));
    ASSERT_EQ(back.size(), whole) << "cut at byte " << at;
    for (size_t k = 0; k < back.size(); ++k) ASSERT_TRUE(same(back[k], written[k])) << "cut at " << at << ", event " << k;
    // The checked reader (io/lcm_log.h, what a replay reads with) takes a
    // cut only at an event's end, and names the byte of any other.
    const bool at_an_end = at > 0 && std::find(ends.begin(), ends.end(), static_cast<std::int64_t>(at)) != ends.end();
    std::uint64_t checked_events = 0;
    std::string why;
    try {
      checked_events = read_lcm_log(cut, nullptr).event_count;
    } catch (const InputError& e) {
      why = e.what();
    }
    ASSERT_EQ(why.empty(), at_an_end) << "cut at " << at << ": " << why;
    if (at_an_end) {
      ASSERT_EQ(checked_events, whole);
    } else {
      ASSERT_NE(why.find(cut + ": byte "), std::string::npos) << why;
    }
  }
  // Garbled: bytes flipped, then cut. No crash; what decodes on the applied
  // channel is a whole control_t or is refused by decode.
  std::mt19937_64 rng(fuzz_seed() ^ 7);
  int events = 0, decoded = 0, refused = 0, checked_whole = 0, checked_refused = 0;
  const QuietStderr quiet;  // LCM says why it stops reading each one
  for (int i = 0; i < iterations(1500); ++i) {
    std::string garbled = bytes;
    for (int k = 0, n = 1 + static_cast<int>(rng() % 6); k < n; ++k)
      garbled[rng() % garbled.size()] = static_cast<char>(rng() % 256);
    if (rng() % 2) garbled.resize(rng() % (garbled.size() + 1));
    write_text(cut, garbled);
    // The checked reader: whole, or refused naming the file and the byte.
    try {
      const LcmLog checked = read_lcm_log(cut, [](const std::string&) { return true; });
      ++checked_whole;
      for (const LcmLogEvent& e : checked.kept) ASSERT_LE(e.data_offset_bytes + e.data.size(), garbled.size());
    } catch (const InputError& e) {
      ++checked_refused;
      ASSERT_NE(std::string(e.what()).find(cut + ": byte "), std::string::npos) << e.what();
    }
    for (const LoggedEvent& e : read_log(cut)) {
      ++events;
      if (e.channel != "SKIDSIM_CONTROL_APPLIED") continue;
      skidsim_lcm::control_t m{};
      (m.decode(e.data.data(), 0, static_cast<int>(e.data.size())) < 0 ? refused : decoded)++;
    }
  }
  std::printf("[ fuzz     ] lcm log: %zu cuts, %d garbled logs (%d events read: %d controls decoded, %d refused; "
              "the checked reader: %d whole, %d refused naming the byte)\n",
              bytes.size(), iterations(1500), events, decoded, refused, checked_whole, checked_refused);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace skidsim::io
