#pragma once
// Place recognition over the map's keyframes: one vocabulary per run, each keyframe's BoW vector
// and direct index (computed once, when the keyframe is indexed) and the inverted-file keyframe
// database. Culled keyframes are dropped from the database when indexing or querying notices
// them (KeyFrame::is_bad), so a query never returns a bad keyframe.
//
// Thread-safe: one mutex for the keyframe store (never held while calling into the database or
// a keyframe), the database has its own. Lock order: store mutex is a leaf.

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "place/bow_matcher.h"
#include "place/keyframe_database.h"
#include "place/vocabulary.h"
#include "map/map_types.h"
#include "map/feature_set.h"

namespace esdslam {

struct ImageBow {
  BowVector bow;
  FeatureVector direct_index;  // node at depth PlaceRecognitionOptions::direct_index_level
};

struct PlaceRecognitionOptions {
  // Depth of the direct-index nodes below the root. ORB-SLAM2 uses 4 levels up from the leaves of
  // a 6-level tree (depth 2); with our 5-level tree depth 2 keeps ~100 nodes (same granularity).
  int direct_index_level = 2;
  int covisible_neighbours = 10;  // covisibility group size for candidate scoring
  KeyFrameDatabaseOptions database;
  void Check() const;
};

class PlaceRecognition {
 public:
  PlaceRecognition(std::shared_ptr<const Vocabulary> vocabulary, const PlaceRecognitionOptions& options = {});

  // BoW vector and direct index of an image's descriptors (dynamic keypoints included in the BoW
  // vector: they are few and the vector only ranks candidates).
  ImageBow Compute(const FeatureSet& features) const;

  // Computes and stores the keyframe's BoW and adds it to the database (no-op when indexed).
  void AddKeyFrame(KeyFrame* keyframe);
  // Adds the listed keyframes that are not indexed yet (e.g. the map's first keyframe).
  void AddMissing(const std::vector<KeyFrame*>& keyframes);
  void EraseKeyFrame(const KeyFrame* keyframe);
  // Removes every culled keyframe from the database.
  void PurgeBadKeyFrames();
  bool Contains(const KeyFrame* keyframe) const;
  std::size_t size() const;
  // The stored BoW of an indexed keyframe (nullptr when absent).
  std::shared_ptr<const ImageBow> KeyFrameBow(const KeyFrame* keyframe) const;

  // Relocalization candidates for a frame, best first (live keyframes only).
  std::vector<KeyFrame*> RelocalizationCandidates(const ImageBow& query);
  // Loop candidates for an indexed keyframe (ORB-SLAM2's DetectLoopCandidates), best first: the
  // minimum score is the lowest score between it and `score_neighbours` (its covisible
  // keyframes); `excluded` (its connected keyframes), the query itself and every keyframe newer
  // than the query (indexed by tracking but not yet seen by loop closing) are never returned.
  std::vector<KeyFrame*> LoopCandidates(KeyFrame* query, const std::vector<KeyFrame*>& score_neighbours,
                                        const std::vector<KeyFrame*>& excluded);

  const Vocabulary& vocabulary() const { return *vocabulary_; }
  const PlaceRecognitionOptions& options() const { return options_; }

 private:
  CovisibleNeighbours NeighbourFunction() const;
  std::vector<KeyFrame*> ToKeyFrames(const std::vector<PlaceCandidate>& candidates) const;

  std::shared_ptr<const Vocabulary> vocabulary_;
  PlaceRecognitionOptions options_;
  KeyFrameDatabase database_;
  mutable std::mutex mutex_;
  std::map<long, KeyFrame*> keyframes_;  // indexed keyframes by id
  std::map<long, std::shared_ptr<const ImageBow>> bows_;
};

}  // namespace esdslam
