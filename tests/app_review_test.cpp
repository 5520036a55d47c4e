// skidsim review: the review page in a real browser (headless Chromium,
// installed by the setup step): it loads without script errors, the
// scrubber moves the frame and every plot's marker together; the contact
// sheet; re-rendering a session from another camera from its log's scene
// stream.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>
#include <cstdlib>
#include <filesystem>
#include <vector>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "io/exercise.h"
#include "io/png_image.h"
#include "render/renderer.h"
#include "tests/app_support.h"
#include "visual/scene_dust.h"
#include "visual/scene_stream.h"

namespace {

namespace fs = std::filesystem;
using skidsim::testing::run_command;
using skidsim::testing::run_skidsim;

const std::string kScenario = std::string(SKIDSIM_SOURCE_DIR) + "/scenarios/pile_to_zone.xml";
const std::string kScript = std::string(SKIDSIM_SOURCE_DIR) + "/scenarios/pile_to_zone.operator.xml";

std::string chromium() {
  for (const char* name : {"chromium-headless-shell", "chromium"}) {
    const auto r = run_command(std::string("command -v ") + name);
    if (r.exit_code == 0) return r.output.substr(0, r.output.find('\n'));
  }
  return "";
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Page {
  std::string dom, log;
};

// The page's DOM after its scripts ran, and the browser's log.
Page open_page(const std::string& browser, const fs::path& html, const std::string& fragment, const fs::path& work) {
  const fs::path dom = work / "dom.html", log = work / "chromium.log";
  const std::string cmd = "{ timeout 120 " + browser + " --no-sandbox --disable-gpu --user-data-dir=" + (work / "profile").string() +
                          " --enable-logging=stderr --v=0 --virtual-time-budget=2000 --dump-dom 'file://" + html.string() +
                          fragment + "' > " + dom.string() + " 2> " + log.string() + "; }";
  const auto r = run_command(cmd);
  EXPECT_EQ(r.exit_code, 0) << r.output << slurp(log);
  return {slurp(dom), slurp(log)};
}

std::vector<double> marker_positions(const std::string& dom) {
  std::vector<double> xs;
  const std::regex line("<line ([^>]*)>"), x1("x1=\"([-0-9.]+)\"");
  for (auto it = std::sregex_iterator(dom.begin(), dom.end(), line); it != std::sregex_iterator(); ++it) {
    const std::string attrs = (*it)[1];
    std::smatch m;
    if (attrs.find("class=\"marker\"") != std::string::npos && std::regex_search(attrs, m, x1)) xs.push_back(std::stod(m[1]));
  }
  return xs;
}

std::string attribute(const std::string& dom, const std::string& pattern) {
  std::smatch m;
  return std::regex_search(dom, m, std::regex(pattern)) ? std::string(m[1]) : "";
}

TEST(SkidsimReview, PageWorksInABrowserAndReRendersFromAnotherCamera) {
  const std::string browser = chromium();
  ASSERT_FALSE(browser.empty()) << "headless Chromium is needed (scripts/setup.sh installs chromium-headless-shell)";
  const fs::path run = fs::temp_directory_path() / "skidsim_review_run";
  const fs::path work = fs::temp_directory_path() / "skidsim_review_browser";
  fs::remove_all(run);
  fs::remove_all(work);
  fs::create_directories(work);
  ASSERT_EQ(run_skidsim("run " + kScenario + " --script " + kScript +
                        " --max-s 6 --record --frame-width 160 --frame-height 90 --render-backend osmesa --out " + run.string())
                .exit_code,
            0);
  const auto r = run_skidsim("review " + run.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path html = run / "review.html";
  ASSERT_TRUE(fs::exists(html));

  // The contact sheet: 12 of the 60 frames, 4 across, 320 px thumbnails.
  const skidsim::io::RgbImage sheet = skidsim::io::read_png_rgb8((run / "contact_sheet.png").string());
  EXPECT_EQ(sheet.width, 6 + 4 * (320 + 6));
  EXPECT_EQ(sheet.height, 6 + 3 * (180 + 5 + 6));

  // The scrubber at 0 s, then moved (review.html#t=...: through its input
  // handler) to 4.3 s: frame 43 shows and every marker moves with it.
  const Page start = open_page(browser, html, "#t=0", work);
  const Page moved = open_page(browser, html, "#t=4.3", work);
  for (const Page* p : {&start, &moved}) {
    EXPECT_NE(p->dom.find("<ul id=\"errors\"></ul>"), std::string::npos) << "script errors:\n" << p->dom;
    EXPECT_EQ(p->log.find("Uncaught"), std::string::npos) << p->log;
    EXPECT_EQ(p->log.find("CONSOLE"), std::string::npos) << p->log;
  }
  EXPECT_EQ(attribute(start.dom, "id=\"frame\"[^>]*src=\"([^\"]+)\""), "frames/frame_000000.png");
  EXPECT_EQ(attribute(moved.dom, "id=\"frame\"[^>]*src=\"([^\"]+)\""), "frames/frame_000043.png");
  EXPECT_EQ(attribute(moved.dom, "data-time=\"([^\"]+)\""), "4.300");
  const std::vector<double> x0 = marker_positions(start.dom), x1 = marker_positions(moved.dom);
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(run / "report.json"));
  ASSERT_EQ(x1.size(), report["timeline"].size() - 1) << "a marker on each plot (all series but t_s)";
  ASSERT_EQ(x0.size(), x1.size());
  for (std::size_t k = 0; k < x1.size(); ++k) {
    EXPECT_DOUBLE_EQ(x1[k], x1[0]) << "the markers move together";
    EXPECT_GT(x1[k], x0[k] + 100.0) << "4.3 s of 6 s is well right of the start";
  }
  // A screenshot: the page drawn, frame and plots (not blank).
  const fs::path shot = run / "review_screenshot.png";
  ASSERT_EQ(run_command("timeout 120 " + browser + " --no-sandbox --disable-gpu --user-data-dir=" + (work / "profile").string() +
                        " --window-size=1280,1000 --virtual-time-budget=2000 --screenshot=" + shot.string() + " 'file://" +
                        html.string() + "#t=4.3'")
                .exit_code,
            0);
  const skidsim::io::RgbImage screenshot = skidsim::io::read_png_rgb8(shot.string());
  std::set<std::uint32_t> colours;
  for (std::size_t k = 0; k < screenshot.rgb.size(); k += 3)
    colours.insert(static_cast<std::uint32_t>(screenshot.rgb[k]) << 16 | static_cast<std::uint32_t>(screenshot.rgb[k + 1]) << 8 |
                   screenshot.rgb[k + 2]);
  EXPECT_GT(colours.size(), 200u);

  // Re-rendered from above at 5 fps from the log's scene stream (no
  // physics): 30 frames, offered on the page beside the chase set.
  const auto again = run_skidsim("review " + run.string() + " --camera aerial --fps 5 --width 160 --height 90 --backend osmesa");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  const fs::path aerial = run / "frames_aerial_5fps";
  const nlohmann::json meta = nlohmann::json::parse(std::ifstream(aerial / "frames.json"));
  EXPECT_EQ(meta["frames"], 30);
  EXPECT_GE(meta["scene_messages"].get<int>(), 149);  // 6 s at 25 a second
  EXPECT_TRUE(fs::exists(aerial / "frame_000029.png"));
  EXPECT_NE(skidsim::io::read_png_rgb8((aerial / "frame_000010.png").string()).rgb,
            skidsim::io::read_png_rgb8((run / "frames" / "frame_000020.png").string()).rgb)
      << "another camera, another picture";
  EXPECT_NE(slurp(html).find("frames_aerial_5fps"), std::string::npos);
  EXPECT_FALSE(fs::exists(run / ".review_view"));
  // A review re-renders from one camera (skidsim view draws several).
  const auto two = run_skidsim("review " + run.string() + " --camera chase,aerial --fps 5");
  EXPECT_EQ(two.exit_code, 2) << two.output;
  EXPECT_NE(two.output.find("one camera"), std::string::npos) << two.output;
  EXPECT_FALSE(fs::exists(run / ".review_view_chase"));

  // A damaged log: refused, nothing kept.
  fs::resize_file(run / "session.lcmlog", fs::file_size(run / "session.lcmlog") - 7);
  const auto damaged = run_skidsim("review " + run.string() + " --camera cab --fps 2 --width 160 --height 90 --backend osmesa");
  EXPECT_EQ(damaged.exit_code, 2) << damaged.output;
  EXPECT_NE(damaged.output.find("session.lcmlog"), std::string::npos) << damaged.output;
  EXPECT_FALSE(fs::exists(run / "frames_cab_2fps"));
  EXPECT_FALSE(fs::exists(run / ".review_view"));
}

// Frames lost from a recording (a copy that failed, a frame deleted by
// hand): review still writes the page, and says which frames are missing,
// on stderr, in its summary line and on the page (the frames after the gap,
// and those the recorder wrote past the last one found, are not dropped).
TEST(SkidsimReview, MissingFramesAreNamedNotDropped) {
  const fs::path run = fs::temp_directory_path() / "skidsim_review_gaps";
  fs::remove_all(run);
  ASSERT_EQ(run_skidsim("run " + kScenario + " --script " + kScript +
                        " --max-s 2 --record --frame-width 64 --frame-height 36 --render-backend osmesa --out " + run.string())
                .exit_code,
            0);
  ASSERT_TRUE(fs::exists(run / "frames" / "frame_000019.png"));
  for (const char* lost : {"frame_000003.png", "frame_000004.png", "frame_000019.png"}) fs::remove(run / "frames" / lost);
  const auto r = run_skidsim("review " + run.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("frames: 3 of 20 frames missing (frame_000003.png to frame_000004.png, frame_000019.png)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("1 recording(s), 3 frame(s) missing"), std::string::npos) << r.output;
  const std::string html = slurp(run / "review.html");
  EXPECT_NE(html.find("\"frames\":20"), std::string::npos) << "frame k stays at k / fps";
  EXPECT_NE(html.find("\"missing\":[[3,4],[19,19]]"), std::string::npos);
  EXPECT_NE(html.find("(3 frames missing)"), std::string::npos) << "in the set's label";
  // In a browser (when there is one): the gap is said under the frame.
  const std::string browser = chromium();
  if (browser.empty()) return;
  const fs::path work = fs::temp_directory_path() / "skidsim_review_gaps_browser";
  fs::remove_all(work);
  fs::create_directories(work);
  const Page gap = open_page(browser, run / "review.html", "#t=0.35", work);
  EXPECT_NE(gap.dom.find("<ul id=\"errors\"></ul>"), std::string::npos) << gap.dom;
  EXPECT_NE(gap.dom.find("frames/frame_000003.png is missing"), std::string::npos) << gap.dom;
  EXPECT_NE(gap.dom.find("frames/: 3 of 20 frames missing (3-4, 19)"), std::string::npos) << gap.dom;
  const Page after = open_page(browser, run / "review.html", "#t=0.55", work);
  EXPECT_EQ(attribute(after.dom, "id=\"frame\"[^>]*src=\"([^\"]+)\""), "frames/frame_000005.png");
}

TEST(SkidsimReview, BadRunDirectoriesAndCamerasAreRefused) {
  const fs::path none = fs::temp_directory_path() / "skidsim_review_none";
  fs::remove_all(none);
  auto r = run_skidsim("review " + none.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no such run directory"), std::string::npos) << r.output;
  fs::create_directories(none);
  std::ofstream(none / "report.json") << "{ not json";
  r = run_skidsim("review " + none.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("report.json"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(none / "review.html"));
  // A report of the wrong shape, and mistyped fields: named, exit 2.
  std::ofstream(none / "report.json") << "[1, 2]";
  r = run_skidsim("review " + none.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("not a report"), std::string::npos) << r.output;
  std::ofstream(none / "report.json") << R"({"recording": {"fps": "fast", "camera": 3}, "events": [{"time_s": 1, "severity": 1e300, "text": "<!--<script>"}]})";
  fs::create_directories(none / "frames_cab_2fps");
  std::ofstream(none / "frames_cab_2fps" / "frames.json") << R"({"fps": "x"})";
  r = run_skidsim("review " + none.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("frames_cab_2fps/frames.json"), std::string::npos) << r.output;
  fs::remove_all(none / "frames_cab_2fps");
  r = run_skidsim("review " + none.string());  // the rest is read as far as it makes sense
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const std::string html = slurp(none / "review.html");
  EXPECT_EQ(html.find("<!--<script>"), std::string::npos) << "no '<' inside the page's data";
  EXPECT_NE(html.find("\\u003c!--\\u003cscript>"), std::string::npos);
  // Bad re-render options: refused before anything runs.
  for (const std::string bad : {" --camera drone", " --fps -3", " --fps 1000"}) {
    r = run_skidsim("review " + none.string() + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.output;
  }
}

}  // namespace

namespace {

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The visual channel as a process of its own: `skidsim view` draws a run
// from its log's scene stream, without the physics, and gets the run's own
// recording pixel for pixel (both draw the stream; one renderer). It draws
// another camera as well, and refuses a log of another exercise.
TEST(SkidsimView, DrawsARunsLogAsTheRunsRecordingDidPixelForPixel) {
  const fs::path run = fs::temp_directory_path() / "skidsim_view_run";
  fs::remove_all(run);
  const auto r = run_skidsim("run " + kScenario + " --script " + kScript +
                             " --max-s 12 --record --fps 5 --frame-width 96 --frame-height 54 --render-backend osmesa --out " +
                             run.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path out = fs::temp_directory_path() / "skidsim_view_out";
  fs::remove_all(out);
  const auto v = run_skidsim("view " + run.string() + " --fps 5 --width 96 --height 54 --backend osmesa --out " + out.string());
  ASSERT_EQ(v.exit_code, 0) << v.output;
  int frames = 0, differ = 0;
  for (int k = 0;; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", k);
    const bool recorded = fs::exists(run / "frames" / name), viewed = fs::exists(out / "frames" / name);
    EXPECT_EQ(recorded, viewed) << name;
    if (!recorded || !viewed) break;
    ++frames;
    differ += bytes_of(run / "frames" / name) != bytes_of(out / "frames" / name);
  }
  std::printf("[ measured ] %d frames drawn from the log, %d differ from the run's recording\n", frames, differ);
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(run / "report.json"));
  EXPECT_EQ(frames, report["recording"]["frames"].get<int>());
  EXPECT_GE(frames, 59);  // 12 s at 5 fps
  EXPECT_EQ(differ, 0);
  const nlohmann::json meta = nlohmann::json::parse(std::ifstream(out / "frames" / "frames.json"));
  EXPECT_EQ(meta["frames"], frames);
  EXPECT_GE(meta["scene_messages"].get<int>(), 299);  // 12 s at 25 a second

  const fs::path aerial = fs::temp_directory_path() / "skidsim_view_aerial";
  fs::remove_all(aerial);
  ASSERT_EQ(run_skidsim("view " + run.string() + " --camera aerial --fps 2 --width 64 --height 36 --backend osmesa --out " +
                        aerial.string())
                .exit_code,
            0);
  EXPECT_TRUE(fs::exists(aerial / "frames" / "frame_000023.png"));  // 0 to 11.5 s at 2 fps
  EXPECT_FALSE(fs::exists(aerial / "frames" / "frame_000024.png"));

  // Two cameras at once: each the frames a view from that camera alone draws.
  const fs::path both = fs::temp_directory_path() / "skidsim_view_both", aerial_alone = fs::temp_directory_path() / "skidsim_view_aerial5";
  fs::remove_all(both.string() + "_chase"), fs::remove_all(both.string() + "_aerial"), fs::remove_all(aerial_alone);
  const auto two = run_skidsim("view " + run.string() + " --camera chase,aerial --fps 5 --width 96 --height 54 --backend osmesa --out " +
                               both.string());
  ASSERT_EQ(two.exit_code, 0) << two.output;
  ASSERT_EQ(run_skidsim("view " + run.string() + " --camera aerial --fps 5 --width 96 --height 54 --backend osmesa --out " +
                        aerial_alone.string())
                .exit_code,
            0);
  int two_frames = 0, two_differ = 0;
  for (int k = 0; k < frames; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", k);
    two_frames += fs::exists(fs::path(both.string() + "_chase") / "frames" / name) &&
                  fs::exists(fs::path(both.string() + "_aerial") / "frames" / name);
    two_differ += bytes_of(fs::path(both.string() + "_chase") / "frames" / name) != bytes_of(out / "frames" / name);
    two_differ += bytes_of(fs::path(both.string() + "_aerial") / "frames" / name) != bytes_of(aerial_alone / "frames" / name);
  }
  EXPECT_EQ(two_frames, frames);
  EXPECT_EQ(two_differ, 0);
  EXPECT_NE(bytes_of(fs::path(both.string() + "_chase") / "frames" / "frame_000030.png"),
            bytes_of(fs::path(both.string() + "_aerial") / "frames" / "frame_000030.png"));
  const auto twice = run_skidsim("view " + run.string() + " --camera chase,chase --out " + (both.string() + "_twice"));
  EXPECT_EQ(twice.exit_code, 2) << twice.output;
  for (const fs::path& p : {fs::path(both.string() + "_chase"), fs::path(both.string() + "_aerial"), aerial_alone}) fs::remove_all(p);

  const auto other = run_skidsim("view " + run.string() + " --exercise " + std::string(SKIDSIM_SOURCE_DIR) +
                                 "/scenarios/driving_course.xml --out " + (aerial.string() + "_other"));
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_NE(other.output.find("was recorded from exercise"), std::string::npos) << other.output;
  EXPECT_FALSE(fs::exists(aerial.string() + "_other"));
  for (const fs::path& p : {run, out, aerial}) fs::remove_all(p);
}

// A live session drawn by two views of their own (other processes, over
// LCM on this host's network) that join when they like: a first message,
// the whole ground, is often lost to the host's UDP buffer, and the
// stream's refresh makes the picture whole within 5 s. From then on a view
// draws frame k from the session's state at k / fps, as a view of the
// session's log does. The view that draws every frame draws the log's
// pixels once the dust raised before its picture was whole has faded (a
// puff lives at most 3.5 s, skidsim::visual::kMaxPuffLifeS; every frame when it heard the first message).
// The one that skips drawing when behind (the session runs in lockstep
// faster than real time) differs only where the sand's moving texture,
// which the renderer moves on from frame to frame it draws, went without a
// frame in the 0.9 s its layers last (render::kFlowPeriodS, 8.2.3).
TEST(SkidsimView, DrawsALiveSessionAsItsLogDrawsIt) {
  const std::string url = "udpm://239.255.76.67:7697?ttl=0";
  const fs::path tmp = fs::temp_directory_path(), run = tmp / "skidsim_view_live_run", logged = tmp / "skidsim_view_live_log";
  const fs::path views[2] = {tmp / "skidsim_view_live_every", tmp / "skidsim_view_live_skipping"};
  for (const fs::path& p : {run, logged, views[0], views[1]}) fs::remove_all(p);
  const auto start = std::chrono::steady_clock::now();
  for (int v = 0; v < 2; ++v) {
    const std::string rc = views[v].string() + ".rc", out = views[v].string() + ".out";
    fs::remove(rc);
    const std::string view = std::string(SKIDSIM_BINARY) + " view --session lv-1 --exercise " + kScenario + " --lcm '" + url +
                             "' --fps 5 --width 96 --height 54 --backend osmesa --idle-s 20" + (v == 0 ? " --every-frame" : "") +
                             " --out " + views[v].string() + " > " + out + " 2>&1; echo $? > " + rc;
    ASSERT_EQ(std::system(("(" + view + ") &").c_str()), 0);
    while (bytes_of(out).find("listening") == std::string::npos && std::chrono::steady_clock::now() - start < std::chrono::seconds(60))
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    ASSERT_NE(bytes_of(out).find("listening"), std::string::npos) << bytes_of(out);
  }
  ASSERT_EQ(std::system((std::string(SKIDSIM_BINARY) + " operator " + kScript + " --session lv-1 --lcm '" + url +
                         "' --idle-s 5 > /dev/null 2>&1 &")
                            .c_str()),
            0);
  const auto r = run_skidsim("run " + kScenario + " --mode lockstep --session lv-1 --lcm '" + url + "' --max-s 20 --out " + run.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto v = run_skidsim("view " + run.string() + " --fps 5 --width 96 --height 54 --backend osmesa --out " + logged.string());
  ASSERT_EQ(v.exit_code, 0) << v.output;
  for (int k = 0; k < 2; ++k) {
    const std::string rc = views[k].string() + ".rc", out = views[k].string() + ".out";
    while (!fs::exists(rc) && std::chrono::steady_clock::now() - start < std::chrono::seconds(180))
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the rc file written
    ASSERT_EQ(bytes_of(rc), "0\n") << bytes_of(out);
    fs::remove(rc), fs::remove(out);
  }
  for (int k = 0; k < 2; ++k) {
    const fs::path& live = views[k];
    const nlohmann::json meta = nlohmann::json::parse(std::ifstream(live / "frames" / "frames.json"));
    EXPECT_EQ(meta["end"], "session_ended");
    const int first = meta["first_frame"], last = meta["last_frame"];
    const double fps = 5.0, refresh_s = skidsim::visual::kSceneRefreshMessages / skidsim::io::kMaxRecordFps;
    const double joined_s = meta["first_time_s"];
    const int settled = meta["first_step"] == 0 ? 0 : first + static_cast<int>(std::ceil(skidsim::visual::kMaxPuffLifeS * fps));
    // A message lost to the network (rare past the first): its squares come
    // again within the refresh, and the dust they raise fades 3.5 s later.
    const auto after_a_loss = [&](int frame) {
      for (const auto& lost : meta["lost_after_s"]) {
        const double t = lost.get<double>();
        if (frame / fps > t && frame / fps <= t + refresh_s + skidsim::visual::kMaxPuffLifeS) return true;
      }
      return false;
    };
    const int texture_frames = static_cast<int>(std::ceil(skidsim::render::kFlowPeriodS * fps));
    int drawn = 0, compared = 0, differ = 0, unexplained = 0;
    std::vector<bool> was_drawn(static_cast<std::size_t>(last + 1), false);
    for (int f = first; f <= last; ++f) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%06d.png", f);
      if (!fs::exists(live / "frames" / name)) continue;
      ++drawn;
      was_drawn[static_cast<std::size_t>(f)] = true;
      ASSERT_TRUE(fs::exists(logged / "frames" / name)) << name;
      if (f < settled || after_a_loss(f)) continue;
      ++compared;
      if (bytes_of(live / "frames" / name) == bytes_of(logged / "frames" / name)) continue;
      ++differ;
      bool skipped_before = false;
      for (int b = std::max(first, f - texture_frames); b < f; ++b) skipped_before = skipped_before || !was_drawn[static_cast<std::size_t>(b)];
      unexplained += !skipped_before;
    }
    std::printf("[ measured ] live view %s: first message at step %d, frames %d to %d (picture whole at %.1f s), %d drawn, "
                "%d skipped behind, %d messages lost; %d of %d settled frames differ from the log's (%d with no frame skipped "
                "in the 0.9 s before)\n",
                k == 0 ? "drawing every frame" : "skipping when behind", meta["first_step"].get<int>(), first, last, first / 5.0, drawn,
                meta["frames_skipped"].get<int>(), meta["messages_lost"].get<int>(), differ, compared, unexplained);
    EXPECT_EQ(meta["frames"], drawn);
    EXPECT_EQ(meta["messages_refused"], 0);
    // Whole within the refresh of joining (and the frame due after it).
    EXPECT_LE(first / fps - joined_s, refresh_s + 1.0 / fps + 1.0 / skidsim::io::kMaxRecordFps) << "joined at " << joined_s << " s";
    EXPECT_EQ(last, 99) << "the last frame due (19.8 s of 20) drawn";
    EXPECT_GE(compared, 10);
    if (k == 0) {
      EXPECT_EQ(meta["frames_skipped"], 0);
      EXPECT_EQ(differ, 0);
    }
    EXPECT_EQ(unexplained, 0);
  }
  for (const fs::path& p : {run, logged, views[0], views[1]}) fs::remove_all(p);
}

// What a view is asked to draw must be one thing it can: a run, or a live
// session with its exercise and a name a session can have.
TEST(SkidsimView, RefusesWhatItCannotDrawNamingWhy) {
  struct Bad {
    std::string args, says;
  };
  const Bad bad[] = {
      {"view", "give a run directory"},
      {"view /tmp --session bay-1 --exercise " + kScenario, "not both"},
      {"view --session bay-1", "--exercise"},
      {"view --session 'bay.1' --exercise " + kScenario, "--session"},
      {"view --session bay-1 --exercise " + kScenario + " --idle-s 0", "--idle-s"},
  };
  for (const Bad& b : bad) {
    const auto r = run_skidsim(b.args);
    EXPECT_EQ(r.exit_code, 2) << b.args << ": " << r.output;
    EXPECT_NE(r.output.find(b.says), std::string::npos) << b.args << ": " << r.output;
  }
}

}  // namespace
