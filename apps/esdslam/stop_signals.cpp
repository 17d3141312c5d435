#include "apps/esdslam/stop_signals.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>

namespace esdslam::cli {
namespace {

volatile std::sig_atomic_t g_stop_signal = 0;
// Self-pipe: the handler writes one byte on the first signal, WaitForStopSignal blocks reading
// it (whichever thread the signal was delivered to). -1: not made.
int g_wake_pipe[2] = {-1, -1};

// Async-signal-safe: a flag, write(2) and _exit only.
void OnStopSignal(int signal_number) {
  if (g_stop_signal != 0) ::_exit(128 + signal_number);
  g_stop_signal = signal_number;
  if (g_wake_pipe[1] >= 0) {
    const ssize_t woke = ::write(g_wake_pipe[1], "x", 1);
    (void)woke;
  }
  static const char kMessage[] = "\nesdslam: stopping after the current frame; signal again to quit at once\n";
  const ssize_t ignored = ::write(STDERR_FILENO, kMessage, sizeof(kMessage) - 1);
  (void)ignored;
}

}  // namespace

void InstallStopSignals() {
  static bool installed = false;
  if (installed) return;
  installed = true;
  if (::pipe2(g_wake_pipe, O_CLOEXEC) != 0) g_wake_pipe[0] = g_wake_pipe[1] = -1;
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // reads and writes in progress go on
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int StopSignal() { return static_cast<int>(g_stop_signal); }

int WaitForStopSignal() {
  InstallStopSignals();
  char byte = 0;
  while (g_stop_signal == 0 && g_wake_pipe[0] >= 0) {
    const ssize_t got = ::read(g_wake_pipe[0], &byte, 1);
    if (got < 0 && errno != EINTR) break;
  }
  return StopSignal();
}

}  // namespace esdslam::cli
