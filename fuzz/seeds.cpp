#include "fuzz/seeds.h"

#include <algorithm>

#include "map/core_test_scene.h"
#include "map/map.h"
#include "map/map_serialization.h"
#include "place/vocabulary.h"

namespace esdslam::fuzz {

std::shared_ptr<const RgbdRig> SeedRig() { return esdslam::testing::TestRig(); }

void WriteMapSeed(const std::string& path) {
  constexpr int kLandmarks = 12;
  const std::vector<Vec3> landmarks = esdslam::testing::RandomLandmarks(kLandmarks);
  const cv::Mat descriptors = esdslam::testing::RandomDescriptors(kLandmarks);
  Map map;
  std::vector<KeyFrame*> keyframes;
  std::vector<std::vector<int>> landmark_of_keypoint(2);
  for (int k = 0; k < 2; ++k) {
    const Rigid3 cam_from_world(Quat::Identity(), Vec3(-0.1 * k, 0, 0));
    auto features =
        esdslam::testing::ProjectLandmarks(landmarks, descriptors, cam_from_world, true, &landmark_of_keypoint[k]);
    KeyFrame* keyframe = map.CreateKeyFrame(k, 0.5 * k, features, cam_from_world);
    map.AddKeyFrame(keyframe);
    keyframes.push_back(keyframe);
  }
  for (int l = 0; l < kLandmarks; ++l) {
    MapPoint* point = nullptr;
    for (int k = 0; k < 2; ++k) {
      const auto& ids = landmark_of_keypoint[k];
      const auto it = std::find(ids.begin(), ids.end(), l);
      if (it == ids.end()) continue;
      const int index = static_cast<int>(it - ids.begin());
      if (point == nullptr) point = map.CreateMapPoint(landmarks[l], keyframes[k]);
      point->AddObservation(keyframes[k], index, true);
      keyframes[k]->AddMapPoint(point, index);
    }
    if (point == nullptr) continue;
    point->ComputeDistinctiveDescriptor();
    point->UpdateNormalAndDepth();
    map.AddMapPoint(point);
  }
  SaveMap(map, path);
}

void WriteVocabularySeed(const std::string& path) {
  VocabularyOptions options;
  options.branching = 3;
  options.levels = 2;
  const std::vector<cv::Mat> images = {esdslam::testing::RandomDescriptors(40, 1),
                                       esdslam::testing::RandomDescriptors(40, 2)};
  Vocabulary::Train(images, options).Save(path);
}

}  // namespace esdslam::fuzz
