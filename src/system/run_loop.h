#pragma once
// The run loop: every frame of a FrameSource through the Pipeline, in order, on the calling
// thread. Pipeline::look_ahead() frames are taken from the source and submitted to the semantic
// stage (Pipeline::SubmitAhead) before the current one is tracked: in every-frame mode the
// network works on frame i+1 while frame i is extracted and tracked; with predicted masks on a
// recorded sequence it labels frame i+A (Semantic.lookAhead) while frames i..i+A-1 are tracked.
//
// After each frame `on_frame` gets its report (progress, timing.csv, debug pictures, a viewer);
// it runs on the tracking thread between frames, so it must be quick or hand the report on.

#include <functional>

#include "io/frame_source.h"
#include "system/frame_report.h"
#include "system/pipeline.h"

namespace esdslam {

using FrameCallback = std::function<void(const FrameReport&)>;

// Asked after each frame's on_frame (and before the first frame): true = stop the run there.
// A signal handler's flag, a viewer's close button; it must be quick (no waiting).
using StopPredicate = std::function<bool()>;

// Returns after the source's last frame (false), or when stop_requested said so (true; the
// frames submitted ahead are not tracked). What the source, a stage or on_frame throws is passed
// on; every frame tracked before it has been given to on_frame.
bool RunFrames(FrameSource& source, Pipeline& pipeline, const FrameCallback& on_frame,
               const StopPredicate& stop_requested = nullptr);

}  // namespace esdslam
