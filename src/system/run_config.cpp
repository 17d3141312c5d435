#include "system/run_config.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <sstream>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common/error.h"

namespace esdslam {

namespace {
constexpr DynamicMode kDynamicModes[] = {DynamicMode::kNone, DynamicMode::kSemantic, DynamicMode::kGeometry,
                                         DynamicMode::kFull};
}  // namespace

const char* ToString(DynamicMode mode) {
  switch (mode) {
    case DynamicMode::kNone: return "none";
    case DynamicMode::kSemantic: return "semantic";
    case DynamicMode::kGeometry: return "geometry";
    case DynamicMode::kFull: return "full";
  }
  return "?";
}

DynamicMode ParseDynamicMode(const std::string& text) {
  for (DynamicMode mode : kDynamicModes)
    if (text == ToString(mode)) return mode;
  throw Error("unknown dynamic mode '" + text + "' (none | semantic | geometry | full)");
}

bool UsesSegmentation(DynamicMode mode) { return mode == DynamicMode::kSemantic || mode == DynamicMode::kFull; }
bool UsesGeometryCheck(DynamicMode mode) { return mode == DynamicMode::kGeometry || mode == DynamicMode::kFull; }

void PipelineOptions::Check() const {
  if (std::find(std::begin(kDynamicModes), std::end(kDynamicModes), mode) == std::end(kDynamicModes))
    throw Error("pipeline: unknown dynamic mode " + std::to_string(static_cast<int>(mode)));
  if (!dense && !dense_mask_dir.empty()) throw Error("pipeline: dense_mask_dir needs the dense map");
  if (look_ahead_frames < 1 || look_ahead_frames > 30)
    throw Error("pipeline: look_ahead_frames must be in [1, 30], got " + std::to_string(look_ahead_frames));
}

void RunOptions::Check() const {
  if (max_frames < 0) throw Error("run: max_frames must be >= 0 (0 = all), got " + std::to_string(max_frames));
}

int MaxFramesBetweenKeyframes(double fps) { return std::max(1, static_cast<int>(std::lround(fps))); }

namespace {

// The settings keys of the SLAM options' copies must be those recorded from `settings`.
void CheckSlamAgreesWithSettings(const RunSettings& settings, const SlamOptions& slam) {
  RunSettings from_slam = settings;
  from_slam.loop = slam.loop;
  from_slam.geometry = slam.geometry;
  if (RunSettingsYaml(from_slam) != RunSettingsYaml(settings))
    throw Error("run config: the SLAM options' Loop.* or Dynamic.check.* values differ from the settings");
  if (slam.tracker.max_frames_between_keyframes != MaxFramesBetweenKeyframes(settings.core.fps))
    throw Error("run config: the keyframe interval differs from Camera.fps");
}

}  // namespace

void RunConfig::Check() const {
  settings.Check();
  slam.Check();
  pipeline.Check();
  run.Check();
  CheckSlamAgreesWithSettings(settings, slam);
  if (slam.geometry_check != UsesGeometryCheck(pipeline.mode))
    throw Error(std::string("run config: the geometry check does not match mode ") + ToString(pipeline.mode));
}

RunConfig ResolveRunConfig(RunSettings settings, const RunFlags& flags) {
  RunConfig config;
  if (flags.no_relocalization) settings.loop.relocalization = false;
  if (flags.no_loop) settings.loop.closing = false;
  if (flags.realtime) settings.semantic.mode = SegmentationMode::kNewestWins;
  if (flags.segment_every > 0) settings.semantic.segment_every = flags.segment_every;
  ApplyLabelSchedule(settings.semantic);
  settings.loop.relocalizer.pnp.seed = flags.seed;
  settings.loop.closer.verification.ransac.seed = flags.seed;
  config.settings = std::move(settings);
  SlamOptions& slam = config.slam;
  slam.single_thread = flags.single_thread;
  slam.tracker.max_frames_between_keyframes = MaxFramesBetweenKeyframes(config.settings.core.fps);
  slam.tracker.localization_only = flags.localization;
  slam.tracker.motion_prior_below_matches = config.settings.motion_prior_below_matches;
  slam.tracker.max_coasted_frames = config.settings.max_coasted_frames;
  slam.tracker.depth_prior = config.settings.depth_prior != 0;
  slam.tracker.depth_prior_weight = config.settings.depth_prior_weight;
  slam.loop = config.settings.loop;
  slam.geometry_check = UsesGeometryCheck(flags.mode);
  slam.geometry = config.settings.geometry;
  // The mask is known before extraction (made ahead by the semantic stage, or the caller's);
  // a frame without a mask (modes none and geometry) is extracted everywhere.
  slam.frame.mask_extraction = flags.mask_extraction;
  slam.load_map = flags.load_map;
  config.pipeline.mode = flags.mode;
  config.pipeline.dense = flags.dense;
  if (flags.dense && !flags.run.out_dir.empty())
    config.pipeline.dense_mask_dir = (std::filesystem::path(flags.run.out_dir) / "masks").string();
  config.pipeline.threaded_dense = !flags.single_thread;
  const SemanticSettings& semantic = config.settings.semantic;
  // A camera's frames cannot be read ahead: looking ahead there would delay every pose.
  if (UsesSegmentation(flags.mode) && semantic.predicted() && semantic.mode != SegmentationMode::kNewestWins &&
      !flags.run.live)
    config.pipeline.look_ahead_frames = semantic.look_ahead_frames;
  config.run = flags.run;
  config.Check();
  return config;
}

void LogRunConfig(const RunConfig& config) {
  const Settings& s = config.settings.core;
  const auto& c = s.camera;
  // Written with the run's results (system/run_outputs.h), once, whatever ends the run.
  const std::string where = config.run.out_dir.empty()
                                ? std::string("not saved (no output folder)")
                                : (std::filesystem::path(config.run.out_dir) / "settings_used.yaml").string();
  const SemanticSettings& semantic = config.settings.semantic;
  const std::string labels = semantic.mode == SegmentationMode::kNewestWins
                                 ? std::string("newest frame whenever the network is free, predicted masks between")
                             : semantic.segment_every == 1
                                 ? std::string("every frame")
                                 : fmt::format("every {}th frame, predicted masks between (frames submitted {} ahead, "
                                               "labels used {} frames later)",
                                               semantic.segment_every, config.pipeline.look_ahead_frames,
                                               semantic.label_delay_frames);
  spdlog::info("run: mode {}, {}, seed {}; effective settings in {}", ToString(config.pipeline.mode),
               config.slam.single_thread ? "single thread" : "threaded", config.settings.loop.relocalizer.pnp.seed,
               where);
  spdlog::debug("run: sequence {} -> {}{}", config.run.sequence_dir, config.run.out_dir,
                config.run.live ? " (live: sensor-clock playback, frames dropped while busy)" : "");
  spdlog::debug("run: camera fx={} fy={} cx={} cy={} k=[{} {} {} {} {}] {}x{} fps={}", c.fx, c.fy, c.cx, c.cy, c.k1,
                c.k2, c.p1, c.p2, c.k3, c.width, c.height, s.fps);
  spdlog::debug("run: segmentation labels {}, model {}, dense {}, debug frames {}", labels, semantic.onnx.model_path,
                config.pipeline.dense ? "on" : "off",
                config.run.debug_frames_dir.empty() ? "off" : config.run.debug_frames_dir);
  std::istringstream lines(RunSettingsYaml(config.settings));
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("%YAML", 0) != 0) spdlog::debug("settings: {}", line);
  }
}

}  // namespace esdslam
