#include "io/live_playback_source.h"

#include <exception>
#include <utility>

#include "common/error.h"

namespace esdslam {

LivePlaybackSource::LivePlaybackSource(std::unique_ptr<FrameSource> source, std::shared_ptr<PlaybackClock> clock)
    : source_(std::move(source)), clock_(std::move(clock)),
      player_("live playback", WorkerMode::kThread, 1, [this](PlayJob&) { Play(); }) {
  if (!source_ || !clock_) throw Error("live playback: needs a frame source and a clock");
}

LivePlaybackSource::~LivePlaybackSource() {
  clock_->Interrupt();
  try {
    player_.Close();
  } catch (const std::exception&) {  // none expected: Play keeps its errors for Next()
  }
}

void LivePlaybackSource::Play() {
  std::exception_ptr error;
  try {
    std::optional<RgbdFrame> frame = source_->Next();
    // Clock time = start_s + (frame time - first_s): the first frame arrives now.
    const double first_s = frame ? frame->timestamp : 0.0;
    const double start_s = clock_->NowS();
    while (frame && clock_->SleepUntil(start_s + (frame->timestamp - first_s))) {  // false: stopped
      Arrive(std::move(*frame));
      frame = source_->Next();  // read ahead of its time
    }
  } catch (...) {
    error = std::current_exception();  // the consumer gets it from Next(), type and all
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ended_ = true;
    error_ = error;
  }
  arrived_.notify_one();
}

void LivePlaybackSource::Arrive(RgbdFrame frame) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (slot_) {
      ++dropped_since_return_;
      ++dropped_total_;
    }
    slot_ = std::move(frame);
  }
  arrived_.notify_one();
}

std::optional<RgbdFrame> LivePlaybackSource::Next() {
  if (!started_) {
    started_ = true;
    player_.Start();
    player_.Push(PlayJob{});
  }
  std::unique_lock<std::mutex> lock(mutex_);
  arrived_.wait(lock, [&] { return slot_.has_value() || ended_; });
  if (slot_) {
    RgbdFrame frame = std::move(*slot_);
    slot_.reset();
    frame.dropped_before = dropped_since_return_;
    dropped_since_return_ = 0;
    return frame;
  }
  // The wrapped source's error comes after every frame that arrived before it.
  if (error_) std::rethrow_exception(error_);
  return std::nullopt;
}

std::size_t LivePlaybackSource::frames_dropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_total_;
}

}  // namespace esdslam
