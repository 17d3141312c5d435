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

inline constexpr const char* kDefaultSegmentationModel = "models/espnetv2_s2.0_voc_384x288.onnx";

struct SemanticSettings {
  enum class Kind { kOnnx, kFolder };
  Kind kind = Kind::kOnnx;
  OnnxSegmenterOptions onnx;  // model_path resolved to an existing file when possible
  FolderSegmenterOptions folder;
  ClassGroupOptions groups;
  SegmentationMode mode = SegmentationMode::kEveryFrame;
  // The class groups, and the chosen segmenter's options. Throws SettingError naming the key.
  void Check() const;
};

// Finds a model file: absolute or existing as given; else relative to `settings_dir`, the
// executable's folder and its two parents. Returns
// `path` unchanged when nothing exists (the segmenter then reports it as missing).
std::string ResolveModelPath(const std::string& path, const std::string& settings_dir = "");

// Sets the ONNX model (resolved as above) and, if its name ends in _<W>x<H>.onnx, the input size.
void SetModel(SemanticSettings& settings, const std::string& path, const std::string& settings_dir = "");

// Builds the configured segmenter (loads the model / indexes the mask folder).
std::unique_ptr<Segmenter> MakeSegmenter(const SemanticSettings& settings);

}  // namespace esdslam
