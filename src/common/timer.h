#pragma once
// Wall-clock stopwatch in milliseconds (steady clock), and a CPU-time stopwatch of the calling
// thread (time the thread ran: on a shared machine, unlike wall time, not inflated by waiting for
// a core).

#include <chrono>
#include <ctime>

namespace esdslam {

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  void Restart() { start_ = std::chrono::steady_clock::now(); }
  double ElapsedMs() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

class ThreadCpuStopwatch {
 public:
  ThreadCpuStopwatch() { Restart(); }
  void Restart() { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &start_); }
  double ElapsedMs() const {
    timespec now;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return 1e3 * static_cast<double>(now.tv_sec - start_.tv_sec) + 1e-6 * static_cast<double>(now.tv_nsec - start_.tv_nsec);
  }

 private:
  timespec start_;
};

}  // namespace esdslam
