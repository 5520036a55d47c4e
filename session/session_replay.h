// A session log belongs to its exercise, and a replay reads it only after
// the whole file has been checked (io/lcm_log.h; liblcm's reader is not used
// for input at all, only lcm::LogFile for writing).
//
// The first event of every session log is its header, on SKIDSIM_SESSION at
// timestamp 0: a JSON object (UTF-8, no LCM type, so any tool shows it as
// text) naming the exercise and the FNV-1a 64-bit hash of the bytes of
// every file that defines the session's world:
//   {"format": "skidsim-session", "version": 1, "exercise": "pile_to_zone",
//    "files": [{"role": "exercise", "file": "pile_to_zone.xml", "fnv1a64": "89ab...ef"},
//              {"role": "loader_parameters", ...}, {"role": "loader_urdf", ...},
//              {"role": "soil_table", ...}]}
// A replay refuses a log without that header (one written before skidsim
// recorded it, or by another program), and one whose exercise or files
// differ from those it is asked to replay in: the same controls in another
// world are another session.
#pragma once

#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "io/exercise.h"
#include "io/lcm_log.h"
#include "vehicle/loader_description.h"
#include "vehicle/powertrain.h"

namespace skidsim::session {

inline constexpr const char* kSessionChannel = "SKIDSIM_SESSION";

// What a session is run from: the exercise's name and its files' hashes.
struct SessionFile {
  std::string role;  // exercise, loader_parameters, loader_urdf, soil_table
  std::string path;  // as read here (the header keeps only the file's name)
  std::uint64_t fnv1a64 = 0;
};
struct SessionIdentity {
  std::string exercise_name;
  std::vector<SessionFile> files;  // the exercise first
};

// FNV-1a, 64 bits (Fowler, Noll, Vo; the offset basis 14695981039346656037
// and prime 1099511628211 of the reference, isthe.com/chongo/tech/comp/fnv).
std::uint64_t fnv1a64(const std::string& bytes);

// Reads (io::read_input_file) and hashes the exercise, the loader's
// parameter file and URDF, and the soil table.
SessionIdentity session_identity(const io::Exercise& ex, const vehicle::LoaderDescription& loader,
                                 const std::string& soil_table_path);

// The header event; written first, before any other event of the log.
void write_session_header(lcm::LogFile& log, const SessionIdentity& identity);

// What a replay applies: the controls of each control tick from tick 0, and
// the step the recorded session stopped at (its "end" event).
struct Replay {
  std::vector<vehicle::LoaderControls> controls;
  long end_step = -1;
};

// Checks the log (io::read_lcm_log), its header against `identity`, then
// reads the controls applied on the exercise's channel + "_APPLIED": one per
// tick (every `steps_per_tick` steps) from the start, each finite and in
// range, and the one "end" event on SKIDSIM_EVENTS, which the controls must
// reach. Anything else: io::InputError naming the file and, for an event,
// its byte and index.
Replay load_replay(const std::string& path, const io::Exercise& ex, const SessionIdentity& identity, int steps_per_tick);

// Checks the log and its header against `identity` as load_replay does, then
// returns its scene stream's messages (SKIDSIM_SCENE, still encoded) in
// order; io::InputError when there are none.
std::vector<io::LcmLogEvent> load_scene_events(const std::string& path, const SessionIdentity& identity);

}  // namespace skidsim::session
