#include "apps/frame_recorder.h"

#include <cstdio>
#include <stdexcept>

#include "io/png_image.h"
#include "render/renderer.h"

namespace skidsim::apps {

constexpr std::size_t kMaxQueued = 3;

FrameRecorder::FrameRecorder(std::string dir, int width, int height, std::string backend)
    : dir_(std::move(dir)), backend_(std::move(backend)), width_(width), height_(height) {
  thread_ = std::thread([this] { run(); });
}

FrameRecorder::~FrameRecorder() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closing_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void FrameRecorder::submit(render::Scene scene, const render::Camera& camera) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return queue_.size() < kMaxQueued || !error_.empty(); });
  if (!error_.empty()) return;  // reported by finish()
  queue_.emplace_back(std::move(scene), camera);
  changed_.notify_all();
}

void FrameRecorder::finish() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    closing_ = true;
    changed_.notify_all();
  }
  if (thread_.joinable()) thread_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  if (!error_.empty()) throw std::runtime_error("recording frames: " + error_);
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
    }
    io::RgbImage image;
    image.width = width_;
    image.height = height_;
    for (;;) {
      std::pair<render::Scene, render::Camera> job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        changed_.wait(lock, [this] { return !queue_.empty() || closing_; });
        if (queue_.empty()) return;
        job = std::move(queue_.front());
        queue_.pop_front();
      }
      changed_.notify_all();
      image.rgb = render::render_rgb(*context, renderer, job.first, job.second);
      char name[32];
      std::snprintf(name, sizeof name, "/frame_%06d.png", written_);
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

}  // namespace skidsim::apps
