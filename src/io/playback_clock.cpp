#include "io/playback_clock.h"

namespace esdslam {

SteadyPlaybackClock::SteadyPlaybackClock() : origin_(std::chrono::steady_clock::now()) {}

double SteadyPlaybackClock::NowS() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - origin_).count();
}

bool SteadyPlaybackClock::SleepUntil(double t_s) {
  const auto deadline = origin_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                      std::chrono::duration<double>(t_s));
  std::unique_lock<std::mutex> lock(mutex_);
  // wait_until returns the predicate: true = interrupted (early or at the deadline).
  return !wake_.wait_until(lock, deadline, [&] { return interrupted_; });
}

void SteadyPlaybackClock::Interrupt() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    interrupted_ = true;
  }
  wake_.notify_all();
}

double ManualPlaybackClock::NowS() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return now_s_;
}

bool ManualPlaybackClock::SleepUntil(double t_s) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (interrupted_) return false;
  if (t_s <= now_s_) return true;
  const auto entry = sleeping_until_s_.insert(t_s);
  changed_.notify_all();
  changed_.wait(lock, [&] { return interrupted_ || now_s_ >= t_s; });
  sleeping_until_s_.erase(entry);
  changed_.notify_all();
  return !interrupted_;
}

void ManualPlaybackClock::Interrupt() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    interrupted_ = true;
  }
  changed_.notify_all();
}

void ManualPlaybackClock::AdvanceTo(double t_s) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (t_s <= now_s_) return;
    now_s_ = t_s;
  }
  changed_.notify_all();
}

bool ManualPlaybackClock::WaitForSleeper() {
  std::unique_lock<std::mutex> lock(mutex_);
  // A sleeper not due yet: the latest wake-up time is after now.
  changed_.wait(lock, [&] { return interrupted_ || (!sleeping_until_s_.empty() && *sleeping_until_s_.rbegin() > now_s_); });
  return !interrupted_;
}

}  // namespace esdslam
