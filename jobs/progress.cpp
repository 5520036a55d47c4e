#include "jobs/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace skidsim::jobs {

Progress::Progress(std::string label, double total_sim_s)
    : label_(std::move(label)),
      total_sim_s_(total_sim_s),
      enabled_(::isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

double Progress::wall_seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::update(double sim_s, const std::string& extra) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  const double wall = wall_seconds();
  const double fraction = total_sim_s_ > 0 ? std::clamp(sim_s / total_sim_s_, 0.0, 1.0) : 1.0;
  const double rtf = wall > 0 ? sim_s / wall : 0.0;
  const double eta = rtf > 0 ? (total_sim_s_ - sim_s) / rtf : 0.0;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(fraction * kWidth);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(kWidth, '-');
  std::fprintf(stderr, "\r%s [%s] %6.2f/%.2f s sim  x%.2f real time  ETA %4.0f s %s\033[K", label_.c_str(),
               bar.c_str(), sim_s, total_sim_s_, rtf, eta, extra.c_str());
  std::fflush(stderr);
}

void Progress::finish() {
  if (!enabled_) return;
  last_draw_ = {};
  std::fprintf(stderr, "\n");
}

}  // namespace skidsim::jobs
