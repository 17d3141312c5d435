#pragma once
// The files and the summary of `esdslam run` (README, CLI reference):
//   OUT/trajectory.txt, keyframes.txt   TUM format, world_from_cam: while the run goes a line per
//                                       frame / keyframe as tracked, at the end the final poses
//   OUT/timing.csv                      one row per frame (system/frame_columns.h), as the run goes
//                                       (system/live_outputs.h)
//   OUT/settings_used.yaml              the effective settings (RunConfig::settings)
//   debug pictures                      one PNG per frame (--debug-frames DIR)
// and the end-of-run summary (per-stage mean/median, frames tracked, fps, map, loops).

#include <cstddef>
#include <string>

#include "system/frame_log.h"
#include "system/frame_report.h"
#include "system/live_outputs.h"
#include "system/pipeline.h"

namespace esdslam {

// DIR/<timestamp>.png (dynamic/debug_picture.h). Throws Error when it cannot be written.
void WriteDebugFrame(const std::string& dir, const FrameReport& report);

// Writes every output of a run that ended (at the last frame, stopped by a signal, or failed),
// trajectory first, so that a thread that never returns cannot keep it from the disk:
//   1. trajectory.txt and keyframes.txt at the poses now (local mapping may still be running);
//   2. Pipeline::StopSlam (segmentation, local mapping, loop closing), then both files again at
//      the final poses;
//   3. settings_used.yaml; the map file when RunConfig::run.save_map is set;
//   4. Pipeline::Finish: the dense thread is stopped and the dense outputs written.
// timing.csv is complete already (LiveOutputs). Every step is tried even when an earlier one
// failed; the first failure is rethrown afterwards as an Error.
void WriteRunResults(Pipeline& pipeline, LiveOutputs& live, const std::string& out_dir);

// total_frames: frames the source held; elapsed_ms: wall time of the frame loop;
// frames_unreadable: frames skipped because an image could not be read.
std::string FormatRunSummary(const FrameLog& log, std::size_t total_frames, const SlamSystem& system,
                             double elapsed_ms, std::size_t frames_unreadable = 0);

}  // namespace esdslam
