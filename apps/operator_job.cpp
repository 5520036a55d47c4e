#include "apps/operator_job.h"

#include <lcm/lcm-cpp.hpp>

#include <unistd.h>

#include <chrono>
#include <iostream>

#include "session/control_message.h"
#include "session/operator_player.h"
#include "io/atomic_file.h"
#include "io/exercise.h"
#include "io/lcm_bridge.h"
#include "skidsim_lcm/control_t.hpp"

namespace skidsim::apps {

using session::OperatorPlayer;
using session::to_message;

int run_operator(const OperatorJob& job) {
  if (job.session.empty())
    throw io::InputError("--session: name the session to drive (skidsim run --session NAME, or the name it prints)");
  io::check_session_name(job.session, "--session");
  if (job.control_channel.empty() || job.control_channel.size() > 30 || !io::channel_name_text(job.control_channel))
    throw io::InputError("--channel '" + job.control_channel + "': expected a base channel name, 1 to 30 of A-Z a-z 0-9 _ -");
  const io::LcmChannels channels = io::session_channels(job.session, job.control_channel);
  OperatorPlayer player(io::load_operator_script(job.script_path));
  const std::string url = job.lcm_url.empty() ? std::string(io::kDefaultLcmUrl) : job.lcm_url;
  lcm::LCM lcm(url);
  if (!lcm.good()) throw io::InputError("LCM provider '" + url + "' could not be opened");
  if (!(job.idle_timeout_s > 0.0)) throw io::InputError("--idle-s: expected > 0");
  struct Handler {
    OperatorPlayer* player;
    lcm::LCM* lcm;
    std::string channel;
    std::int64_t seq = 0, last_step = -1;
    skidsim_lcm::control_t answer{};  // the answer to last_step's state
    bool finished = false, moved_on = false;  // the script done; a state of a later tick since
    void on_state(const lcm::ReceiveBuffer*, const std::string&, const skidsim_lcm::state_t* s) {
      if (s->step < last_step) return;  // an old state, late
      if (finished && s->step > last_step) {
        moved_on = true;  // the last answer arrived
        return;
      }
      // The state sent again while a lockstep simulator waits: the answer may
      // have been lost, so the same answer goes again (the same seq: the
      // simulator takes it once). The script steps once per state.
      if (s->step > last_step) {
        last_step = s->step;
        answer = to_message(player->step(*s), ++seq, s->step);
        answer.sender_id = sender_id;
      }
      answer.sender_time_us =
          std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
              .count();
      lcm->publish(channel, &answer);
    }
    std::int64_t sender_id = 0;
  } handler{&player, &lcm, channels.control};
  // A restart is a new sender (the simulator then accepts a new count).
  handler.sender_id = static_cast<std::int64_t>(
      std::chrono::steady_clock::now().time_since_epoch().count() ^ (static_cast<std::int64_t>(::getpid()) << 32));
  lcm.subscribe(io::session_channels(job.session).state, &Handler::on_state, &handler);
  auto last_state = std::chrono::steady_clock::now();
  while (!player.done()) {
    if (lcm.handleTimeout(200) > 0) {
      last_state = std::chrono::steady_clock::now();
    } else if (std::chrono::steady_clock::now() - last_state > std::chrono::duration<double>(job.idle_timeout_s)) {
      std::cerr << "skidsim operator: no state from the simulator for " << job.idle_timeout_s << " s; stopping\n";
      return 1;
    }
  }
  // The script is done, but its last answer may yet be lost: a repeated state
  // is answered until the simulator moves on to a later tick or falls silent.
  handler.finished = true;
  auto quiet_since = std::chrono::steady_clock::now();
  while (!handler.moved_on &&
         std::chrono::steady_clock::now() - quiet_since < std::chrono::duration<double>(job.idle_timeout_s))
    if (lcm.handleTimeout(200) > 0) quiet_since = std::chrono::steady_clock::now();
  std::cout << "operator: script '" << job.script_path << "' finished after " << handler.seq << " commands\n";
  for (const std::string& t : player.timed_out()) std::cout << "  timed out: " << t << "\n";
  return 0;
}

}  // namespace skidsim::apps
