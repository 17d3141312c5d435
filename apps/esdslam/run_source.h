#pragma once
// Where `esdslam run` takes its frames from (resolved here, at the edge, before the run's
// configuration, because a camera decides the camera model):
//   --sequence DIR      the folder read frame by frame (TumFolderSource, decoded ahead on a loader
//                       thread: PrefetchingFrameSource), at most --max-frames
//   --sequence --live   the same frames played on the steady clock (LivePlaybackSource)
//   --camera [URI]      an OpenNI2 device or .oni recording (device/openni_source.h); its camera
//                       model replaces the settings' (--camera-model device) or is checked
//                       against them (settings); --live plays a recording on its own clock

#include <cstddef>
#include <memory>
#include <string>

#include "io/frame_source.h"
#include "io/settings.h"
#include "system/run_config.h"

namespace esdslam::cli {

struct CameraArgs {
  bool use = false;                  // --camera given
  std::string uri;                   // "" = the first device attached
  std::string model_from = "device";  // device | settings
  std::string registration = "device";  // device | off
};

struct RunSource {
  std::unique_ptr<FrameSource> source;
  std::size_t total_frames = 0;  // frames in the input (the summary's "of", dropped ones included); 0 = unknown
  const TumFolderSource* folder = nullptr;  // the folder read, inside `source` (null for a camera)
  std::string groundtruth_path;             // the folder's groundtruth.txt when it has one, else ""
  // Frames of the folder skipped as unreadable so far.
  std::size_t frames_skipped() const { return folder != nullptr ? folder->frames_skipped() : 0; }
};

// settings: the file's core settings; with a camera, changed to its camera model. A folder's
// images are checked against settings->camera's size; max_consecutive_bad_frames unreadable frames
// in a row end the run (Sequence.maxConsecutiveBadFrames). Throws Error (InputError naming the
// file) when the input cannot be opened.
RunSource OpenRunSource(const RunOptions& run, const CameraArgs& camera, int max_consecutive_bad_frames,
                        Settings* settings);

}  // namespace esdslam::cli
