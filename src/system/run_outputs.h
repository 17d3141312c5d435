#pragma once
// The files and the summary of `esdslam run` (README, CLI reference):
//   OUT/trajectory.txt, keyframes.txt   TUM format, world_from_cam, at the final poses
//   OUT/timing.csv                      one row per frame (system/frame_columns.h)
//   OUT/settings_used.yaml              the effective settings (RunConfig::settings)
//   debug pictures                      one PNG per frame (--debug-frames DIR)
// and the end-of-run summary (per-stage mean/median, frames tracked, fps, map, loops).

#include <cstddef>
#include <string>

#include "system/frame_log.h"
#include "system/frame_report.h"
#include "system/pipeline.h"

namespace esdslam {

// DIR/<timestamp>.png (dynamic/debug_picture.h). Throws Error when it cannot be written.
void WriteDebugFrame(const std::string& dir, const FrameReport& report);

// Finishes the pipeline (stops the threads, writes the dense map if any), then writes the four
// result files into out_dir, also when finishing failed; rethrows that failure afterwards.
void WriteRunResults(Pipeline& pipeline, const FrameLog& log, const std::string& out_dir);

// total_frames: frames the source held; elapsed_ms: wall time of the frame loop.
std::string FormatRunSummary(const FrameLog& log, std::size_t total_frames, const SlamSystem& system,
                             double elapsed_ms);

}  // namespace esdslam
