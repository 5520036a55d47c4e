// The simulator's side of LCM (docs/architecture.md, "A session"; the
// messages: README, "File formats"): controls in on one channel (into a
// ControlInput), state and events out on two others. A real LCM provider:
// UDP multicast on this host by default (udpm://239.255.76.67:7667?ttl=0),
// memq:// in-process for tests. Message handling happens in poll(), between
// steps, never inside the 2 ms step.
#pragma once

#include <lcm/lcm-cpp.hpp>

#include <atomic>

#include <memory>
#include <string>

#include "io/control_input.h"
#include "skidsim_lcm/event_t.hpp"
#include "skidsim_lcm/scene_t.hpp"
#include "skidsim_lcm/state_t.hpp"
#include "skidsim_lcm/terrain_tile_t.hpp"

namespace skidsim::io {

inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0";

struct LcmChannels {
  std::string control = "SKIDSIM_CONTROL";
  std::string state = "SKIDSIM_STATE";
  std::string events = "SKIDSIM_EVENTS";
  std::string terrain = "SKIDSIM_TERRAIN";  // optional: terrain_tile_t
  std::string scene = "SKIDSIM_SCENE";      // scene_t: what a view draws (docs/rendering.md)
};

// A live session's own channels: each base name, "@" and the session's name
// (SKIDSIM_STATE@bay-3), so that sessions sharing one provider (a centre's
// trainees side by side on one host's multicast) never hear each other; an
// operator attaches to a session by its name. `control` is the
// exercise's control channel. A session's log keeps the base names (a log
// holds one session; bare_channel).
LcmChannels session_channels(const std::string& session, const std::string& control = LcmChannels{}.control);
inline std::string bare_channel(const std::string& channel) { return channel.substr(0, channel.find('@')); }
// A session name is 1 to 32 of A-Z a-z 0-9 _ - (it goes into channel
// names, which LCM keeps under 64 bytes and subscribes to as regular
// expressions: no '.', which would match any character); io::InputError
// naming `option` otherwise.
void check_session_name(const std::string& name, const std::string& option);
// The name a live session takes unless it is given one, unique on this
// host: its exercise's name (other characters as '-') and this process's id.
std::string default_session_name(const std::string& exercise_name);

// A listener's receiving thread (a view, the station): handles `lcm`'s
// messages as they come until `stop`, waking every 100 ms to look; a
// provider that fails is tried again 100 ms later rather than spun on.
void handle_until(lcm::LCM& lcm, const std::atomic<bool>& stop);

class LcmBridge {
 public:
  // Opens the provider at `url` (throws io::InputError naming the URL when
  // LCM cannot) and subscribes to the control channel. `input` must outlive
  // the bridge.
  LcmBridge(const std::string& url, const LcmChannels& channels, ControlInput* input);
  // The same on an LCM instance the caller owns (tests publish into it).
  LcmBridge(lcm::LCM& lcm, const LcmChannels& channels, ControlInput* input);
  ~LcmBridge();
  LcmBridge(const LcmBridge&) = delete;
  LcmBridge& operator=(const LcmBridge&) = delete;

  // Handles the messages waiting, without blocking, at most kMaxPerPoll (a
  // flooding sender cannot stall the session); commands are stamped with
  // `sim_time_s`. Returns how many were handled.
  static constexpr int kMaxPerPoll = 256;
  int poll(double sim_time_s);
  // Waits up to `timeout_ms` for one message (lockstep). True if one came.
  bool wait(int timeout_ms, double sim_time_s);

  // Every message received on the control channel, as received (even one
  // that does not decode), is also written to `log` stamped with the
  // simulated time, under the channel's base name: the session's log holds
  // every channel. nullptr: none.
  void record_controls_to(lcm::LogFile* log) { recorder_ = log; }

  void publish_state(const skidsim_lcm::state_t& state);
  void publish_event(const skidsim_lcm::event_t& event);
  void publish_terrain_tile(const skidsim_lcm::terrain_tile_t& tile);
  void publish_scene(const skidsim_lcm::scene_t& scene);
  lcm::LCM& lcm() { return *lcm_; }

 private:
  void subscribe();
  void on_control(const lcm::ReceiveBuffer* buffer, const std::string& channel);

  std::unique_ptr<lcm::LCM> owned_;
  lcm::LCM* lcm_ = nullptr;
  LcmChannels channels_;
  ControlInput* input_ = nullptr;
  lcm::Subscription* subscription_ = nullptr;
  double now_s_ = 0.0;
  lcm::LogFile* recorder_ = nullptr;
};

}  // namespace skidsim::io
