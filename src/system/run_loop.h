#pragma once
// The run loop: every frame of a FrameSource through the Pipeline, in order, on the calling
// thread. The next frame is taken from the source and submitted for segmentation before the
// current one is tracked (Pipeline::SubmitAhead), so in every-frame mode the network works on
// frame i+1 while frame i is extracted and tracked.
//
// After each frame `on_frame` gets its report (progress, timing.csv, debug pictures, a viewer);
// it runs on the tracking thread between frames, so it must be quick or hand the report on.

#include <functional>

#include "io/frame_source.h"
#include "system/frame_report.h"
#include "system/pipeline.h"

namespace esdslam {

using FrameCallback = std::function<void(const FrameReport&)>;

// Returns after the source's last frame. What the source, a stage or on_frame throws is passed
// on; every frame tracked before it has been given to on_frame.
void RunFrames(FrameSource& source, Pipeline& pipeline, const FrameCallback& on_frame);

}  // namespace esdslam
