// Recording (EXERCISES.md, "Outputs"): frames rendered on a thread of their
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

namespace skidsim::apps {

class FrameRecorder {
 public:
  // Frames go to `dir`/frame_000000.png, ...; the context is made on the
  // recorder's thread (`backend`: auto, egl or osmesa).
  FrameRecorder(std::string dir, int width, int height, std::string backend);
  ~FrameRecorder();
  FrameRecorder(const FrameRecorder&) = delete;
  FrameRecorder& operator=(const FrameRecorder&) = delete;

  void submit(render::Scene scene, const render::Camera& camera);
  // Waits for every frame to be written; throws std::runtime_error if the
  // recorder failed (no context, a full disk), naming why.
  void finish();
  int frames_written() const;
  std::string renderer() const;  // the backend and GL renderer it got

 private:
  void run();

  std::string dir_, backend_;
  int width_, height_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::pair<render::Scene, render::Camera>> queue_;
  bool closing_ = false;
  int written_ = 0;
  std::string error_, renderer_;
  std::thread thread_;
};

}  // namespace skidsim::apps
