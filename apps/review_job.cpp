#include "apps/review_job.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "visual/contact_sheet.h"
#include "report/review_html.h"
#include "apps/view_job.h"
#include "io/exercise.h"
#include "io/atomic_file.h"
#include "io/json_file.h"

namespace skidsim::apps {

using report::FrameSet;
using report::render_review_html;
using visual::contact_sheet;
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json read_json(const fs::path& path) {
  if (!fs::exists(fs::symlink_status(path)))
    throw io::InputError(path.string() + ": no such file (is this a run directory of skidsim run?)");
  return io::read_json_file(path.string(), "JSON file");
}

// A report's or frames.json's fields, read without trusting their types.
double number_at(const json& j, const char* key, double fallback) {
  if (!j.is_object()) return fallback;
  const auto it = j.find(key);
  return it != j.end() && it->is_number() && std::isfinite(it->get<double>()) ? it->get<double>() : fallback;
}

std::string text_at(const json& j, const char* key, const std::string& fallback) {
  if (!j.is_object()) return fallback;
  const auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : fallback;
}

std::string fps_text(double fps) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", fps);
  return buf;
}

// The frames of a set: frame_000000.png, frame_000001.png, ... as the
// recorder names them, frame k taken at k / fps. Every one there is found
// (the folder is listed, not probed until the first gap), and a frame the
// set should have but lacks (lost in a copy, deleted by hand) is named:
// the set has as many frames as the recorder wrote (`recorded`, from
// report.json or frames.json; -1: not known) or up to the last one found.
struct FrameScan {
  std::vector<std::string> paths;              // the frames there, in order
  int slots = 0;                               // frames 0 .. slots - 1 belong to the set
  std::vector<std::pair<int, int>> missing;    // first and last of each run of missing frames
  int missing_count = 0;
};

FrameScan scan_frames(const fs::path& dir, double recorded) {
  constexpr int kMaxFrames = 1000000;  // frame_%06d: six digits
  FrameScan scan;
  std::vector<int> found;
  std::error_code ec;
  if (fs::is_directory(dir, ec))
    for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
      const std::string name = e.path().filename().string();
      if (name.size() != 16 || name.compare(0, 6, "frame_") != 0 || name.compare(12, 4, ".png") != 0) continue;
      if (!std::all_of(name.begin() + 6, name.begin() + 12, [](char c) { return c >= '0' && c <= '9'; })) continue;
      found.push_back(std::stoi(name.substr(6, 6)));
    }
  std::sort(found.begin(), found.end());
  scan.slots = found.empty() ? 0 : found.back() + 1;
  if (recorded >= 1.0 && recorded <= kMaxFrames && recorded == std::floor(recorded))
    scan.slots = std::max(scan.slots, static_cast<int>(recorded));
  int next = 0;  // the first frame not yet accounted for
  const auto gap_until = [&](int k) {
    if (k > next) {
      scan.missing.emplace_back(next, k - 1);
      scan.missing_count += k - next;
    }
  };
  for (const int k : found) {
    gap_until(k);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", k);
    scan.paths.push_back((dir / name).string());
    next = k + 1;
  }
  gap_until(scan.slots);
  return scan;
}

// "frame_000012.png to frame_000013.png, frame_000040.png"
std::string missing_text(const std::vector<std::pair<int, int>>& missing) {
  std::string text;
  for (std::size_t k = 0; k < missing.size() && k < 8; ++k) {
    char a[32], b[32];
    std::snprintf(a, sizeof a, "frame_%06d.png", missing[k].first);
    std::snprintf(b, sizeof b, "frame_%06d.png", missing[k].second);
    text += (k ? ", " : "") + std::string(a) + (missing[k].second > missing[k].first ? " to " + std::string(b) : "");
  }
  if (missing.size() > 8) text += " and " + std::to_string(missing.size() - 8) + " more gaps";
  return text;
}

// A set as the page shows it, and its frames for the contact sheet. A set
// with frames missing is shown (the report, the plots and the frames there
// are still the session's; the lost ones can be rendered again from the
// log with --camera / --fps), and the gap is said on stderr, in the page
// under the frame and in the set's label, never skipped over.
struct FoundSet {
  FrameSet set;
  std::vector<std::string> paths;
};

void add_set(std::vector<FoundSet>& sets, const fs::path& run, FrameSet f, double recorded) {
  FrameScan scan = scan_frames(run / f.dir, recorded);
  f.frames = scan.slots;
  f.missing = scan.missing;
  if (scan.missing_count > 0) {
    f.label += " (" + std::to_string(scan.missing_count) + " frames missing)";
    std::cerr << "skidsim review: " << (run / f.dir).string() << ": " << scan.missing_count << " of " << scan.slots
              << " frames missing (" << missing_text(scan.missing)
              << "); the page shows them as missing (re-render with --camera or --fps to have them again)\n";
  }
  if (!scan.paths.empty()) sets.push_back({f, std::move(scan.paths)});
}

// The run's own recording (report.json "recording") and every re-render
// (a frames_* folder with its frames.json).
std::vector<FoundSet> find_frame_sets(const fs::path& run, const json& report) {
  std::vector<FoundSet> sets;
  const json recording = report.is_object() && report.contains("recording") ? report["recording"] : json();
  const double recorded_fps = number_at(recording, "fps", 0.0);
  if (recorded_fps >= 0.1 && recorded_fps <= 1000.0) {
    FrameSet f;
    f.dir = "frames";
    f.fps = recorded_fps;
    f.label = text_at(recording, "camera", "recorded") + ", " + fps_text(f.fps) + " fps";
    add_set(sets, run, f, number_at(recording, "frames", -1.0));
  }
  std::vector<fs::path> extra;
  for (const fs::directory_entry& e : fs::directory_iterator(run))
    if (e.is_directory() && e.path().filename().string().rfind("frames_", 0) == 0 && fs::exists(e.path() / "frames.json"))
      extra.push_back(e.path());
  std::sort(extra.begin(), extra.end());
  for (const fs::path& dir : extra) {
    const json meta = read_json(dir / "frames.json");
    FrameSet f;
    f.dir = dir.filename().string();
    f.fps = number_at(meta, "fps", 0.0);
    if (!(f.fps >= 0.1 && f.fps <= 1000.0))
      throw io::InputError((dir / "frames.json").string() + ": 'fps' must be a number of frames a second (0.1 to 1000)");
    f.label = text_at(meta, "camera", "?") + ", " + fps_text(f.fps) + " fps (re-rendered)";
    add_set(sets, run, f, number_at(meta, "frames", -1.0));
  }
  return sets;
}

// Draws the run again from its log's scene stream (skidsim view, no
// physics) and keeps the frames. Returns the exit code.
int rerender(const ReviewJob& job, const fs::path& run, std::string* frames_dir) {
  ViewJob v;
  v.source = run.string();
  v.exercise_path = job.exercise_path;
  v.camera = job.camera;
  v.fps = job.fps;
  v.width = job.width;
  v.height = job.height;
  v.backend = job.backend;
  v.out_dir = (run / ".review_view").string();
  const int code = run_view(v);
  if (code != 0) return code;
  const fs::path drawn = v.out_dir;
  const json meta = read_json(drawn / "frames" / "frames.json");  // written by this build: its types are right
  const std::string camera = meta.value("camera", std::string("chase"));
  const double fps = meta.value("fps", 10.0);
  const fs::path target = run / ("frames_" + camera + "_" + fps_text(fps) + "fps");
  // Swap in the new frames; an older set of the same name goes only after.
  const fs::path old = run / ".review_old_frames";
  fs::remove_all(old);
  if (fs::exists(target)) fs::rename(target, old);
  fs::rename(drawn / "frames", target);
  if (fs::exists(drawn / "session.mp4")) fs::rename(drawn / "session.mp4", run / (target.filename().string() + ".mp4"));
  fs::remove_all(old);
  fs::remove_all(drawn);
  *frames_dir = target.filename().string();
  std::cout << "re-rendered " << meta.value("frames", 0) << " frames from the " << camera << " camera at " << fps_text(fps)
            << " fps into " << target.string() << " (drawn from the log's scene stream)\n";
  return 0;
}

}  // namespace

int review_session(const ReviewJob& job) {
  const fs::path run = job.run_dir;
  if (!fs::is_directory(run)) throw io::InputError(job.run_dir + ": no such run directory");
  const json report = read_json(run / "report.json");
  if (!report.is_object()) throw io::InputError((run / "report.json").string() + ": not a report (expected a JSON object)");
  if (job.fps != 0.0) io::check_frame_rate(job.fps);
  if (job.camera.find(',') != std::string::npos) throw io::InputError("--camera '" + job.camera + "': review re-renders from one camera");
  if (job.width < 0 || job.height < 0) throw io::InputError("--width / --height: expected 16 to 8192 pixels");
  std::string rendered;  // the frames just re-rendered, if any
  if (!job.camera.empty() || job.fps > 0.0 || job.width > 0 || job.height > 0) {
    const int code = rerender(job, run, &rendered);
    if (code != 0) return code;
  }
  const std::vector<FoundSet> found = find_frame_sets(run, report);
  std::vector<FrameSet> sets;
  int missing = 0;
  for (const FoundSet& f : found) {
    sets.push_back(f.set);
    for (const auto& [first, last] : f.set.missing) missing += last - first + 1;
  }
  // The sheet of the frames just rendered, else the run's own recording;
  // made before anything is written, so a bad frame leaves both files as
  // they were.
  const FoundSet* shown = found.empty() ? nullptr : &found.front();
  for (const FoundSet& f : found)
    if (f.set.dir == rendered) shown = &f;
  io::RgbImage sheet;
  if (shown) sheet = contact_sheet(shown->paths);
  io::write_text_atomically((run / "review.html").string(), render_review_html(report, sets));
  std::cout << "wrote " << (run / "review.html").string();
  if (shown) {
    io::write_png_rgb8((run / "contact_sheet.png").string(), sheet);
    std::cout << " and " << (run / "contact_sheet.png").string() << " (" << shown->set.label << ")";
  }
  std::cout << "; " << sets.size() << " recording(s)";
  if (missing > 0) std::cout << ", " << missing << " frame(s) missing (see above)";
  std::cout << "\n";
  return 0;
}

}  // namespace skidsim::apps
