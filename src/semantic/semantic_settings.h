#pragma once
// The semantic part of a run's configuration. Its settings keys (Semantic.*) are read, with
// every other key, by the one settings loader, system/run_settings.h (keys documented there);
// this file holds the resolved options and the model-path rules.

#include <memory>
#include <string>

#include "semantic/class_groups.h"
#include "semantic/folder_segmenter.h"
#include "semantic/onnx_segmenter.h"
#include "semantic/segmentation_worker.h"

namespace esdslam {

// The network for every-frame labels, and the cheaper one for labels every K-th frame (the
// predicted masks between them lose more to label age than the smaller input costs; measured in
// docs/RESULTS.md, "Mask prediction").
inline constexpr const char* kDefaultSegmentationModel = "models/espnetv2_s2.0_voc_384x288.onnx";
inline constexpr const char* kFastSegmentationModel = "models/espnetv2_s2.0_voc_256x192.onnx";

struct SemanticSettings {
  // kProvided: each frame's labels come from the library caller (semantic/provided_labels.h).
  enum class Kind { kOnnx, kFolder, kProvided };
  Kind kind = Kind::kOnnx;
  OnnxSegmenterOptions onnx;  // model_path resolved to an existing file when possible
  FolderSegmenterOptions folder;
  ClassGroupOptions groups;
  SegmentationMode mode = SegmentationMode::kEveryFrame;  // kNewestWins: --realtime (Semantic.realtime)
  // Semantic.segmentEvery K: 1 = the network labels every frame and tracking waits for each
  // frame's labels; K > 1 = it labels every K-th frame (and earlier when the predicted mask is no
  // longer trusted) on its own thread and the frames between get predicted masks
  // (dynamic/semantic_front_end.h). [1, 1000] frames.
  int segment_every = 4;
  // Semantic.labelDelay L: with K > 1, labels are used from L frames after their frame on (a
  // single-thread run waits for them there, so it repeats exactly). [0, 100] frames.
  int label_delay_frames = 0;
  // Semantic.lookAhead A: with K > 1 (not --realtime, not --live), a recorded sequence's frames
  // reach the label schedule A frames before they are tracked, so the network labels frame s
  // while the frames before it are tracked and its labels are back by the time s is masked.
  // Costs A decoded frames of memory and nothing on a live camera (not used there). [1, 30].
  int look_ahead_frames = 8;
  // Semantic.model not given: the model follows the schedule (ApplyLabelSchedule).
  bool model_auto = true;
  bool threads_auto = true;  // Semantic.threads not given (0): chosen with the model
  // Labels come from the predictor between network frames (segment_every > 1 or --realtime).
  bool predicted() const { return segment_every > 1 || mode == SegmentationMode::kNewestWins; }
  // The class groups, and the chosen segmenter's options. Throws SettingError naming the key.
  void Check() const;
};

// Finds a model file: absolute or existing as given; else under `settings_dir` and the data
// roots (common/data_files.h). Returns `path` unchanged when nothing exists (the segmenter then
// reports it as missing).
std::string ResolveModelPath(const std::string& path, const std::string& settings_dir = "");

// Sets the ONNX model (resolved as above) and, if its name ends in _<W>x<H>.onnx, the input size.
void SetModel(SemanticSettings& settings, const std::string& path, const std::string& settings_dir = "");

// With model_auto: the model for the schedule (kFastSegmentationModel when predicted(), else
// kDefaultSegmentationModel) and, when predicted and Semantic.threads is 0, one OpenCV thread:
// the network then runs beside tracking and local mapping on its own core instead of spreading
// over cores that are busy.
void ApplyLabelSchedule(SemanticSettings& settings);

// Builds the configured segmenter (loads the model / indexes the mask folder).
std::unique_ptr<Segmenter> MakeSegmenter(const SemanticSettings& settings);

}  // namespace esdslam
