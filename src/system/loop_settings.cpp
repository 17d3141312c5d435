#include "system/loop_settings.h"

#include <spdlog/spdlog.h>

#include "common/error.h"
#include "common/setting_error.h"
#include "common/timer.h"
#include "semantic/semantic_settings.h"

namespace esdslam {

void LoopOptions::Check() const {
  // The bound keys first, so that an error names the key (and its line, on load).
  CheckRange("Loop.directIndexLevel", places.direct_index_level, 1, 6);
  CheckRange("Loop.relocMinInliers", relocalizer.min_final_inliers, relocalizer.min_optimized_inliers, 10000);
  CheckRange("Loop.relocMaxCandidates", relocalizer.max_candidates, 1, 1000);
  CheckRange("Loop.relocRatio", relocalizer.bow.ratio, 0.01, 1.0);
  CheckRange("Loop.consistency", closer.consistency_threshold, 1, 100);
  CheckRange("Loop.minInliers", closer.verification.min_refined_inliers, 3, 10000);
  CheckRange("Loop.minMatches", closer.verification.min_total_matches, 3, 10000);
  CheckRange("Loop.essentialMinCovisibility", closer.essential_min_covisibility, 1, 100000);
  places.Check();
  relocalizer.Check();
  closer.Check();
  if (needs_vocabulary() && vocabulary.empty())
    throw Error("LoopOptions: relocalization and loop closing need a vocabulary path");
}

void BindLoopSettings(LoopOptions& options, SettingsTable& table) {
  table.Add("Loop.vocabulary", &options.vocabulary);
  table.Add("Loop.relocalization", &options.relocalization);
  table.Add("Loop.directIndexLevel", &options.places.direct_index_level);
  table.Add("Loop.relocMinInliers", &options.relocalizer.min_final_inliers);
  table.Add("Loop.relocMaxCandidates", &options.relocalizer.max_candidates);
  table.Add("Loop.relocRatio", &options.relocalizer.bow.ratio);
  table.Add("Loop.closing", &options.closing);
  table.Add("Loop.globalBA", &options.closer.global_bundle_adjustment);
  table.Add("Loop.consistency", &options.closer.consistency_threshold);
  table.Add("Loop.minInliers", &options.closer.verification.min_refined_inliers);
  table.Add("Loop.minMatches", &options.closer.verification.min_total_matches);
  table.Add("Loop.essentialMinCovisibility", &options.closer.essential_min_covisibility);
}

std::shared_ptr<const Vocabulary> LoadVocabulary(const std::string& path, const std::string& settings_dir) {
  const std::string resolved = ResolveModelPath(path, settings_dir);
  Stopwatch watch;
  auto vocabulary = std::make_shared<const Vocabulary>(Vocabulary::Load(resolved));
  spdlog::info("loop: vocabulary {} ({} words, {} levels) loaded in {:.0f} ms", resolved, vocabulary->num_words(),
               vocabulary->levels(), watch.ElapsedMs());
  return vocabulary;
}

}  // namespace esdslam
