// skidsim station in a real browser: headless Chromium, driven over the
// DevTools protocol on a pipe (--remote-debugging-pipe: JSON messages ended
// by a NUL, on the browser's file descriptors 3 and 4), opens the station's
// page for a live session running in real time on this host's LCM; keys
// pressed in the page drive the machine.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "tests/app_support.h"

extern char** environ;

namespace skidsim::testing {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

const std::string kSource = SKIDSIM_SOURCE_DIR;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string browser_path() {
  for (const char* name : {"chromium-headless-shell", "chromium"}) {
    const auto r = run_command(std::string("command -v ") + name);
    if (r.exit_code == 0) return r.output.substr(0, r.output.find('\n'));
  }
  return "";
}

// Headless Chromium and its DevTools protocol over two pipes.
class Browser {
 public:
  Browser(const std::string& path, const fs::path& profile) {
    ::signal(SIGPIPE, SIG_IGN);  // a browser that died: a failed write, not the end of the tests
    int in[2], out[2];  // in: we write, it reads on 3; out: it writes on 4, we read
    if (::pipe(in) != 0 || ::pipe(out) != 0) return;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, in[0], 3);
    posix_spawn_file_actions_adddup2(&actions, out[1], 4);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    std::vector<std::string> args = {path, "--headless", "--no-sandbox", "--disable-gpu", "--remote-debugging-pipe",
                                      "--user-data-dir=" + profile.string(), "--no-first-run",
                                      // every page keeps its timers: the driver's sends its levers every 50 ms
                                      "--disable-background-timer-throttling", "--disable-renderer-backgrounding",
                                      "--disable-backgrounding-occluded-windows", "about:blank"};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    if (posix_spawn(&pid_, path.c_str(), &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
    ::close(in[0]), ::close(out[1]);
    to_ = in[1], from_ = out[0];
  }
  ~Browser() {
    if (to_ >= 0) ::close(to_);
    if (from_ >= 0) ::close(from_);
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  bool started() const { return pid_ > 0; }

  // Sends a command (to a page's session when given) and waits for its
  // answer: its result, or a JSON null after `timeout_s`.
  json call(const std::string& method, const json& params = json::object(), const std::string& session = "", double timeout_s = 30) {
    json m = {{"id", ++id_}, {"method", method}, {"params", params}};
    if (!session.empty()) m["sessionId"] = session;
    const std::string text = m.dump() + std::string(1, '\0');
    if (::write(to_, text.data(), text.size()) != static_cast<ssize_t>(text.size())) return nullptr;
    const auto until = Clock::now() + std::chrono::duration<double>(timeout_s);
    for (;;) {
      const std::size_t end = buffer_.find('\0');
      if (end != std::string::npos) {
        const json reply = json::parse(buffer_.substr(0, end), nullptr, false);
        buffer_.erase(0, end + 1);
        if (reply.is_object() && reply.contains("id") && reply["id"] == id_) return reply.value("result", json::object());
        continue;  // an event, or an older answer
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now()).count();
      if (left <= 0) return nullptr;
      pollfd p{from_, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(left)) <= 0) return nullptr;
      char chunk[65536];
      const ssize_t n = ::read(from_, chunk, sizeof chunk);
      if (n <= 0) return nullptr;
      buffer_.append(chunk, static_cast<std::size_t>(n));
    }
  }

  // A new page at `url`; its session id.
  std::string open(const std::string& url, std::string* target = nullptr) {
    const json t = call("Target.createTarget", {{"url", url}});
    if (!t.is_object() || !t.contains("targetId")) return "";
    if (target) *target = t["targetId"];
    const json s = call("Target.attachToTarget", {{"targetId", t["targetId"]}, {"flatten", true}});
    return s.is_object() && s.contains("sessionId") ? s["sessionId"].get<std::string>() : "";
  }
  // A page's expression, evaluated (promises awaited), as JSON text parsed.
  json eval(const std::string& session, const std::string& expression) {
    const json r = call("Runtime.evaluate", {{"expression", "Promise.resolve(" + expression + ").then(v => JSON.stringify(v))"}, {"returnByValue", true}, {"awaitPromise", true}},
                        session);
    if (!r.is_object() || !r.contains("result") || !r["result"].contains("value") || !r["result"]["value"].is_string()) return nullptr;
    return json::parse(r["result"]["value"].get<std::string>(), nullptr, false);
  }
  void key(const std::string& session, const char* type, const char* code, const char* key, int key_code) {
    call("Input.dispatchKeyEvent", {{"type", type}, {"code", code}, {"key", key}, {"windowsVirtualKeyCode", key_code}}, session);
  }

 private:
  pid_t pid_ = -1;
  int to_ = -1, from_ = -1, id_ = 0;
  std::string buffer_;
};

// One raw HTTP request to 127.0.0.1:`port` (what a browser would not send);
// the answer's status line and body.
std::string raw_http(int port, const std::string& request) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  std::string answer;
  if (fd >= 0 && ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
      ::write(fd, request.data(), request.size()) == static_cast<ssize_t>(request.size())) {
    char chunk[4096];
    pollfd p{fd, POLLIN, 0};
    while (::poll(&p, 1, 3000) > 0) {
      const ssize_t n = ::read(fd, chunk, sizeof chunk);
      if (n <= 0) break;
      answer.append(chunk, static_cast<std::size_t>(n));
    }
  }
  if (fd >= 0) ::close(fd);
  return answer;
}

// The machine's state as a page sees it (null until one came).
json state_of(Browser& b, const std::string& page) { return b.eval(page, "window.station.status && window.station.status.state"); }

double forward_m(const json& a, const json& b) {
  // Along +x, the way pile-to-zone's machine faces at the start.
  return b["chassis_position_m"][0].get<double>() - a["chassis_position_m"][0].get<double>();
}

// Waits until `ready(state)` holds on the page (or `timeout_s`).
template <class Ready>
json wait_for_state(Browser& b, const std::string& page, double timeout_s, Ready ready) {
  const auto until = Clock::now() + std::chrono::duration<double>(timeout_s);
  json s;
  while (Clock::now() < until) {
    s = state_of(b, page);
    if (s.is_object() && ready(s)) return s;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return s;
}

// A live pile-to-zone session in real time, its station, two pages: the
// driver's (with the driver's token) and an instructor's (without). Keys
// in the driver's page move the machine; its frames and the instructor's
// update; the instructor's keys and a control without the token move
// nothing; closing the driver's page puts the levers to neutral and the
// machine stops.
TEST(SkidsimStation, APageDrivesALiveSessionAndAnotherWatchesIt) {
  const std::string browser_exe = browser_path();
  ASSERT_FALSE(browser_exe.empty()) << "headless Chromium is needed (scripts/setup.sh installs chromium-headless-shell)";
  const std::string url = "udpm://239.255.76.67:7701?ttl=0";
  const fs::path work = fs::temp_directory_path() / ("skidsim_station_test_" + std::to_string(::getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  const std::string exercise = kSource + "/scenarios/pile_to_zone.xml";
  // Each process within a time limit, whatever the test does.
  const std::string station = "timeout 180 " + std::string(SKIDSIM_BINARY) + " station --session st-1 --exercise " + exercise + " --lcm '" + url +
                              "' --port 0 --driver-token 0123456789abcdef --fps 5 --width 160 --height 90 --backend osmesa " +
                              "--linger-s 2 > " + (work / "station.out").string() + " 2>&1; echo $? > " + (work / "station.rc").string();
  ASSERT_EQ(std::system(("(" + station + ") &").c_str()), 0);
  std::smatch port;
  const auto start = Clock::now();
  std::string out;
  while (!std::regex_search(out = slurp(work / "station.out"), port, std::regex("127\\.0\\.0\\.1:([0-9]+)/")) &&
         Clock::now() - start < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_FALSE(port.empty()) << out;
  const std::string base = "http://127.0.0.1:" + std::string(port[1]) + "/";
  Browser b(browser_exe, work / "profile");
  ASSERT_TRUE(b.started());
  std::string driver_target;
  const std::string driver = b.open(base + "?driver=0123456789abcdef", &driver_target);
  const std::string watcher = b.open(base);
  ASSERT_FALSE(driver.empty());
  ASSERT_FALSE(watcher.empty());
  // The session once both pages are open.
  const std::string run = "timeout 120 " + std::string(SKIDSIM_BINARY) + " run " + exercise + " --mode realtime --session st-1 --lcm '" +
                          url + "' --max-s 30 --out " + (work / "run").string() + " > " + (work / "run.out").string() +
                          " 2>&1; echo $? > " + (work / "run.rc").string();
  ASSERT_EQ(std::system(("(" + run + ") &").c_str()), 0);

  // Both pages get the session: its state, and frames from both cameras.
  const json at_rest = wait_for_state(b, driver, 30, [](const json& s) { return s["sim_time_s"].get<double>() > 2.0; });
  ASSERT_TRUE(at_rest.is_object()) << slurp(work / "station.out");
  const auto frames = [&](const std::string& page) { return b.eval(page, "window.station.frames"); };
  const auto until_frames = Clock::now() + std::chrono::seconds(30);
  json f0 = frames(driver), w0 = frames(watcher);
  while ((f0["trainee"].get<int>() < 2 || f0["aerial"].get<int>() < 2 || w0["aerial"].get<int>() < 2) && Clock::now() < until_frames) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    f0 = frames(driver), w0 = frames(watcher);
  }
  EXPECT_GE(f0["trainee"].get<int>(), 2);
  EXPECT_GE(f0["aerial"].get<int>(), 2);
  EXPECT_GE(w0["aerial"].get<int>(), 2);
  EXPECT_EQ(b.eval(driver, "window.station.status.you_drive"), true);
  EXPECT_EQ(b.eval(watcher, "window.station.status.you_drive"), false);

  // W held 0.8 s in the driver's page: both tracks forward (towards the
  // pile, 3 m ahead).
  const json before = state_of(b, driver);
  b.key(driver, "keyDown", "KeyW", "w", 87);
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  b.key(driver, "keyUp", "KeyW", "w", 87);
  const json after = wait_for_state(b, driver, 5, [](const json& s) { return s["speed_m_s"].get<double>() < 0.05; });
  const double moved = forward_m(before, after);
  // From the key to the first frame that shows the machine moving: the
  // first state moving after the key (its time in the session), then the
  // first trainee frame drawn at or after that time, on the page's clock.
  const json log = b.eval(driver, "window.station.log");
  double key_ms = -1, moving_s = -1, frame_ms = -1, state_ms = -1;
  for (const json& k : log["keys"])
    if (k["code"] == "KeyW") key_ms = k["at_ms"];
  for (const json& st : log["states"])
    if (st["at_ms"].get<double>() > key_ms && st["speed_m_s"].get<double>() > 0.05 && moving_s < 0)
      moving_s = st["sim_time_s"], state_ms = st["at_ms"];
  for (const json& fr : log["frames"])
    if (fr["view"] == "trainee" && fr["sim_time_s"].get<double>() >= moving_s && moving_s >= 0 && frame_ms < 0) frame_ms = fr["at_ms"];
  std::printf("[ measured ] key to the first state showing the machine moving %.0f ms, to the first frame drawn then %.0f ms "
              "(5 frames a second, 160 x 90)\n",
              state_ms - key_ms, frame_ms - key_ms);
  EXPECT_GT(frame_ms, key_ms) << "a frame shows it";
  std::printf("[ measured ] W held 0.8 s in the page: the machine went %.2f m forward (now %.3f m/s)\n", moved,
              after["speed_m_s"].get<double>());
  EXPECT_GT(moved, 0.3);
  EXPECT_LT(std::abs(after["chassis_position_m"][1].get<double>() - before["chassis_position_m"][1].get<double>()), 0.2)
      << "straight on";
  const json f1 = frames(driver), w1 = frames(watcher);
  EXPECT_GT(f1["trainee"].get<int>(), f0["trainee"].get<int>()) << "the driver's view goes on";
  EXPECT_GT(w1["trainee"].get<int>(), w0["trainee"].get<int>()) << "the instructor's too";

  // The instructor's page: its keys move nothing, and a control without
  // the token is refused.
  const json still = wait_for_state(b, watcher, 5, [](const json& s) { return s["speed_m_s"].get<double>() < 0.01; });
  b.key(watcher, "keyDown", "KeyW", "w", 87);
  const json refused = b.eval(watcher,
                              "fetch('/control', {method: 'POST', body: JSON.stringify({drive_left: 1, drive_right: 1, lift: 0, "
                              "tilt: 0, throttle: 1, parking_brake: false})}).then(r => r.status)");
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  b.key(watcher, "keyUp", "KeyW", "w", 87);
  const json still_after = state_of(b, watcher);
  EXPECT_EQ(refused, 403);
  // Requests that do not fit are refused, naming what, and change nothing.
  const json bad = b.eval(watcher,
                          "Promise.all(["
                          "fetch('/frame.jpg?camera=roof'), fetch('/frame.jpg?camera=trainee&after=-3'), "
                          "fetch('/status?events_after=x'), "
                          "fetch('/control?driver=0123456789abcdef', {method: 'POST', body: 'not json'}), "
                          "fetch('/control?driver=0123456789abcdef', {method: 'POST', body: JSON.stringify({drive_left: 2, "
                          "drive_right: 0, lift: 0, tilt: 0, throttle: 1, parking_brake: false})}), "
                          "fetch('/control?driver=0123456789abcdef', {method: 'POST', body: 'x'.repeat(100000)}), "
                          "fetch('/nothing')].map(p => p.then(async r => [r.status, await r.text()])))");
  ASSERT_TRUE(bad.is_array()) << bad;
  const int want[] = {400, 400, 400, 400, 400, 413, 404};
  const char* says[] = {"camera", "after", "events_after", "not a JSON object", "drive_left", "", ""};
  for (std::size_t k = 0; k < 7; ++k) {
    EXPECT_EQ(bad[k][0], want[k]) << k << ": " << bad[k];
    EXPECT_NE(bad[k][1].get<std::string>().find(says[k]), std::string::npos) << k << ": " << bad[k];
  }
  // What no page here sends: a request for another host (a page elsewhere
  // renamed to this one), a chunked body of any length.
  const int port_number = std::stoi(std::string(port[1]));
  const std::string other_host = raw_http(port_number, "GET /status HTTP/1.1\r\nHost: elsewhere.example\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(other_host.rfind("HTTP/1.1 403", 0), 0u) << other_host;
  const std::string chunked = raw_http(port_number,
                                       "POST /control?driver=0123456789abcdef HTTP/1.1\r\nHost: 127.0.0.1\r\nTransfer-Encoding: chunked\r\n"
                                       "Connection: close\r\n\r\n5\r\nhello\r\n0\r\n\r\n");
  EXPECT_EQ(chunked.rfind("HTTP/1.1 411", 0), 0u) << chunked;
  EXPECT_LT(std::abs(forward_m(still, still_after)), 0.05) << "the instructor's keys moved the machine";

  // S held in the driver's page (back, away from the pile), then the page
  // closed: neutral, it stops.
  b.key(driver, "keyDown", "KeyS", "s", 83);
  const json moving = wait_for_state(b, watcher, 5, [](const json& s) { return s["speed_m_s"].get<double>() > 0.2; });
  ASSERT_GT(moving["speed_m_s"].get<double>(), 0.2);
  b.call("Target.closeTarget", {{"targetId", driver_target}});
  const auto closed = Clock::now();
  const json stopped = wait_for_state(b, watcher, 5, [](const json& s) { return s["speed_m_s"].get<double>() < 0.05; });
  const double took = std::chrono::duration<double>(Clock::now() - closed).count();
  std::printf("[ measured ] driver's page closed moving at %.2f m/s: stopped (%.3f m/s) %.1f s later (%d release beacons)\n",
              moving["speed_m_s"].get<double>(), stopped["speed_m_s"].get<double>(), took,
              b.eval(watcher, "window.station.status.releases").get<int>());
  EXPECT_LT(stopped["speed_m_s"].get<double>(), 0.05);
  EXPECT_GE(b.eval(watcher, "window.station.status.releases").get<int>(), 1) << "the closing page's beacon";
  const auto until_gone = Clock::now() + std::chrono::seconds(3);  // the page's status comes every 250 ms
  while (b.eval(watcher, "window.station.status.driver_connected") != false && Clock::now() < until_gone)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(b.eval(watcher, "window.station.status.driver_connected"), false);
  const json later = wait_for_state(b, watcher, 5, [](const json& s) { return s["speed_m_s"].get<double>() < 0.01; });
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  EXPECT_LT(std::abs(forward_m(later, state_of(b, watcher))), 0.05) << "it stays where it stopped";

  // The session ends at its 30 s; the station then (after 2 s) too.
  const auto until_end = Clock::now() + std::chrono::seconds(60);
  while ((!fs::exists(work / "run.rc") || !fs::exists(work / "station.rc")) && Clock::now() < until_end)
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(slurp(work / "run.rc"), "0\n") << slurp(work / "run.out");
  EXPECT_EQ(slurp(work / "station.rc"), "0\n") << slurp(work / "station.out");
  fs::remove_all(work);
}

// A station refuses what it cannot do safely, naming why.
TEST(SkidsimStation, RefusesToListenBeyondThisHostWithoutAToken) {
  const std::string exercise = kSource + "/scenarios/pile_to_zone.xml";
  const auto r = run_skidsim("station --session st-2 --exercise " + exercise + " --bind 0.0.0.0 --port 0");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--token"), std::string::npos) << r.output;
  const auto bad_token = run_skidsim("station --session st-2 --exercise " + exercise + " --port 0 --driver-token 'a<b'");
  EXPECT_EQ(bad_token.exit_code, 2) << bad_token.output;
  const auto bad_name = run_skidsim("station --session 'st.2' --exercise " + exercise + " --port 0");
  EXPECT_EQ(bad_name.exit_code, 2) << bad_name.output;
  const auto short_token = run_skidsim("station --session st-2 --exercise " + exercise + " --bind 0.0.0.0 --port 0 --token abc");
  EXPECT_EQ(short_token.exit_code, 2) << short_token.output;
  EXPECT_NE(short_token.output.find("16 or more"), std::string::npos) << short_token.output;
  const auto a_name = run_skidsim("station --session st-2 --exercise " + exercise + " --bind 127.example.org --port 0");
  EXPECT_EQ(a_name.exit_code, 2) << a_name.output << ": a name that looks like this host's address is not it";
}

}  // namespace
}  // namespace skidsim::testing
