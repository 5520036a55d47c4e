#include "station/station.h"

#include <lcm/lcm-cpp.hpp>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <vector>

#include "io/exercise.h"
#include "io/atomic_file.h"
#include "io/jpeg_image.h"
#include "io/lcm_bridge.h"
#include "io/loader_files.h"
#include "io/soil_table.h"
#include "jobs/interrupt.h"
#include "render/offscreen_context.h"
#include "render/renderer.h"
#include "session/session_world.h"
#include "skidsim_lcm/control_t.hpp"
#include "skidsim_lcm/event_t.hpp"
#include "skidsim_lcm/state_t.hpp"
#include "visual/scene_view.h"

// Last, after Eigen: httplib.h brings <resolv.h>, whose _res macro would
// rename a parameter of Eigen's products.
#include <httplib.h>

namespace skidsim::station {
namespace {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

// The driver's page sends its levers every 50 ms; after this long without
// them (a closed tab, a lost network) the levers go to neutral.
constexpr double kDriverGoneS = 0.5;
// Controls go out 50 a second, or twice in the session's watchdog time
// when that is shorter (the exercise's <operator watchdog_ms>).
constexpr double kControlPeriodS = 0.02;
// Neutral goes out this many times when the driver goes (then the
// session's watchdog holds it).
constexpr int kNeutralMessages = 10;
// A view nobody asked for in this long is not drawn.
constexpr double kViewIdleS = 2.0;
// A page's request for a frame newer than it has waits this long at most.
constexpr auto kFrameWait = std::chrono::milliseconds(1000);
constexpr const char* kTraineeView = "trainee";
constexpr const char* kAerialView = "aerial";
constexpr const char* kViews[] = {kTraineeView, kAerialView};
// A second of the stream that does not fit (the session started again
// under its name): the station joins it afresh.
constexpr int kRefusedInARow = static_cast<int>(io::kMaxRecordFps);
constexpr std::size_t kMaxEvents = 10000, kMaxEventText = 1000, kMaxScenes = 2000;
// Connections: each holds one of the server's threads while it is open, so
// idle ones are closed soon.
constexpr int kServerThreads = 32;
constexpr time_t kKeepAliveS = 1, kReadTimeoutS = 2;

// Compares without stopping at the first difference (a token's check takes
// no longer for a better guess).
bool same_secret(const std::string& a, const std::string& b) {
  unsigned char d = a.size() == b.size() ? 0 : 1;
  for (std::size_t k = 0; k < a.size(); ++k) d |= static_cast<unsigned char>(a[k] ^ b[k < b.size() ? k : 0]);
  return d == 0 && !b.empty();
}

std::string random_token() {
  unsigned char bytes[12] = {};
  std::ifstream urandom("/dev/urandom", std::ios::binary);
  if (!urandom.read(reinterpret_cast<char*>(bytes), sizeof bytes)) throw io::InputError("station: /dev/urandom could not be read");
  std::string hex;
  char two[3];
  for (unsigned char b : bytes) std::snprintf(two, sizeof two, "%02x", b), hex += two;
  return hex;
}

// The addresses a station listens on without a token: this host's own
// (written out, not a name to look up), which pages on this host address
// it by.
bool loopback(const std::string& address) { return address == "127.0.0.1" || address == "::1" || address == "localhost"; }

// The Host header a page on this host sends (a page elsewhere that renamed
// itself to 127.0.0.1 through DNS sends its own name: refused).
bool local_host_header(const std::string& host, int port) {
  const std::string p = ":" + std::to_string(port);
  return host == "127.0.0.1" + p || host == "localhost" + p || host == "[::1]" + p || host == "127.0.0.1" || host == "localhost";
}

json state_json(const skidsim_lcm::state_t& s) {
  const double speed = std::sqrt(s.chassis_velocity_m_s[0] * s.chassis_velocity_m_s[0] +
                                 s.chassis_velocity_m_s[1] * s.chassis_velocity_m_s[1] +
                                 s.chassis_velocity_m_s[2] * s.chassis_velocity_m_s[2]);
  return {{"step", s.step},
          {"sim_time_s", s.sim_time_s},
          {"chassis_position_m", {s.chassis_position_m[0], s.chassis_position_m[1], s.chassis_position_m[2]}},
          {"chassis_orientation_wxyz",
           {s.chassis_orientation_wxyz[0], s.chassis_orientation_wxyz[1], s.chassis_orientation_wxyz[2], s.chassis_orientation_wxyz[3]}},
          {"speed_m_s", speed},
          {"lift_angle_rad", s.lift_angle_rad},
          {"tilt_angle_rad", s.tilt_angle_rad},
          {"bucket_payload_kg", s.bucket_payload_kg},
          {"active_task", s.active_task},
          {"score", s.score},
          {"controls_neutral", s.controls_neutral}};
}

// What the threads share: LCM's (messages in), the drawing's (frames out),
// the HTTP server's (pages' requests) and the controls' (levers out).
struct Shared {
  std::mutex mutex;
  // In from the session.
  std::condition_variable scene_arrived;
  std::deque<std::vector<std::uint8_t>> scenes;
  json state;  // null until one came
  std::vector<json> events;
  bool ended = false;
  Clock::time_point ended_at;
  // Out to the pages.
  std::condition_variable frame_ready;
  struct Frame {
    std::int64_t seq = 0;
    double sim_time_s = 0.0;
    std::string jpeg;
  };
  std::map<std::string, Frame> frames;
  std::map<std::string, Clock::time_point> wanted;
  // The driver's page.
  skidsim_lcm::control_t levers{};
  Clock::time_point driver_seen;
  bool driver_connected = false;
  long controls_received = 0, controls_refused = 0, releases = 0;

  // On LCM's thread, where nothing may escape.
  void on_message(const lcm::ReceiveBuffer* buffer, const std::string& channel) noexcept {
    try {
      const auto* bytes = static_cast<const std::uint8_t*>(buffer->data);
      const int size = buffer->data_size > static_cast<std::uint32_t>(INT32_MAX) ? -1 : static_cast<int>(buffer->data_size);
      const std::string base = io::bare_channel(channel);
      std::lock_guard<std::mutex> lock(mutex);
      if (base == io::LcmChannels{}.scene) {
        // Behind by more than kMaxScenes (the drawing stalled, or a flood):
        // the oldest go; the stream's refresh mends what they changed.
        if (scenes.size() >= kMaxScenes) scenes.pop_front();
        scenes.emplace_back(bytes, bytes + buffer->data_size);
        scene_arrived.notify_all();
      } else if (base == io::LcmChannels{}.state) {
        skidsim_lcm::state_t s;
        if (size >= 0 && s.decode(buffer->data, 0, size) == size) state = state_json(s);
      } else if (base == io::LcmChannels{}.events) {
        skidsim_lcm::event_t e;
        if (size < 0 || e.decode(buffer->data, 0, size) != size) return;
        if (e.kind == "end" && !ended) ended = true, ended_at = Clock::now();
        scene_arrived.notify_all();
        // A page shows the first kMaxEvents, each cut to kMaxEventText.
        if (events.size() >= kMaxEvents) return;
        events.push_back({{"index", events.size()}, {"sim_time_s", e.sim_time_s}, {"kind", e.kind.substr(0, kMaxEventText)},
                          {"severity", e.severity}, {"text", e.text.substr(0, kMaxEventText)}});
      }
    } catch (const std::exception&) {
    }
  }
};

// The levers a page sent, checked: each a finite number in its range.
// Returns "" or what is wrong.
std::string read_levers(const std::string& body, skidsim_lcm::control_t& c) {
  const json j = json::parse(body, nullptr, false);
  if (!j.is_object()) return "the body is not a JSON object";
  const auto number = [&](const char* field, double lo, double hi, double& out) -> std::string {
    if (!j.contains(field)) return std::string(field) + ": missing";
    if (!j[field].is_number() || !std::isfinite(j[field].get<double>()) || j[field].get<double>() < lo || j[field].get<double>() > hi)
      return std::string(field) + ": expected a number from " + std::to_string(lo) + " to " + std::to_string(hi);
    out = j[field].get<double>();
    return "";
  };
  for (const std::string& why : {number("drive_left", -1, 1, c.drive_left), number("drive_right", -1, 1, c.drive_right),
                                 number("lift", -1, 1, c.lift), number("tilt", -1, 1, c.tilt), number("throttle", 0, 1, c.throttle)})
    if (!why.empty()) return why;
  if (!j.contains("parking_brake") || !j["parking_brake"].is_boolean()) return "parking_brake: expected true or false";
  c.parking_brake = j["parking_brake"].get<bool>();
  return "";
}

std::string read_page() {
  const std::string path = io::default_assets_dir() + "/station/index.html";
  std::ifstream in(path);
  if (!in) throw io::InputError(path + ": the station's page is not there");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The HTTP routes: the page, frames, the status, the levers.
void add_routes(httplib::Server& server, Shared& shared, const StationOptions& o, const std::string& page,
                const std::string& trainee_camera, int port) {
  const auto may_watch = [&o](const httplib::Request& req) {
    return o.token.empty() || same_secret(req.get_param_value("token"), o.token) || same_secret(req.get_param_value("driver"), o.driver_token);
  };
  const auto drives = [&o](const httplib::Request& req) { return same_secret(req.get_param_value("driver"), o.driver_token); };
  const auto refuse = [](httplib::Response& res, int status, const std::string& why) {
    res.status = status;
    res.set_content(why + "\n", "text/plain");
  };
  // Before a request's body is read: its token, its Host (a page on this
  // host, when there is no token), and a body of a stated length, within
  // the limit (a chunked or compressed one could be any size).
  server.set_pre_routing_handler([=](const httplib::Request& req, httplib::Response& res) {
    using R = httplib::Server::HandlerResponse;
    if (o.token.empty() && !local_host_header(req.get_header_value("Host"), port)) {
      refuse(res, 403, "this station answers pages on this host (give it --token to be reached from elsewhere)");
      return R::Handled;
    }
    if (!may_watch(req)) {
      refuse(res, 403, "this station needs its token (?token=...)");
      return R::Handled;
    }
    if (req.method == "POST" && (req.has_header("Transfer-Encoding") || req.has_header("Content-Encoding") ||
                                 !req.has_header("Content-Length"))) {
      refuse(res, 411, "a body of a stated length, neither chunked nor compressed");
      return R::Handled;
    }
    return R::Unhandled;
  });
  // The routes below run only for requests the check above let through.
  server.Get("/", [=](const httplib::Request&, httplib::Response& res) {
    res.set_header("Cache-Control", "no-store");
    res.set_content(page, "text/html; charset=utf-8");
  });
  server.Get("/frame.jpg", [=, &shared](const httplib::Request& req, httplib::Response& res) {
    const std::string view = req.get_param_value("camera");
    if (view != kTraineeView && view != kAerialView) return refuse(res, 400, "camera: expected trainee or aerial");
    long long after = 0;
    const std::string after_text = req.get_param_value("after");
    if (!after_text.empty()) {
      char* end = nullptr;
      after = std::strtoll(after_text.c_str(), &end, 10);
      if (end == after_text.c_str() || *end != '\0' || after < 0) return refuse(res, 400, "after: expected a frame number");
    }
    std::unique_lock<std::mutex> lock(shared.mutex);
    shared.wanted[view] = Clock::now();
    // A page's number beyond this station's (it ran before a restart): from the start.
    if (after > shared.frames[view].seq) after = 0;
    const auto newer = [&] { return shared.frames[view].seq > after && !shared.frames[view].jpeg.empty(); };
    if (!shared.frame_ready.wait_for(lock, kFrameWait, newer)) {
      res.status = 204;  // nothing newer yet: ask again
      return;
    }
    const Shared::Frame& f = shared.frames[view];
    res.set_header("X-Frame-Seq", std::to_string(f.seq));
    res.set_header("X-Sim-Time-S", std::to_string(f.sim_time_s));
    res.set_header("Cache-Control", "no-store");
    res.set_content(f.jpeg, "image/jpeg");
  });
  server.Get("/status", [=, &shared](const httplib::Request& req, httplib::Response& res) {
    std::size_t after = 0;
    const std::string after_text = req.get_param_value("events_after");
    if (!after_text.empty()) {
      char* end = nullptr;
      const long long v = std::strtoll(after_text.c_str(), &end, 10);
      if (end == after_text.c_str() || *end != '\0' || v < 0) return refuse(res, 400, "events_after: expected an event's index");
      after = static_cast<std::size_t>(v);
    }
    json s;
    {
      std::lock_guard<std::mutex> lock(shared.mutex);
      json events = json::array();
      for (std::size_t k = after; k < shared.events.size() && events.size() < 200; ++k) events.push_back(shared.events[k]);
      s = {{"session", o.session},          {"ended", shared.ended},
           {"you_drive", drives(req)},      {"driver_connected", shared.driver_connected},
           {"trainee_camera", trainee_camera}, {"state", shared.state},
           {"events", events},              {"controls_received", shared.controls_received},
           {"controls_refused", shared.controls_refused}, {"releases", shared.releases}};
    }
    res.set_header("Cache-Control", "no-store");
    res.set_content(s.dump(-1, ' ', false, json::error_handler_t::replace), "application/json");
  });
  server.Post("/control", [=, &shared](const httplib::Request& req, httplib::Response& res) {
    if (!drives(req)) {
      std::lock_guard<std::mutex> lock(shared.mutex);
      ++shared.controls_refused;
      return refuse(res, 403, "only the page holding the driver's token drives");
    }
    skidsim_lcm::control_t c{};
    const std::string why = read_levers(req.body, c);
    if (!why.empty()) return refuse(res, 400, "control: " + why);
    std::lock_guard<std::mutex> lock(shared.mutex);
    shared.levers = c;
    shared.driver_seen = Clock::now();
    shared.driver_connected = true;
    ++shared.controls_received;
    res.set_content("{}", "application/json");
  });
  server.Post("/release", [=, &shared](const httplib::Request& req, httplib::Response& res) {
    if (!drives(req)) return refuse(res, 403, "only the page holding the driver's token drives");
    std::lock_guard<std::mutex> lock(shared.mutex);
    shared.driver_seen = Clock::time_point{};  // gone: neutral at the next control tick
    ++shared.releases;
    res.set_content("{}", "application/json");
  });
}

// The controls' thread: the driver's levers 50 a second while they keep
// coming, then neutral.
void send_controls(lcm::LCM& lcm, const std::string& channel, double watchdog_s, Shared& shared, const std::atomic<bool>& stop) {
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(std::min(kControlPeriodS, watchdog_s / 2)));
  const std::int64_t sender =
      static_cast<std::int64_t>(Clock::now().time_since_epoch().count() ^ (static_cast<std::int64_t>(::getpid()) << 32));
  std::int64_t seq = 0;
  int neutral_left = 0;
  auto next = Clock::now();
  while (!stop) {
    next += period;
    if (next < Clock::now()) next = Clock::now();  // behind (a stall): on from now, no burst
    std::this_thread::sleep_until(next);
    skidsim_lcm::control_t c{};
    bool send = false;
    {
      std::lock_guard<std::mutex> lock(shared.mutex);
      if (shared.driver_connected && Clock::now() - shared.driver_seen <= std::chrono::duration<double>(kDriverGoneS)) {
        c = shared.levers;
        send = true;
      } else if (shared.driver_connected) {
        shared.driver_connected = false;
        neutral_left = kNeutralMessages;
      }
    }
    if (!send && neutral_left > 0) {
      --neutral_left;
      c = skidsim_lcm::control_t{};  // levers centred, throttle 0, brake off
      send = true;
    }
    if (!send) continue;
    c.sender_id = sender;
    c.seq = ++seq;
    c.sim_step = -1;
    c.sender_time_us = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
    lcm.publish(channel, &c);
  }
}

}  // namespace

int run_station(const StationOptions& o_in) {
  const jobs::InterruptScope interrupt_scope;
  StationOptions o = o_in;
  io::check_session_name(o.session, "--session");
  if (o.exercise_path.empty()) throw io::InputError("--exercise: the station needs the session's exercise file");
  if (!loopback(o.bind) && o.token.empty())
    throw io::InputError("--bind " + o.bind + ": a station listening beyond this host needs --token");
  if (o.port < 0 || o.port > 65535) throw io::InputError("--port: expected 0 to 65535");
  io::check_frame_rate(o.fps);
  if (o.width < 16 || o.height < 16 || o.width > 4096 || o.height > 4096) throw io::InputError("--width / --height: expected 16 to 4096");
  if (!(o.linger_s >= 0.0)) throw io::InputError("--linger-s: expected >= 0");
  if (o.driver_token.empty()) o.driver_token = random_token();
  if (o.driver_token.size() < 16 || o.driver_token.find_first_not_of("0123456789abcdefABCDEF-_") != std::string::npos)
    throw io::InputError("--driver-token: expected 16 or more of 0-9 a-f A-F - _");
  if (!o.token.empty() && (o.token.size() < 16 || o.token.find_first_not_of("0123456789abcdefABCDEF-_") != std::string::npos))
    throw io::InputError("--token: expected 16 or more of 0-9 a-f A-F - _");

  const io::Exercise ex = io::load_exercise(o.exercise_path);
  const vehicle::LoaderDescription loader = io::load_loader(ex.machine.loader);
  const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
  const std::unique_ptr<engine::World> world = session::build_session_world(ex, loader, soils);
  const std::string camera = o.camera.empty() ? ex.recording.camera : o.camera;
  std::unique_ptr<visual::SceneView> view;
  try {
    view = std::make_unique<visual::SceneView>(ex, *world, camera, o.fps, visual::SceneStreamReader::Start::kJoining);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(std::string("--camera: ") + e.what());
  }
  std::unique_ptr<render::OffscreenContext> context;
  try {
    context = render::make_offscreen_context(o.backend, o.width, o.height);
  } catch (const std::runtime_error& e) {
    throw io::InputError(std::string("station: ") + e.what());
  }
  render::Renderer renderer(*context);
  const std::string page = read_page();

  const std::string url = o.lcm_url.empty() ? std::string(io::kDefaultLcmUrl) : o.lcm_url;
  lcm::LCM lcm(url);
  if (!lcm.good()) throw io::InputError("LCM provider '" + url + "' could not be opened");
  const io::LcmChannels channels = io::session_channels(o.session, ex.operator_source.channel);
  Shared shared;
  for (const std::string& channel : {channels.scene, channels.state, channels.events}) lcm.subscribe(channel, &Shared::on_message, &shared);

  httplib::Server server;
  server.set_payload_max_length(4096);
  server.set_keep_alive_timeout(kKeepAliveS);
  server.set_read_timeout(kReadTimeoutS, 0);
  server.new_task_queue = [] { return new httplib::ThreadPool(kServerThreads); };
  const int port = o.port == 0 ? server.bind_to_any_port(o.bind) : (server.bind_to_port(o.bind, o.port) ? o.port : -1);
  if (port <= 0) throw io::InputError("--port " + std::to_string(o.port) + ": cannot listen on " + o.bind + " (in use?)");
  add_routes(server, shared, o, page, camera, port);

  // LCM's, the server's and the controls' threads; stopped and joined
  // however this function leaves.
  struct Threads {
    std::atomic<bool> stop{false};
    httplib::Server* server = nullptr;
    std::vector<std::thread> all;
    ~Threads() {
      stop = true;
      if (server) server->stop();
      for (std::thread& t : all)
        if (t.joinable()) t.join();
    }
  } threads;
  threads.server = &server;
  threads.all.emplace_back([&] { io::handle_until(lcm, threads.stop); });
  threads.all.emplace_back([&] { server.listen_after_bind(); });
  // stop() does nothing to a server not yet listening: wait until it is.
  for (int k = 0; k < 500 && !server.is_running(); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  threads.all.emplace_back([&] { send_controls(lcm, channels.control, ex.operator_source.watchdog_s, shared, threads.stop); });
  const std::string host = o.bind.find(':') != std::string::npos ? "[" + o.bind + "]" : o.bind;
  const std::string base = "http://" + host + ":" + std::to_string(port) + "/";
  const std::string watch = o.token.empty() ? base : base + "?token=" + o.token;
  std::cout << "station: session " << o.session << " at " << watch << " (watch); drive at " << base << "?driver=" << o.driver_token
            << std::endl;

  // The drawing: every message into the view; at each frame due, each view
  // a page asked for lately, drawn and kept as JPEG.
  long refused = 0, refused_in_a_row = 0;
  std::int64_t seq = 0;
  for (;;) {
    std::deque<std::vector<std::uint8_t>> batch;
    bool ended = false;
    {
      std::unique_lock<std::mutex> lock(shared.mutex);
      shared.scene_arrived.wait_for(lock, std::chrono::milliseconds(200), [&] { return !shared.scenes.empty(); });
      batch.swap(shared.scenes);
      ended = shared.ended && Clock::now() - shared.ended_at > std::chrono::duration<double>(o.linger_s);
    }
    if (const int signal = jobs::interrupting_signal(); signal != 0)
      throw jobs::Interrupted("station stopped", signal);
    if (ended) break;
    bool due = false;
    for (const std::vector<std::uint8_t>& bytes : batch) {
      try {
        skidsim_lcm::scene_t m;
        visual::decode_scene(bytes.data(), bytes.size(), m);
        due = view->apply(m) > 0 || due;
        refused_in_a_row = 0;
      } catch (const visual::SceneStreamError& e) {
        if (refused++ == 0) std::cerr << "skidsim station: refused a scene message: " << e.what() << "\n";
        if (++refused_in_a_row >= kRefusedInARow) {
          std::cerr << "skidsim station: the stream no longer fits (" << e.what() << "); joining it afresh\n";
          view = std::make_unique<visual::SceneView>(ex, *world, camera, o.fps, visual::SceneStreamReader::Start::kJoining);
          refused_in_a_row = 0;
        }
      }
    }
    if (!due) continue;
    ++seq;
    for (const char* name : kViews) {
      {
        std::lock_guard<std::mutex> lock(shared.mutex);
        const auto w = shared.wanted.find(name);
        if (w == shared.wanted.end() || Clock::now() - w->second > std::chrono::duration<double>(kViewIdleS)) continue;
      }
      io::RgbImage image;
      image.width = o.width, image.height = o.height;
      image.rgb = render::render_rgb(*context, renderer, view->scene(),
                                     std::string(name) == kTraineeView ? view->camera() : view->camera("aerial"));
      std::string jpeg = io::encode_jpeg(image);
      std::lock_guard<std::mutex> lock(shared.mutex);
      shared.frames[name] = {seq, view->frame_time_s(), std::move(jpeg)};
      shared.frame_ready.notify_all();
    }
  }
  std::cout << "station: session " << o.session << " ended" << std::endl;
  return 0;
}

}  // namespace skidsim::station
