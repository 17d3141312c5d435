#include "system/run_loop.h"

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
  double load_ms = 0;  // loading done during the current frame's step
  std::optional<RgbdFrame> current = TakeAhead(source, pipeline, &load_ms);
  while (current) {
    std::optional<RgbdFrame> next = TakeAhead(source, pipeline, &load_ms);
    FrameReport report = pipeline.Track(*current);
    report.load_ms = load_ms;
    report.dropped_before = current->dropped_before;
    load_ms = 0;
    on_frame(report);
    if (stop()) return true;
    current = std::move(next);
  }
  return false;
}

}  // namespace esdslam
