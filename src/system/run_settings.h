#pragma once
// All settings of one run in ONE key table: the core (ORB-SLAM2 keys), Semantic.*, Dynamic.*
// (region growing and multi-view geometry check) and Dense.*. Keys bound by no stage are warned
// about once; SaveRunSettings writes every bound key (settings_used.yaml).
//
// Semantic.* keys (all optional):
//   Semantic.segmenter: onnx | folder | provided (each frame's labels from the library caller)
//   Semantic.model: .onnx path (resolved); not given: espnetv2 256x192 with Semantic.segmentEvery
//     > 1 or realtime, 384x288 with every-frame labels (ApplyLabelSchedule)
//   Semantic.inputWidth/inputHeight: 0 = from a model name ending in _<W>x<H>.onnx
//   Semantic.threads, Semantic.upsampleScores (1/0)
//   Semantic.dynamicClasses, Semantic.potentiallyDynamicClasses: a YAML list or "a,b" text
//   Semantic.maskFolder, Semantic.maskTolerance (s), Semantic.allowMissingMasks (folder segmenter)
//   Semantic.realtime: 1 = newest-wins: the network takes the newest frame whenever it is free
//   Semantic.segmentEvery: K, 1 = every frame (tracking waits for its labels); K > 1 (default 4)
//     = every K-th frame, predicted masks between (dynamic/semantic_front_end.h)
//   Semantic.labelDelay: labels used from this many frames after their frame on (default 0)
//   Semantic.lookAhead: frames a recorded sequence reaches the label schedule before it is
//     tracked (default 8; SemanticSettings::look_ahead_frames)
// Dynamic.* keys: Dynamic.grow.* (RegionGrowingOptions) and Dynamic.check.* (GeometryFilterOptions:
// the check itself, its own region growing under Dynamic.check.grow.*, reference keyframes and
// their minimum age Dynamic.check.minReferenceAge (s),
// keyframe depth kept, culling), see BindDynamicSettings in run_settings.cpp.

#include <string>
#include <vector>

#include "dense/dense_options.h"
#include "dynamic/mask_refine.h"
#include "dynamic/region_growing.h"
#include "io/settings.h"
#include "semantic/semantic_settings.h"
#include "system/loop_settings.h"
#include "dynamic/geometry_filter.h"

namespace esdslam {

class SettingsTable;

struct RunSettings {
  Settings core;
  SemanticSettings semantic;
  RegionGrowingOptions region_growing;
  GeometryFilterOptions geometry;  // the multi-view geometry check in tracking (modes geometry, full)
  DenseOptions dense;
  MaskRefineOptions mask_refine{10, 2};  // Dynamic.maskDilation (px), Dynamic.refineScale: the class mask -> dynamic mask
  // Sequence.maxConsecutiveBadFrames: unreadable frames are skipped with a warning, this many in
  // a row stop the run with an error (io/frame_source.h). 1..100000.
  int max_consecutive_bad_frames = 10;
  LoopOptions loop;  // Loop.* keys (system/loop_settings.h); vocabulary path resolved on load
  // Tracking.motionPriorBelowMatches, Tracking.maxCoastedFrames (tracking/tracker.h TrackerOptions:
  // the motion prior when local-map matches are fewer, 0 = off; blind frames given the motion model's pose).
  int motion_prior_below_matches = 0;
  int max_coasted_frames = 5;
  // Tracking.depthPrior (TrackerOptions::depth_prior): 1 = the pose optimisation gets the static
  // depth's alignment to the previous frame as a prior (tracking/depth_alignment.h), 0 = off.
  int depth_prior = 1;
  double depth_prior_weight = 0.01;  // Tracking.depthPriorWeight (TrackerOptions::depth_prior_weight)

  void Check() const;  // throws Error
};

// The Semantic.* keys as written in the file; converted to SemanticSettings after loading
// (model path resolution, input size from the model name, class lists).
struct SemanticKeys {
  std::string segmenter = "onnx";
  std::string model;  // empty: chosen by the schedule (SemanticSettings::model_auto)
  int input_width = 0, input_height = 0;  // 0 = from the model name (else 384x288)
  int threads = 0;
  bool upsample_scores = true;
  std::string dynamic_classes = "person";
  std::string potentially_dynamic_classes = "bicycle,bird,bottle,car,cat,chair,cow,dog,horse,motorbike,sheep";
  std::string mask_folder;
  double mask_tolerance_s = 0.02;
  bool allow_missing_masks = false;
  bool realtime = false;
  int segment_every = 4;
  int label_delay = 0;
  int look_ahead = 8;

  // The keys of `settings` (inverse of ToSemanticSettings, for saving).
  static SemanticKeys From(const SemanticSettings& settings);
  // settings_dir: folder of the settings file (for relative model paths). Throws Error.
  SemanticSettings ToSemanticSettings(const std::string& settings_dir) const;
};

void BindSemanticSettings(SemanticKeys& keys, SettingsTable& table);
void BindDynamicSettings(RunSettings& run, SettingsTable& table);

// Loads, converts and checks. Unknown keys are warned about once (and appended to `warnings`).
// Throws InputError for file/syntax/type errors and failed checks (a value out of its range at
// the line of its key).
RunSettings LoadRunSettings(const std::string& path, std::vector<std::string>* warnings = nullptr);
// The same from the file's text (the library API's SystemConfig::settings_text); `name` is used
// in messages, relative model and vocabulary paths are looked for in `base_dir` first.
RunSettings LoadRunSettingsFromText(const std::string& text, const std::string& name, const std::string& base_dir = "",
                                    std::vector<std::string>* warnings = nullptr);

// The Semantic.* part of a settings file, through the same table (`esdslam segment`): no key is
// required, only the semantic part is checked. Defaults (default model resolved) when `path`
// is empty. Throws InputError.
SemanticSettings LoadSemanticSettings(const std::string& path);

// Writes every key of every stage (loadable by LoadRunSettings; core keys by ORB-SLAM2).
void SaveRunSettings(const RunSettings& settings, const std::string& path);
// The same as 'key: value' lines (for logging the effective settings).
std::string RunSettingsYaml(const RunSettings& settings);

}  // namespace esdslam
