#pragma once
// Semantic options from an ORB-SLAM2-style YAML settings file (flat keys). Keys read, all
// optional:
//   Semantic.segmenter: onnx | folder                  (default onnx)
//   Semantic.model: path to the .onnx file             (default models/espnetv2_s2.0_voc_384x288.onnx)
//   Semantic.inputWidth, Semantic.inputHeight: network input size in pixels (default: taken from a
//       model file name ending in _<W>x<H>.onnx, else 384x288)
//   Semantic.threads: OpenCV threads, 0 = leave unchanged (default 0)
//   Semantic.upsampleScores: 1/0 (default 1, see onnx_segmenter.h)
//   Semantic.dynamicClasses, Semantic.potentiallyDynamicClasses: VOC class names, as a YAML list
//       ([person, chair]) or one comma-separated string ("person,chair")
//   Semantic.maskFolder, Semantic.maskTolerance (s), Semantic.allowMissingMasks: folder segmenter
//   Semantic.realtime: 1 = newest-wins segmentation thread, 0 = every frame (default 0)
// A leading "%YAML:1.0" line (written by OpenCV's FileStorage, rejected by yaml-cpp) is skipped.

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
};

// Defaults (with the default model resolved) when `path` is empty. Throws InputError on a
// missing or malformed file or a value of the wrong type.
SemanticSettings LoadSemanticSettings(const std::string& path);

// Finds a model file: absolute or existing as given; else relative to `settings_dir`, the
// executable's folder and its two parents. Returns
// `path` unchanged when nothing exists (the segmenter then reports it as missing).
std::string ResolveModelPath(const std::string& path, const std::string& settings_dir = "");

// Sets the ONNX model (resolved as above) and, if its name ends in _<W>x<H>.onnx, the input size.
void SetModel(SemanticSettings& settings, const std::string& path, const std::string& settings_dir = "");

// Builds the configured segmenter (loads the model / indexes the mask folder).
std::unique_ptr<Segmenter> MakeSegmenter(const SemanticSettings& settings);

}  // namespace esdslam
