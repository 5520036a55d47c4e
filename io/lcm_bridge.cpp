#include "io/lcm_bridge.h"

#include <unistd.h>

#include <chrono>
#include <thread>

#include <stdexcept>

#include "io/atomic_file.h"
#include "io/exercise.h"

namespace skidsim::io {

LcmChannels session_channels(const std::string& session, const std::string& control) {
  LcmChannels c;
  c.control = control;
  for (std::string* name : {&c.control, &c.state, &c.events, &c.terrain, &c.scene}) *name = bare_channel(*name) + "@" + session;
  return c;
}

void check_session_name(const std::string& name, const std::string& option) {
  const bool ok = !name.empty() && name.size() <= 32 && channel_name_text(name);
  if (!ok) throw InputError(option + " '" + name + "': expected 1 to 32 of A-Z a-z 0-9 _ -");
}

std::string default_session_name(const std::string& exercise_name) {
  std::string base;
  for (char ch : exercise_name.substr(0, 24)) {
    base += channel_name_text(std::string(1, ch)) ? ch : '-';
  }
  return (base.empty() ? std::string("session") : base) + "-" + std::to_string(::getpid());
}

LcmBridge::LcmBridge(const std::string& url, const LcmChannels& channels, ControlInput* input)
    : owned_(std::make_unique<lcm::LCM>(url)), lcm_(owned_.get()), channels_(channels), input_(input) {
  if (!lcm_->good()) throw InputError("LCM provider '" + url + "' could not be opened");
  subscribe();
}

LcmBridge::LcmBridge(lcm::LCM& lcm, const LcmChannels& channels, ControlInput* input)
    : lcm_(&lcm), channels_(channels), input_(input) {
  if (!lcm_->good()) throw InputError("LCM provider could not be opened");
  subscribe();
}

LcmBridge::~LcmBridge() {
  if (subscription_) lcm_->unsubscribe(subscription_);
}

void LcmBridge::subscribe() {
  if (!input_) throw std::invalid_argument("LcmBridge: no ControlInput");
  // Raw bytes: a message that does not decode is counted, not dropped
  // silently.
  subscription_ = lcm_->subscribe(channels_.control, &LcmBridge::on_control, this);
}

void LcmBridge::on_control(const lcm::ReceiveBuffer* buffer, const std::string& channel) {
  if (recorder_) {
    lcm::LogEvent e;
    e.eventnum = 0;
    e.timestamp = static_cast<std::int64_t>(now_s_ * 1e6);
    e.channel = bare_channel(channel);
    e.datalen = static_cast<std::int32_t>(buffer->data_size);
    e.data = buffer->data;
    recorder_->writeEvent(&e);
  }
  skidsim_lcm::control_t command;
  if (command.decode(buffer->data, 0, static_cast<int>(buffer->data_size)) < 0) {
    input_->count_malformed();
    return;
  }
  input_->offer(command, now_s_);
}

int LcmBridge::poll(double sim_time_s) {
  now_s_ = sim_time_s;
  int handled = 0;
  while (handled < kMaxPerPoll && lcm_->handleTimeout(0) > 0) ++handled;
  return handled;
}

void handle_until(lcm::LCM& lcm, const std::atomic<bool>& stop) {
  while (!stop)
    if (lcm.handleTimeout(100) < 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
}

bool LcmBridge::wait(int timeout_ms, double sim_time_s) {
  now_s_ = sim_time_s;
  return lcm_->handleTimeout(timeout_ms) > 0;
}

void LcmBridge::publish_state(const skidsim_lcm::state_t& state) { lcm_->publish(channels_.state, &state); }

void LcmBridge::publish_event(const skidsim_lcm::event_t& event) { lcm_->publish(channels_.events, &event); }

void LcmBridge::publish_terrain_tile(const skidsim_lcm::terrain_tile_t& tile) { lcm_->publish(channels_.terrain, &tile); }

void LcmBridge::publish_scene(const skidsim_lcm::scene_t& scene) { lcm_->publish(channels_.scene, &scene); }

}  // namespace skidsim::io
