#include "system/run_loop.h"

#include <algorithm>
#include <deque>
#include <exception>
#include <optional>
#include <utility>

#include "common/timer.h"

namespace esdslam {
namespace {

// The source's next frame, submitted ahead; *load_ms += the time taken to get it.
std::optional<RgbdFrame> TakeAhead(FrameSource& source, Pipeline& pipeline, double* load_ms) {
  Stopwatch watch;
  std::optional<RgbdFrame> frame = source.Next();
  *load_ms += watch.ElapsedMs();
  if (frame) pipeline.SubmitAhead(*frame);
  return frame;
}

}  // namespace

bool RunFrames(FrameSource& source, Pipeline& pipeline, const FrameCallback& on_frame,
               const StopPredicate& stop_requested) {
  const auto stop = [&stop_requested] { return stop_requested && stop_requested(); };
  if (stop()) return true;
  const std::size_t window = static_cast<std::size_t>(pipeline.look_ahead()) + 1;  // tracked + ahead
  // The window opens by one frame per frame tracked: at the start the network is still on frame
  // 0 (its first call is its slowest), and frames handed to the schedule while it is busy are not
  // labelled.
  std::size_t tracked = 0;
  double load_ms = 0;  // loading done during the current frame's step
  std::deque<RgbdFrame> frames;  // submitted, not tracked; oldest first
  bool source_done = false;
  std::exception_ptr source_error;  // what the source threw; passed on after the frames before it
  while (true) {
    while (!source_done && frames.size() < std::min(window, tracked + 2)) {
      try {
        std::optional<RgbdFrame> next = TakeAhead(source, pipeline, &load_ms);
        if (next) frames.push_back(std::move(*next));
        else source_done = true;
      } catch (...) {  // the frames read before it are tracked first
        source_error = std::current_exception();
        source_done = true;
      }
    }
    if (frames.empty()) {
      if (source_error) std::rethrow_exception(source_error);
      return false;
    }
    FrameReport report = pipeline.Track(frames.front());
    report.load_ms = load_ms;
    report.dropped_before = frames.front().dropped_before;
    load_ms = 0;
    frames.pop_front();
    ++tracked;
    on_frame(report);
    if (stop()) return true;
  }
}

}  // namespace esdslam
