// Recording (docs/rendering.md, "Recording"): frames rendered on a thread of their
// own from snapshots of the world taken at the recording rate, so that
// rendering never changes the simulation. The session hands over a copy of
// the scene and goes on; when the recorder is three frames behind, the
// session waits for it (the frames are never dropped).
#pragma once

#include <condition_variable>
#include <deque>
#include <mutex>
#include <string>
#include <thread>

#include "render/scene.h"

namespace skidsim::visual {

class FrameRecorder {
 public:
  // Frames go to `dir`/frame_000000.png, ...; the context is made on the
  // recorder's thread (`backend`: auto, egl or osmesa), and the constructor
  // waits for it: std::runtime_error if there is none (nothing has run yet).
  FrameRecorder(std::string dir, int width, int height, std::string backend);
  ~FrameRecorder();
  FrameRecorder(const FrameRecorder&) = delete;
  FrameRecorder& operator=(const FrameRecorder&) = delete;

  // The frame goes to frame_<number>.png; -1: the next after those written
  // (a live view names its frames by their time and may skip some).
  void submit(render::Scene scene, const render::Camera& camera, int number = -1);
  // Waits for every frame to be written. Returns "" or, if the recorder
  // failed on the way (a full disk), why: the frames up to there remain, and
  // the session is not lost for it.
  std::string finish();
  int frames_written() const;
  std::string renderer() const;  // the backend and GL renderer it got

 private:
  void run();

  std::string dir_, backend_;
  int width_, height_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  struct Job {
    render::Scene scene;
    render::Camera camera;
    int number;
  };
  std::deque<Job> queue_;
  bool closing_ = false, started_ = false;
  int written_ = 0;
  std::string error_, renderer_;
  std::thread thread_;
};

// `dir`/frames/frame_%06d.png -> `dir`/`video_name` with ffmpeg (run
// directly, no shell), when it is on the PATH. Returns the video's name, or
// "" (no ffmpeg, or it failed: the frames remain).
std::string encode_video(const std::string& dir, double fps, const std::string& video_name = "session.mp4");

}  // namespace skidsim::visual
