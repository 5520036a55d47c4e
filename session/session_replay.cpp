#include "session/session_replay.h"

#include "session/control_message.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "io/atomic_file.h"
#include "io/input_file.h"
#include "io/lcm_bridge.h"
#include "io/lcm_log.h"
#include "skidsim_lcm/control_t.hpp"
#include "skidsim_lcm/event_t.hpp"

namespace skidsim::session {
namespace {

using nlohmann::json;

constexpr const char* kHeaderFormat = "skidsim-session";
constexpr int kHeaderVersion = 1;
constexpr std::size_t kMaxHeaderBytes = 64 << 10;  // a name and four hashes: far less

std::string hex64(std::uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::string file_name(const std::string& path) { return std::filesystem::path(path).filename().string(); }

std::string role_words(const std::string& role) {
  if (role == "loader_parameters") return "loader parameter file";
  if (role == "loader_urdf") return "loader URDF";
  if (role == "soil_table") return "soil table";
  return role;
}

// The header as recorded: the exercise's name and each file's role, name
// and hash. Refused when it is not the object write_session_header writes.
struct RecordedFile {
  std::string file, hash;
};
struct RecordedHeader {
  std::string exercise;
  std::vector<std::pair<std::string, RecordedFile>> files;  // by role, in order
};

RecordedHeader parse_header(const io::LcmLogEvent& e, const std::string& path) {
  const std::string where = io::lcm_log_where(path, e.data_offset_bytes, e.index) + std::string("the ") + kSessionChannel + " header ";
  if (e.data.size() > kMaxHeaderBytes)
    throw io::InputError(where + "has " + std::to_string(e.data.size()) + " bytes (at most " + std::to_string(kMaxHeaderBytes) + ")");
  json j;
  try {
    j = json::parse(e.data.begin(), e.data.end());
  } catch (const json::exception& x) {
    throw io::InputError(where + "is not JSON (" + x.what() + ")");
  }
  const auto text = [&](const json& o, const char* key) {
    if (!o.is_object() || !o.contains(key) || !o[key].is_string())
      throw io::InputError(where + "has no text '" + key + "'");
    return o[key].get<std::string>();
  };
  if (text(j, "format") != kHeaderFormat) throw io::InputError(where + "is not of format '" + kHeaderFormat + "'");
  if (!j.contains("version") || !j["version"].is_number_integer() || j["version"].get<long long>() != kHeaderVersion)
    throw io::InputError(where + "has version " + (j.contains("version") ? j["version"].dump() : std::string("none")) +
                         "; this build reads version " + std::to_string(kHeaderVersion));
  RecordedHeader h;
  h.exercise = text(j, "exercise");
  if (!j.contains("files") || !j["files"].is_array()) throw io::InputError(where + "has no list 'files'");
  for (const json& f : j["files"]) h.files.push_back({text(f, "role"), {text(f, "file"), text(f, "fnv1a64")}});
  return h;
}

// The header against the exercise and files this replay runs in.
void check_header(const RecordedHeader& h, const SessionIdentity& now, const std::string& path) {
  const auto recorded = [&](const std::string& role) -> const RecordedFile* {
    for (const auto& [r, f] : h.files)
      if (r == role) return &f;
    return nullptr;
  };
  const SessionFile& ex = now.files.front();
  const RecordedFile* rex = recorded("exercise");
  if (!rex || h.exercise != now.exercise_name || rex->hash != hex64(ex.fnv1a64))
    throw io::InputError(path + " was recorded from exercise '" + h.exercise + "' (" + (rex ? rex->file : "?") + ", hash " +
                         (rex ? rex->hash : "none") + "), not '" + now.exercise_name + "' (" + ex.path + ", hash " +
                         hex64(ex.fnv1a64) + ")" +
                         (h.exercise == now.exercise_name ? ": the exercise file has changed since the session was recorded" : ""));
  for (const SessionFile& f : now.files) {
    const RecordedFile* r = recorded(f.role);
    if (!r || r->hash != hex64(f.fnv1a64))
      throw io::InputError(path + " was recorded with " +
                           (r ? "the " + role_words(f.role) + " " + r->file + " (hash " + r->hash + ")" : "no " + role_words(f.role)) +
                           ", but " + f.path + " hashes " + hex64(f.fnv1a64) +
                           ": the world is not the one recorded, so the replay would not be that session");
  }
  for (const auto& [role, f] : h.files) {
    bool known = false;
    for (const SessionFile& g : now.files) known = known || g.role == role;
    if (!known)
      throw io::InputError(path + " was recorded with a file this build does not read ('" + role + "': " + f.file + ")");
  }
}

}  // namespace

std::uint64_t fnv1a64(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (const char c : bytes) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  return h;
}

SessionIdentity session_identity(const io::Exercise& ex, const vehicle::LoaderDescription& loader,
                                 const std::string& soil_table_path) {
  SessionIdentity id;
  id.exercise_name = ex.name;
  const std::pair<const char*, std::string> files[] = {{"exercise", ex.path},
                                                        {"loader_parameters", loader.parameters_path},
                                                        {"loader_urdf", loader.urdf_path},
                                                        {"soil_table", soil_table_path}};
  for (const auto& [role, path] : files)
    id.files.push_back({role, path, fnv1a64(io::read_input_file(path, io::kMaxXmlBytes, role_words(role).c_str()))});
  return id;
}

void write_session_header(lcm::LogFile& log, const SessionIdentity& identity) {
  // In the order of the README's description (ordered_json keeps it).
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const SessionFile& f : identity.files)
    files.push_back({{"role", f.role}, {"file", file_name(f.path)}, {"fnv1a64", hex64(f.fnv1a64)}});
  const std::string payload = nlohmann::ordered_json{{"format", kHeaderFormat},
                                                     {"version", kHeaderVersion},
                                                     {"exercise", identity.exercise_name},
                                                     {"files", files}}
                                  .dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  lcm::LogEvent e;
  e.eventnum = 0;
  e.timestamp = 0;
  e.channel = kSessionChannel;
  e.datalen = static_cast<std::int32_t>(payload.size());
  e.data = const_cast<char*>(payload.data());
  if (log.writeEvent(&e) != 0) throw io::InputError("cannot write the LCM log's header");
}

std::vector<io::LcmLogEvent> load_scene_events(const std::string& path, const SessionIdentity& identity) {
  const std::string scene = io::LcmChannels{}.scene;
  io::LcmLog log = io::read_lcm_log(path, [&](const std::string& ch) { return ch == kSessionChannel || ch == scene; });
  if (log.kept.empty() || log.kept.front().index != 0 || log.kept.front().channel != kSessionChannel)
    throw io::InputError(path + ": no " + kSessionChannel + " header as its first event: it cannot be checked against " +
                         identity.files.front().path + ", so it is not drawn");
  check_header(parse_header(log.kept.front(), path), identity, path);
  log.kept.erase(log.kept.begin());
  if (log.kept.empty())
    throw io::InputError(path + ": no scene messages on " + scene + " (a log written before sessions recorded the scene stream)");
  return std::move(log.kept);
}

Replay load_replay(const std::string& path, const io::Exercise& ex, const SessionIdentity& identity, int steps_per_tick) {
  const std::string applied = ex.operator_source.channel + "_APPLIED";
  const std::string events = io::LcmChannels{}.events;
  const io::LcmLog log = io::read_lcm_log(
      path, [&](const std::string& ch) { return ch == kSessionChannel || ch == events || ch == applied; });
  // The header: the first event, and the exercise's.
  if (log.kept.empty() || log.kept.front().index != 0 || log.kept.front().channel != kSessionChannel)
    throw io::InputError(path + ": no " + kSessionChannel + " header as its first event: a log written before skidsim "
                         "recorded which exercise a session ran (or by another program, such as lcm-logger) cannot be "
                         "checked against " + ex.path + ", so it is not replayed; record the session again");
  check_header(parse_header(log.kept.front(), path), identity, path);

  Replay replay;
  const io::LcmLogEvent* end_event = nullptr;
  for (const io::LcmLogEvent& e : log.kept) {
    if (e.index == 0) continue;  // the header
    const std::string where = io::lcm_log_where(path, e.data_offset_bytes, e.index);
    const int bytes = static_cast<int>(e.data.size());
    if (e.channel == events) {  // the session's end: the step it stopped at
      skidsim_lcm::event_t m{};
      if (m.decode(e.data.data(), 0, bytes) != bytes)
        throw io::InputError(where + "an event message on " + events + " that does not decode");
      if (m.kind != "end") continue;
      if (end_event)
        throw io::InputError(where + "a second 'end' event (the first is event " + std::to_string(end_event->index) + ")");
      if (m.step < 0) throw io::InputError(where + "the 'end' event's step " + std::to_string(m.step) + " is negative");
      end_event = &e;
      replay.end_step = static_cast<long>(m.step);
      continue;
    }
    if (e.channel != applied) continue;
    skidsim_lcm::control_t m{};
    if (m.decode(e.data.data(), 0, bytes) != bytes || m.sim_step < 0 || m.sim_step % steps_per_tick != 0)
      throw io::InputError(where + "a malformed applied-control message at " + std::to_string(e.timestamp_us) + " us");
    const auto tick = static_cast<std::size_t>(m.sim_step / steps_per_tick);
    if (tick != replay.controls.size())
      throw io::InputError(where + "applied controls are not one per tick from the start (tick " + std::to_string(tick) +
                           " where tick " + std::to_string(replay.controls.size()) + " is due)");
    // A recording holds only accepted controls: anything else is a damaged log.
    const double levers[] = {m.drive_left, m.drive_right, m.lift, m.tilt};
    bool valid = std::isfinite(m.throttle) && m.throttle >= 0.0 && m.throttle <= 1.0;
    for (double v : levers) valid = valid && std::isfinite(v) && std::abs(v) <= 1.0;
    if (!valid)
      throw io::InputError(where + "an applied control out of range or not finite at " + std::to_string(e.timestamp_us) +
                           " us (tick " + std::to_string(tick) + ")");
    replay.controls.push_back(to_controls(m));
  }
  if (replay.controls.empty()) throw io::InputError(path + ": no applied controls on " + applied);
  // Every session's log ends with its "end" event (run_session writes it
  // last, however the session stopped): without it the log was cut at an
  // event's boundary, and the controls after the cut would be missing.
  if (!end_event)
    throw io::InputError(path + ": no 'end' event on " + events + ": the log stops before its session ended (cut short, " +
                         "or the session did not finish writing it)");
  // The session applies a tick's controls before stepping on, and stops at
  // a tick or at its time limit: the ticks recorded reach the end step,
  // and none lies past it.
  const long ticks = static_cast<long>(replay.controls.size());
  if (replay.end_step > ticks * steps_per_tick || ticks > replay.end_step / steps_per_tick + 1)
    throw io::InputError(io::lcm_log_where(path, end_event->data_offset_bytes, end_event->index) + "the 'end' event is at step " +
                         std::to_string(replay.end_step) + ", but the applied controls cover steps 0 to " +
                         std::to_string((ticks - 1) * steps_per_tick) + ": the log is incomplete");
  return replay;
}

}  // namespace skidsim::session
