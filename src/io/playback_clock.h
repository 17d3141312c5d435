#pragma once
// The clock a sensor-clock playback (io/live_playback_source.h) runs on: seconds since an
// arbitrary origin, and a wait until a time that another thread can interrupt for good (shutdown).
//   SteadyPlaybackClock  the real one: std::chrono::steady_clock, waits with a condition
//                        variable's wait_until (woken early only by Interrupt).
//   ManualPlaybackClock  time moves only when its owner calls AdvanceTo (tests, simulations):
//                        runs repeat exactly, and WaitForSleeper tells the owner when the
//                        playback thread has done everything due by now.
// Threads: every member may be called from any thread; each clock has one mutex, a leaf (no
// other lock is taken while it is held).

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <set>

namespace esdslam {

class PlaybackClock {
 public:
  virtual ~PlaybackClock() = default;
  // Seconds since the clock's origin (monotonic).
  virtual double NowS() const = 0;
  // Blocks until NowS() >= t_s (returns true) or Interrupt() was called (returns false, also
  // when it was called before). A time already past returns at once.
  virtual bool SleepUntil(double t_s) = 0;
  // Wakes every sleeper now and every later SleepUntil at once, with false.
  virtual void Interrupt() = 0;
};

class SteadyPlaybackClock final : public PlaybackClock {
 public:
  SteadyPlaybackClock();
  double NowS() const override;
  bool SleepUntil(double t_s) override;
  void Interrupt() override;

 private:
  const std::chrono::steady_clock::time_point origin_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool interrupted_ = false;
};

class ManualPlaybackClock final : public PlaybackClock {
 public:
  double NowS() const override;
  bool SleepUntil(double t_s) override;
  void Interrupt() override;

  // Sets the time to t_s (never backwards: an earlier t_s is ignored) and wakes the sleepers due.
  void AdvanceTo(double t_s);
  // Blocks until some thread sleeps in SleepUntil for a time after NowS(), i.e. a playback
  // thread has handled everything due by now and waits for the future. Returns false when
  // the clock was interrupted.
  bool WaitForSleeper();

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;  // time advanced, a sleeper came or went, or interrupted
  double now_s_ = 0;
  std::multiset<double> sleeping_until_s_;  // one entry per thread in SleepUntil
  bool interrupted_ = false;
};

}  // namespace esdslam
