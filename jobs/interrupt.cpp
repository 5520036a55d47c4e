#include "jobs/interrupt.h"

#include <csignal>
#include <cstring>
#include <iterator>
#include <signal.h>

namespace skidsim::jobs {
namespace {

volatile std::sig_atomic_t g_signal = 0;
extern "C" void on_signal(int signal) { g_signal = signal; }

constexpr int kEndingSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
struct sigaction g_previous[std::size(kEndingSignals)];

}  // namespace

InterruptScope::InterruptScope() {
  g_signal = 0;
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  for (std::size_t k = 0; k < std::size(kEndingSignals); ++k) sigaction(kEndingSignals[k], &action, &g_previous[k]);
}

InterruptScope::~InterruptScope() {
  for (std::size_t k = 0; k < std::size(kEndingSignals); ++k) sigaction(kEndingSignals[k], &g_previous[k], nullptr);
}

int interrupting_signal() { return g_signal; }

void stop_if_interrupted(const std::string& job) {
  if (const int s = g_signal)
    throw Interrupted(job + " interrupted by " + std::string(sigabbrev_np(s) ? "SIG" : "signal ") +
                          (sigabbrev_np(s) ? sigabbrev_np(s) : std::to_string(s)) +
                          ": nothing written, the previous result (if any) is kept",
                      s);
}

}  // namespace skidsim::jobs
