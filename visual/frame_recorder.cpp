#include "visual/frame_recorder.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>

#include <cstdio>
#include <stdexcept>
#include <vector>

#include "io/png_image.h"
#include "render/renderer.h"

namespace skidsim::visual {

constexpr std::size_t kMaxQueued = 3;

FrameRecorder::FrameRecorder(std::string dir, int width, int height, std::string backend)
    : dir_(std::move(dir)), backend_(std::move(backend)), width_(width), height_(height) {
  thread_ = std::thread([this] { run(); });
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return started_ || !error_.empty(); });
  if (!started_) {
    const std::string why = error_;
    lock.unlock();
    thread_.join();
    throw std::runtime_error("recording frames: " + why);
  }
}

FrameRecorder::~FrameRecorder() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closing_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void FrameRecorder::submit(render::Scene scene, const render::Camera& camera, int number) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return queue_.size() < kMaxQueued || !error_.empty(); });
  if (!error_.empty()) return;  // reported by finish()
  queue_.push_back(Job{std::move(scene), camera, number});
  changed_.notify_all();
}

std::string FrameRecorder::finish() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    closing_ = true;
    changed_.notify_all();
  }
  if (thread_.joinable()) thread_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  return error_;
}

int FrameRecorder::frames_written() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return written_;
}

std::string FrameRecorder::renderer() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return renderer_;
}

void FrameRecorder::run() {
  try {
    auto context = render::make_offscreen_context(backend_, width_, height_);
    render::Renderer renderer(*context);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      renderer_ = std::string(render::backend_name(context->backend())) + " (" + context->renderer() + ")";
      started_ = true;
    }
    changed_.notify_all();
    io::RgbImage image;
    image.width = width_;
    image.height = height_;
    for (;;) {
      Job job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        changed_.wait(lock, [this] { return !queue_.empty() || closing_; });
        if (queue_.empty()) return;
        job = std::move(queue_.front());
        queue_.pop_front();
      }
      changed_.notify_all();
      image.rgb = render::render_rgb(*context, renderer, job.scene, job.camera);
      char name[32];
      std::snprintf(name, sizeof name, "/frame_%06d.png", job.number >= 0 ? job.number : written_);
      io::write_png_rgb8(dir_ + name, image, 1);
      std::lock_guard<std::mutex> lock(mutex_);
      ++written_;
    }
  } catch (const std::exception& e) {
    std::lock_guard<std::mutex> lock(mutex_);
    error_ = e.what();
    queue_.clear();
    changed_.notify_all();
  }
}

std::string encode_video(const std::string& dir, double fps, const std::string& video_name) {
  char rate[32];
  std::snprintf(rate, sizeof rate, "%g", fps);
  const std::string input = dir + "/frames/frame_%06d.png", output = dir + "/" + video_name;
  std::vector<std::string> args = {"ffmpeg", "-nostdin", "-loglevel", "error", "-y", "-framerate", rate, "-i", input,
                                   "-pix_fmt", "yuv420p", "-vf", "scale=trunc(iw/2)*2:trunc(ih/2)*2", output};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, "ffmpeg", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return "";  // no ffmpeg on the PATH
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return "";
  return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? video_name : "";
}

}  // namespace skidsim::visual
