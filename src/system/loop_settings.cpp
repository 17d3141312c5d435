#include "system/loop_settings.h"

#include <spdlog/spdlog.h>

#include "common/error.h"
#include "common/timer.h"
#include "semantic/semantic_settings.h"

namespace esdslam {

void LoopOptions::Check() const {
  places.Check();
  relocalizer.Check();
  if (relocalization && vocabulary.empty()) throw Error("LoopOptions: relocalization needs a vocabulary path");
}

void BindLoopSettings(LoopOptions& options, SettingsTable& table) {
  table.Add("Loop.vocabulary", &options.vocabulary);
  table.Add("Loop.relocalization", &options.relocalization);
  table.Add("Loop.directIndexLevel", &options.places.direct_index_level);
  table.Add("Loop.relocMinInliers", &options.relocalizer.min_final_inliers);
  table.Add("Loop.relocMaxCandidates", &options.relocalizer.max_candidates);
  table.Add("Loop.relocRatio", &options.relocalizer.bow.ratio);
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
