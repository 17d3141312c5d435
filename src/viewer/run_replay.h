#pragma once
// `esdslam view OUT`: a finished run's output folder in the live viewer's page. The files are
// the ones `esdslam run` writes (report/run_files.h): trajectory.txt, keyframes.txt and
// timing.csv, plus dense.ply when the run had --dense and the newest debug picture when the run
// wrote them (--debug-frames DIR). The events are the live viewer's ("frame", "map", "status"),
// so the page is the same; the frame panel shows the last frame's row of timing.csv. A
// "timeline" event adds every frame's row (thinned) and the poses with their times: the page's
// slider steps through the run with them.

#include <string>

#include "report/run_files.h"
#include "viewer/event_hub.h"
#include "viewer/viewer_options.h"

namespace esdslam {

struct ReplayInputs {
  std::string out_dir;         // the run's output folder
  std::string debug_dir;       // its --debug-frames folder; empty = none
};

// Reads the run's files (throws InputError as ReadRunFiles; a bad dense.ply: Error) and publishes
// its events to `hub`. Returns the files it read.
RunFiles PublishRun(const ReplayInputs& inputs, const ViewerOptions& options, EventHub* hub);
// The timeline event: per frame (at most max_trajectory, evenly thinned) its row number,
// timestamp, state and every column in ms; the trajectory's positions (thinned the same way,
// the last one kept) with their timestamps.
std::string EncodeReplayTimeline(const RunFiles& files, const ViewerOptions& options);
// The frame event of a finished run: counts and the last row of timing.csv (picture: the newest
// debug picture, if any, scaled as the live picture).
std::string EncodeReplayFrame(const RunFiles& files, const ViewerOptions& options);

}  // namespace esdslam
