#include "semantic/semantic_settings.h"

#include <filesystem>
#include <regex>

#include "common/data_files.h"
#include "common/error.h"
#include "common/setting_error.h"

namespace esdslam {
namespace fs = std::filesystem;
namespace {

// Input size from a file name ending in _<W>x<H>.onnx.
bool SizeFromModelName(const std::string& model, int& width, int& height) {
  static const std::regex pattern(R"(_(\d{1,5})x(\d{1,5})\.onnx$)");
  std::smatch m;
  if (!std::regex_search(model, m, pattern)) return false;
  width = std::stoi(m[1]);
  height = std::stoi(m[2]);
  return true;
}

}  // namespace

std::string ResolveModelPath(const std::string& path, const std::string& settings_dir) {
  return FindDataPath(path, settings_dir);
}

void SetModel(SemanticSettings& settings, const std::string& path, const std::string& settings_dir) {
  settings.onnx.model_path = ResolveModelPath(path, settings_dir);
  SizeFromModelName(path, settings.onnx.input_width, settings.onnx.input_height);
}

void ApplyLabelSchedule(SemanticSettings& settings) {
  if (settings.model_auto) SetModel(settings, settings.predicted() ? kFastSegmentationModel : kDefaultSegmentationModel);
  if (settings.threads_auto) settings.onnx.threads = settings.predicted() ? 1 : 0;
}

void SemanticSettings::Check() const {
  try {
    groups.Check(onnx.class_names);
  } catch (const SettingError&) {
    throw;
  } catch (const Error& e) {
    throw SettingError("Semantic.dynamicClasses", std::string("Semantic.dynamicClasses/potentiallyDynamicClasses: ") +
                                                      e.what());
  }
  // Both segmenters' bound keys are checked, whichever is chosen.
  CheckRange("Semantic.maskTolerance", folder.tolerance_s, 0.0, 10.0, "s");
  CheckRange("Semantic.threads", onnx.threads, 0, 256);
  CheckRange("Semantic.segmentEvery", segment_every, 1, 1000, "frames (1 = every frame)");
  CheckRange("Semantic.labelDelay", label_delay_frames, 0, 100, "frames");
  CheckRange("Semantic.lookAhead", look_ahead_frames, 1, 30, "frames");
  if (kind == Kind::kProvided) {
    CheckSetting(segment_every == 1 && mode == SegmentationMode::kEveryFrame, "Semantic.segmentEvery",
                 "must be 1 (and Semantic.realtime 0) with Semantic.segmenter: provided: every frame brings its labels");
  }
  if (kind == Kind::kOnnx) onnx.Check();
  else if (kind == Kind::kFolder) folder.Check();
}

std::unique_ptr<Segmenter> MakeSegmenter(const SemanticSettings& settings) {
  if (settings.kind == SemanticSettings::Kind::kFolder) return std::make_unique<FolderSegmenter>(settings.folder);
  if (settings.kind == SemanticSettings::Kind::kProvided)
    throw Error("Semantic.segmenter: provided: labels come with each frame, given by the library caller "
                "(esdslam::System with label_input); a folder run cannot use it");
  return std::make_unique<OnnxSegmenter>(settings.onnx);
}

}  // namespace esdslam
