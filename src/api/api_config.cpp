#include "api/api_config.h"

#include <filesystem>

#include "common/error.h"
#include "system/run_settings.h"

namespace esdslam {
namespace {

RunSettings LoadSettings(const SystemConfig& config) {
  if (!config.settings_file.empty()) return LoadRunSettings(config.settings_file);
  return LoadRunSettingsFromText(config.settings_text, "<SystemConfig::settings_text>");
}

RunFlags ToRunFlags(const SystemConfig& config) {
  RunFlags flags;
  flags.mode = ParseDynamicMode(config.mode);
  flags.segment_every = config.label_input ? 1 : config.segment_every;
  flags.single_thread = config.single_thread;
  flags.seed = config.seed;
  flags.no_relocalization = !config.relocalization;
  flags.no_loop = !config.loop_closing;
  flags.dense = config.dense;
  flags.load_map = config.load_map;
  flags.localization = config.localization;
  flags.run.out_dir = config.out_dir;
  return flags;
}

}  // namespace

void SystemConfig::Check() const {
  if (settings_file.empty() && settings_text.empty())
    throw Error("SystemConfig: give settings_file (a settings YAML file) or settings_text (its text)");
  ParseDynamicMode(mode);  // throws naming the choices
  if (segment_every < 0 || segment_every > 1000)
    throw Error("SystemConfig: segment_every must be in [0, 1000] (0 = the settings' Semantic.segmentEvery), got " +
                std::to_string(segment_every));
  if (label_input && mode != "semantic" && mode != "full")
    throw Error("SystemConfig: label_input needs mode semantic or full, got '" + mode + "'");
  if (!label_input && !label_classes.empty())
    throw Error("SystemConfig: label_classes is only used with label_input");
  if (label_classes.size() > 256) throw Error("SystemConfig: label_classes holds more than 256 classes (CV_8U ids)");
  if (localization && load_map.empty()) throw Error("SystemConfig: localization needs load_map");
  if (viewer_port < -1 || viewer_port > 65535)
    throw Error("SystemConfig: viewer_port must be -1 (off) or a TCP port in [0, 65535], got " +
                std::to_string(viewer_port));
}

RunConfig ResolveApiConfig(const SystemConfig& config) {
  config.Check();
  RunSettings settings = LoadSettings(config);
  if (config.label_input) {
    settings.semantic.kind = SemanticSettings::Kind::kProvided;
    if (!config.label_classes.empty()) settings.semantic.onnx.class_names = config.label_classes;
  }
  return ResolveRunConfig(std::move(settings), ToRunFlags(config));
}

Matrix4 ToMatrix4(const Rigid3& transform) {
  const Mat4 m = transform.matrix();
  Matrix4 out{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[static_cast<std::size_t>(4 * r + c)] = m(r, c);
  return out;
}

TrackingStatus ToStatus(TrackingState state) {
  switch (state) {
    case TrackingState::kOk: return TrackingStatus::kOk;
    case TrackingState::kLost: return TrackingStatus::kLost;
    case TrackingState::kNotInitialized: break;
  }
  return TrackingStatus::kNotInitialized;
}

const char* StatusName(TrackingStatus status) {
  switch (status) {
    case TrackingStatus::kOk: return "OK";
    case TrackingStatus::kLost: return "LOST";
    case TrackingStatus::kNotInitialized: break;
  }
  return "NOT_INITIALIZED";
}

}  // namespace esdslam
