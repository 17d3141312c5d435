#pragma once
// Place recognition / relocalization options of a run and their settings keys. Keys (all
// optional):
//   Loop.vocabulary: BoW vocabulary file (default models/vocabulary/orb_vocabulary.bin; resolved
//       like model files: as given, next to the settings file, the executable, the source tree)
//   Loop.relocalization: 1/0, BoW relocalization when tracking is LOST (default 1)
//   Loop.directIndexLevel: depth of the direct-index nodes (default 2)
//   Loop.relocMinInliers: inliers needed to accept a relocalization (default 50)
//   Loop.relocMaxCandidates: BoW candidates tried per lost frame (default 20)
//   Loop.relocRatio: descriptor ratio test of the BoW matching (default 0.75)
//   Loop.closing: 1/0, loop closing thread (default 1; esdslam run --no-loop sets 0)
//   Loop.globalBA: 1/0, global bundle adjustment after each loop correction (default 1)
//   Loop.consistency: consecutive consistent keyframes before a candidate is verified (3)
//   Loop.minInliers: refined inliers of the keyframe-to-keyframe transform (default 20)
//   Loop.minMatches: matches after projecting the loop points (default 40)
//   Loop.essentialMinCovisibility: shared points of an essential-graph covisibility edge (100)

#include <memory>
#include <string>

#include "io/settings_table.h"
#include "loop/loop_closer.h"
#include "place/place_recognition.h"
#include "place/vocabulary.h"
#include "tracking/relocalizer.h"

namespace esdslam {

inline constexpr const char* kDefaultVocabulary = "models/vocabulary/orb_vocabulary.bin";

struct LoopOptions {
  bool relocalization = true;
  bool closing = true;  // loop closing thread
  std::string vocabulary = kDefaultVocabulary;  // resolved when the system loads it
  PlaceRecognitionOptions places;
  RelocalizerOptions relocalizer;
  LoopClosingOptions closer;
  bool needs_vocabulary() const { return relocalization || closing; }
  void Check() const;
};

void BindLoopSettings(LoopOptions& options, SettingsTable& table);

// Loads the vocabulary (path resolved as described above). Throws InputError when missing/corrupt.
std::shared_ptr<const Vocabulary> LoadVocabulary(const std::string& path, const std::string& settings_dir = "");

}  // namespace esdslam
