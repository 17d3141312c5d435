#include "system/run_settings.h"

#include <filesystem>
#include <regex>
#include <sstream>

#include <spdlog/spdlog.h>

#include "common/error.h"
#include "common/setting_error.h"
#include "dense/dense_settings.h"
#include "io/settings_table.h"

namespace esdslam {
namespace {

std::vector<std::string> SplitNames(const std::string& text) {
  std::vector<std::string> names;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto b = item.find_first_not_of(" \t");
    const auto e = item.find_last_not_of(" \t");
    if (b != std::string::npos) names.push_back(item.substr(b, e - b + 1));
  }
  return names;
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ",") + name;
  return text;
}

void BindGrowing(const std::string& prefix, RegionGrowingOptions& o, SettingsTable& table) {
  table.Add(prefix + "absTolerance", &o.abs_tolerance_m);
  table.Add(prefix + "depthSqTolerance", &o.depth_sq_tolerance);
  table.Add(prefix + "maxDepthFromSeed", &o.max_depth_from_seed_m);
  table.Add(prefix + "seedSplitGap", &o.seed_split_gap_m);
  table.Add(prefix + "minSeedFraction", &o.min_seed_fraction);
  table.Add(prefix + "maxOutsideFraction", &o.max_outside_fraction);
  table.Add(prefix + "seedErosion", &o.seed_erosion_px);
  table.Add(prefix + "seedCoreFraction", &o.seed_core_fraction);
  table.Add(prefix + "connectivity", &o.connectivity);
  table.Add(prefix + "growthBand", &o.growth_band_px);
  table.Add(prefix + "noDepthDilation", &o.no_depth_dilation_px);
  table.Add(prefix + "minComponent", &o.min_component_px);
}

SettingsTable MakeTable(RunSettings& run, SemanticKeys& semantic) {
  SettingsTable table;
  BindCoreSettings(run.core, table);
  BindSemanticSettings(semantic, table);
  BindDynamicSettings(run, table);
  BindDenseSettings(run.dense, table);
  BindLoopSettings(run.loop, table);
  return table;
}

}  // namespace

void RunSettings::Check() const {
  core.Check();
  mask_refine.Check();
  CheckRange("Sequence.maxConsecutiveBadFrames", max_consecutive_bad_frames, 1, 100000, "frames");
  CheckRange("Tracking.motionPriorBelowMatches", motion_prior_below_matches, 0, 100000, "matches (0 = off)");
  CheckRange("Tracking.maxCoastedFrames", max_coasted_frames, 0, 1000, "frames (0 = off)");
  CheckRange("Tracking.depthPrior", depth_prior, 0, 1, "(0 = off, 1 = on)");
  CheckRange("Tracking.depthPriorWeight", depth_prior_weight, 1e-6, 1.0, "(share of an independent reading per depth sample)");
  region_growing.Check("Dynamic.grow.");
  geometry.Check();
  dense.Check();
  loop.Check();
  semantic.Check();
}

SemanticKeys SemanticKeys::From(const SemanticSettings& s) {
  SemanticKeys k;
  k.segmenter = s.kind == SemanticSettings::Kind::kFolder     ? "folder"
                : s.kind == SemanticSettings::Kind::kProvided ? "provided"
                                                               : "onnx";
  k.model = s.onnx.model_path;
  k.input_width = s.onnx.input_width, k.input_height = s.onnx.input_height;
  k.threads = s.onnx.threads;
  k.upsample_scores = s.onnx.upsample_scores;
  k.dynamic_classes = JoinNames(s.groups.dynamic_classes);
  k.potentially_dynamic_classes = JoinNames(s.groups.potentially_dynamic_classes);
  k.mask_folder = s.folder.folder;
  k.mask_tolerance_s = s.folder.tolerance_s;
  k.allow_missing_masks = s.folder.allow_missing;
  k.realtime = s.mode == SegmentationMode::kNewestWins;
  k.segment_every = s.segment_every;
  k.label_delay = s.label_delay_frames;
  k.look_ahead = s.look_ahead_frames;
  return k;
}

SemanticSettings SemanticKeys::ToSemanticSettings(const std::string& settings_dir) const {
  SemanticSettings s;
  if (segmenter == "folder") s.kind = SemanticSettings::Kind::kFolder;
  else if (segmenter == "provided") s.kind = SemanticSettings::Kind::kProvided;
  else CheckSetting(segmenter == "onnx", "Semantic.segmenter", "must be onnx, folder or provided, got '" + segmenter + "'");
  s.mode = realtime ? SegmentationMode::kNewestWins : SegmentationMode::kEveryFrame;
  s.segment_every = segment_every;
  s.label_delay_frames = label_delay;
  s.look_ahead_frames = look_ahead;
  s.onnx.threads = threads;
  s.threads_auto = threads == 0;
  s.model_auto = model.empty();
  if (!s.model_auto) SetModel(s, model, settings_dir);  // also the input size from a _<W>x<H>.onnx name
  ApplyLabelSchedule(s);  // the model (when not given) and threads (when 0) for the schedule
  CheckRange("Semantic.inputWidth", input_width, 0, 4096, "px (0 = from the model name)");
  CheckRange("Semantic.inputHeight", input_height, 0, 4096, "px (0 = from the model name)");
  if (input_width > 0) s.onnx.input_width = input_width;
  if (input_height > 0) s.onnx.input_height = input_height;
  if (input_width > 0 || input_height > 0) s.model_auto = false;  // sized for the model chosen here
  s.onnx.upsample_scores = upsample_scores;
  s.onnx.compute_person_probability = false;  // no stage of a run reads it (3-5 ms per network call)
  s.groups.dynamic_classes = SplitNames(dynamic_classes);
  s.groups.potentially_dynamic_classes = SplitNames(potentially_dynamic_classes);
  s.folder.folder = mask_folder;
  if (!mask_folder.empty() && std::filesystem::path(mask_folder).is_relative() && !settings_dir.empty() &&
      !std::filesystem::exists(mask_folder))
    s.folder.folder = (std::filesystem::path(settings_dir) / mask_folder).string();
  s.folder.tolerance_s = mask_tolerance_s;
  s.folder.allow_missing = allow_missing_masks;
  return s;
}

void BindSemanticSettings(SemanticKeys& k, SettingsTable& table) {
  table.Add("Semantic.segmenter", &k.segmenter);
  table.Add("Semantic.model", &k.model);
  table.Add("Semantic.inputWidth", &k.input_width);
  table.Add("Semantic.inputHeight", &k.input_height);
  table.Add("Semantic.threads", &k.threads);
  table.Add("Semantic.upsampleScores", &k.upsample_scores);
  table.Add("Semantic.dynamicClasses", &k.dynamic_classes);
  table.Add("Semantic.potentiallyDynamicClasses", &k.potentially_dynamic_classes);
  table.Add("Semantic.maskFolder", &k.mask_folder);
  table.Add("Semantic.maskTolerance", &k.mask_tolerance_s);
  table.Add("Semantic.allowMissingMasks", &k.allow_missing_masks);
  table.Add("Semantic.realtime", &k.realtime);
  table.Add("Semantic.segmentEvery", &k.segment_every);
  table.Add("Semantic.labelDelay", &k.label_delay);
  table.Add("Semantic.lookAhead", &k.look_ahead);
}

void BindDynamicSettings(RunSettings& run, SettingsTable& table) {
  table.Add("Dynamic.maskDilation", &run.mask_refine.dilation_px);
  table.Add("Dynamic.refineScale", &run.mask_refine.scale);
  table.Add("Sequence.maxConsecutiveBadFrames", &run.max_consecutive_bad_frames);
  table.Add("Tracking.motionPriorBelowMatches", &run.motion_prior_below_matches);
  table.Add("Tracking.maxCoastedFrames", &run.max_coasted_frames);
  table.Add("Tracking.depthPrior", &run.depth_prior);
  table.Add("Tracking.depthPriorWeight", &run.depth_prior_weight);
  BindGrowing("Dynamic.grow.", run.region_growing, table);
  GeometryCheckOptions& g = run.geometry.check;
  table.Add("Dynamic.check.maxParallax", &g.max_parallax_deg);
  table.Add("Dynamic.check.absThreshold", &g.abs_threshold_m);
  table.Add("Dynamic.check.depthSqThreshold", &g.depth_sq_threshold);
  table.Add("Dynamic.check.minDepth", &g.min_depth_m);
  table.Add("Dynamic.check.maxDepth", &g.max_depth_m);
  table.Add("Dynamic.check.windowRadius", &g.window_radius_px);
  table.Add("Dynamic.check.clusterRadius", &g.cluster_radius_px);
  table.Add("Dynamic.check.minClusterPoints", &g.min_cluster_points);
  table.Add("Dynamic.check.minClusterSupport", &g.min_cluster_support);
  table.Add("Dynamic.check.motionWindowFraction", &g.motion_window_fraction);
  table.Add("Dynamic.check.maxWindowRadius", &g.max_window_radius_px);
  table.Add("Dynamic.check.maskRadius", &g.mask_radius_m);
  table.Add("Dynamic.check.maxMaskRadius", &g.max_mask_radius_px);
  BindGrowing("Dynamic.check.grow.", g.growing, table);
  table.Add("Dynamic.check.referenceKeyframes", &run.geometry.reference_keyframes);
  table.Add("Dynamic.check.minReferenceAge", &run.geometry.min_reference_age_s);
  table.Add("Dynamic.check.keyframeDepthCapacity", &run.geometry.keyframe_depth_capacity);
  table.Add("Dynamic.check.keyframeDepthScale", &run.geometry.keyframe_depth_scale);
  table.Add("Dynamic.check.cullAfterFrames", &run.geometry.cull_after_frames);
}

namespace {

// Reads `path` into `run` through the one key table; returns the key lines. Throws InputError.
// text: the file's contents when given (then `path` only names it in messages), else read from
// `path`; base_dir: where relative model and vocabulary paths are looked for first.
SettingsTable::KeyLines ReadRunSettings(const std::string& path, bool all_optional, RunSettings& run,
                                        std::vector<std::string>* warnings, const std::string* text = nullptr,
                                        const std::string& base_dir = "") {
  SemanticKeys semantic = SemanticKeys::From(run.semantic);
  semantic.model = "";  // not given: the model follows the label schedule
  semantic.input_width = semantic.input_height = 0;
  SettingsTable table = MakeTable(run, semantic);
  if (all_optional) table.MakeAllOptional();
  SettingsTable::KeyLines lines;
  std::vector<std::string> load_warnings = text ? table.LoadFromString(*text, path, &lines) : table.Load(path, &lines);
  if (warnings) warnings->insert(warnings->end(), load_warnings.begin(), load_warnings.end());
  const std::string dir = text ? base_dir : std::filesystem::path(path).parent_path().string();
  CheckWithKeyLines(path, lines, [&] {
    run.semantic = semantic.ToSemanticSettings(dir);
    run.loop.vocabulary = ResolveModelPath(run.loop.vocabulary, dir);
    ResolveOrbSlam3Keys(run.core, lines);
  });
  return lines;
}

}  // namespace

RunSettings LoadRunSettings(const std::string& path, std::vector<std::string>* warnings) {
  RunSettings run;
  const SettingsTable::KeyLines lines = ReadRunSettings(path, false, run, warnings);
  CheckWithKeyLines(path, lines, [&] { run.Check(); });
  return run;
}

RunSettings LoadRunSettingsFromText(const std::string& text, const std::string& name, const std::string& base_dir,
                                    std::vector<std::string>* warnings) {
  RunSettings run;
  const SettingsTable::KeyLines lines = ReadRunSettings(name, false, run, warnings, &text, base_dir);
  CheckWithKeyLines(name, lines, [&] { run.Check(); });
  return run;
}

SemanticSettings LoadSemanticSettings(const std::string& path) {
  RunSettings run;
  if (path.empty()) {
    SetModel(run.semantic, kDefaultSegmentationModel);
    CheckWithKeyLines("<default semantic settings>", {}, [&] { run.semantic.Check(); });
    return run.semantic;
  }
  const SettingsTable::KeyLines lines = ReadRunSettings(path, true, run, nullptr);
  CheckWithKeyLines(path, lines, [&] { run.semantic.Check(); });
  return run.semantic;
}

std::string RunSettingsYaml(const RunSettings& settings) {
  RunSettings copy = settings;
  SemanticKeys semantic = SemanticKeys::From(settings.semantic);
  return MakeTable(copy, semantic).ToYaml();
}

void SaveRunSettings(const RunSettings& settings, const std::string& path) {
  RunSettings copy = settings;
  SemanticKeys semantic = SemanticKeys::From(settings.semantic);
  MakeTable(copy, semantic).Save(path);
}

}  // namespace esdslam
