#include "apps/esdslam/stop_signals.h"

#include <unistd.h>

#include <csignal>

namespace esdslam::cli {
namespace {

volatile std::sig_atomic_t g_stop_signal = 0;

// Async-signal-safe: a flag, write(2) and _exit only.
void OnStopSignal(int signal_number) {
  if (g_stop_signal != 0) ::_exit(128 + signal_number);
  g_stop_signal = signal_number;
  static const char kMessage[] = "\nesdslam: stopping after the current frame; signal again to quit at once\n";
  const ssize_t ignored = ::write(STDERR_FILENO, kMessage, sizeof(kMessage) - 1);
  (void)ignored;
}

}  // namespace

void InstallStopSignals() {
  static bool installed = false;
  if (installed) return;
  installed = true;
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // reads and writes in progress go on
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int StopSignal() { return static_cast<int>(g_stop_signal); }

}  // namespace esdslam::cli
