#pragma once
// The one configuration of a run. The settings file and the run's flags are resolved ONCE, at the
// edge (`esdslam run`, a test, later the library API), by ResolveRunConfig; every constructor
// then takes its part as it is and changes nothing:
//   settings  every settings key (RunSettings), the flags that override keys applied; this is
//             what settings_used.yaml records
//   slam      the SLAM system (SlamSystem); slam.loop and slam.geometry are settings.loop and
//             settings.geometry (Check() rejects a configuration where they differ)
//   pipeline  which dynamic stages run and the dense map (Pipeline)
//   run       the run loop's input and outputs (paths, frame limit)
// ResolveRunConfig is the only place where a flag or one setting decides another value:
//   --no-loop, --no-relocalization  Loop.closing: 0, Loop.relocalization: 0
//   --realtime                      Semantic.realtime: 1 (newest-wins segmentation hand-off)
//   --segment-every K               Semantic.segmentEvery: K
//   --realtime, --segment-every     the model and its threads when not given (ApplyLabelSchedule)
//   --seed                          the relocalization PnP RANSAC and loop verification RANSAC seeds
//   Camera.fps                      slam.tracker.max_frames_between_keyframes (ORB-SLAM2: fps)
//   --mode                          slam.geometry_check
//   --single-thread                 slam.single_thread; pipeline.threaded_dense = false; predicted
//                                   masks wait for due labels (semantic_front_end.h)
//   --dense with run.out_dir        pipeline.dense_mask_dir = OUT/masks

#include <cstdint>
#include <string>

#include "system/run_settings.h"
#include "system/slam_system.h"

namespace esdslam {

// How moving objects are handled (every ablation from one binary):
//   none      plain ORB-SLAM2-style RGB-D SLAM
//   semantic  segmentation (dynamic classes) + depth region growing -> dynamic mask per frame
//   geometry  multi-view geometry check in tracking only (no network)
//   full      both: the semantic mask first, then the geometry check on potentially dynamic
//             class regions and unlabelled regions (labelled static classes and the semantic
//             mask are exempt: Frame::geometry_exempt)
enum class DynamicMode { kNone, kSemantic, kGeometry, kFull };
const char* ToString(DynamicMode mode);
DynamicMode ParseDynamicMode(const std::string& text);  // throws Error naming the choices

bool UsesSegmentation(DynamicMode mode);
bool UsesGeometryCheck(DynamicMode mode);

// What the pipeline (system/pipeline.h) runs besides tracking.
struct PipelineOptions {
  DynamicMode mode = DynamicMode::kFull;
  bool dense = false;          // dense map of the keyframes, written by Pipeline::Finish
  std::string dense_mask_dir;  // with dense: each keyframe's dynamic mask as <timestamp>.png; empty = not saved
  bool threaded_dense = true;  // dense mapping on its own thread (else on the tracking thread)
  // Frames the run loop submits ahead of the one it tracks (system/run_loop.h), [1, 30]: 1, or
  // Semantic.lookAhead with predicted masks on a recorded sequence (not --realtime, not --live).
  int look_ahead_frames = 1;
  void Check() const;          // throws Error
};

// The run loop's input and outputs (apps/esdslam/cmd_run.cpp).
struct RunOptions {
  std::string sequence_dir;      // TUM-layout input folder
  std::string associations;      // ORB-SLAM2 association file (io/tum_sequence.h); empty = lists or detected
  std::string out_dir;           // results folder (created)
  int max_frames = 0;            // process at most this many frames; 0 = all
  std::string debug_frames_dir;  // one debug PNG per frame (dynamic/debug_picture.h); empty = off
  std::string save_map;          // the final map file; empty = not written
  // Sensor-clock playback: frames arrive at their timestamps and the ones arriving while the
  // system is busy are dropped (io/live_playback_source.h).
  bool live = false;
  void Check() const;            // throws Error
};

// The flags of one run, as a user gives them (`esdslam run` fills it from its command line).
struct RunFlags {
  RunOptions run;  // taken as it is
  DynamicMode mode = DynamicMode::kFull;
  bool realtime = false;  // newest-wins segmentation (as Semantic.realtime: 1)
  int segment_every = 0;  // > 0: as Semantic.segmentEvery (1 = every frame's labels); 0 = the settings'
  bool single_thread = false;
  // Seeds the run's random choices: the RANSACs of relocalization (PnP) and of loop
  // verification (rigid), via settings.loop. 1 is the options' default seed.
  std::uint32_t seed = 1;
  bool no_relocalization = false;
  bool no_loop = false;
  bool dense = false;
  std::string load_map;       // map file to start from; empty = a new map
  bool localization = false;  // with load_map: track in it without adding keyframes
  // Spend the extractor's budget on the static area (with segmentation). Off: keypoints are
  // extracted everywhere and the ones on the mask are flagged (tests measure the flags).
  bool mask_extraction = true;
};

struct RunConfig {
  RunSettings settings;
  SlamOptions slam;
  PipelineOptions pipeline;
  RunOptions run;
  void Check() const;  // every part's Check(), and the parts agree (see the header comment)
};

// The keyframe interval ORB-SLAM2 derives from the frame rate: round(fps), at least 1.
int MaxFramesBetweenKeyframes(double fps);

// Applies the flags to the file's settings and derives the rest (the list above); checks the
// result. Throws Error on a bad value or combination.
RunConfig ResolveRunConfig(RunSettings settings, const RunFlags& flags);

// Logs one info line (mode, threading, seed, where the effective settings will be: the run's
// outputs write OUT/settings_used.yaml, system/run_outputs.h); the details and one line per key
// go to the debug level (`esdslam -v`).
void LogRunConfig(const RunConfig& config);

}  // namespace esdslam
