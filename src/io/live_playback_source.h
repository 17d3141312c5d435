#pragma once
// Sensor-clock playback: a recorded sequence delivered the way a camera delivers it. A wrapped
// FrameSource (e.g. a TumFolderSource) is read on a playback thread; each frame is held back
// until its time comes on a PlaybackClock (frame time - first frame time after the first Next()
// call), then it "arrives" and replaces the one frame slot. Next() returns the frame in the slot
// (waiting for one to arrive when it is empty). A frame still in the slot when a newer one
// arrives is dropped, as a camera driver drops it when nobody has read it: a consumer busy for
// longer than the frame interval sees only the newest frame, and every dropped frame is counted
// in the next returned frame's RgbdFrame::dropped_before.
//
// Invariants: frames are returned in time order; the last frame of the wrapped source is never
// dropped (nothing arrives after it); returned + dropped = frames the wrapped source gave.
// Reading the wrapped source happens before a frame's time (the thread reads the next frame as
// soon as the previous one arrived), so a frame arrives late only when reading it took longer
// than the interval before it.
//
// Threads: the playback thread is a Worker (common/worker.h) running one playback job; it and
// the consumer share the slot under mutex_ (a leaf; the clock's own mutex is never taken while
// it is held). Next() and the destructor belong to one consumer thread. The destructor
// interrupts the clock and joins. An error of the wrapped source ends the playback: the frames
// that arrived before it are still returned, then Next() throws it.

#include <condition_variable>
#include <cstddef>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>

#include "common/worker.h"
#include "io/frame_source.h"
#include "io/playback_clock.h"

namespace esdslam {

class LivePlaybackSource final : public FrameSource {
 public:
  // clock: shared so a test can drive a ManualPlaybackClock; the source interrupts it when
  // destroyed. Throws Error when source or clock is null.
  LivePlaybackSource(std::unique_ptr<FrameSource> source, std::shared_ptr<PlaybackClock> clock);
  ~LivePlaybackSource() override;
  LivePlaybackSource(const LivePlaybackSource&) = delete;
  LivePlaybackSource& operator=(const LivePlaybackSource&) = delete;

  // The first call starts the playback (the clock's now is the first frame's time).
  std::optional<RgbdFrame> Next() override;
  // Unknown in advance (drops depend on the consumer): nullopt, like a camera.
  std::optional<std::size_t> frame_count() const override { return std::nullopt; }

  // Frames dropped so far (the sum of dropped_before over the returned frames, plus the ones
  // dropped since the last return).
  std::size_t frames_dropped() const;

 private:
  struct PlayJob {};
  void Play();
  void Arrive(RgbdFrame frame);

  std::unique_ptr<FrameSource> source_;  // read on the playback thread only
  const std::shared_ptr<PlaybackClock> clock_;
  mutable std::mutex mutex_;
  std::condition_variable arrived_;      // a frame arrived or the playback ended
  std::optional<RgbdFrame> slot_;        // the newest frame not returned yet
  int dropped_since_return_ = 0;         // frames dropped after the last returned frame
  std::size_t dropped_total_ = 0;
  bool ended_ = false;                   // the playback job returned (end of source, error, stop)
  std::exception_ptr error_;             // what the wrapped source threw, if it did
  bool started_ = false;                 // consumer only
  Worker<PlayJob> player_;               // last: closed (joined) first
};

}  // namespace esdslam
