// Place recognition and BoW direct-index matching on the synthetic static room (real ORB
// features of rendered images, the shipped vocabulary).
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "feature/orb_extractor.h"
#include "place/bow_matcher.h"
#include "place/place_recognition.h"
#include "map/keyframe.h"
#include "map/map.h"
#include "synth/synthetic_scene.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

const std::string kVocabularyPath = ::esdslam::testing::SourceDir() + "/models/vocabulary/orb_vocabulary.bin";

std::shared_ptr<const FeatureSet> Features(const cv::Mat& bgr, const OrbExtractor& extractor,
                                           const std::shared_ptr<const RgbdRig>& rig) {
  auto features = std::make_shared<FeatureSet>();
  features->rig = rig;
  cv::Mat gray;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  extractor.Extract(gray, cv::Mat(), &features->keypoints, &features->descriptors);
  for (const cv::KeyPoint& keypoint : features->keypoints) features->undistorted.push_back(keypoint.pt);
  features->depth.assign(features->keypoints.size(), 0.f);
  features->right_u.assign(features->keypoints.size(), -1.f);
  features->is_dynamic.assign(features->keypoints.size(), 0);
  return features;
}

class PlaceRecognitionTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { vocabulary_ = std::make_shared<const Vocabulary>(Vocabulary::Load(kVocabularyPath)); }
  PlaceRecognitionTest() : scene_(SynthPreset("static")), extractor_(OrbOptions{}) {
    auto rig = std::make_shared<RgbdRig>();
    rig->camera = scene_.camera();
    rig_ = rig;
  }
  std::shared_ptr<const FeatureSet> FrameFeatures(int index) const {
    return Features(scene_.RenderFrame(index).bgr, extractor_, rig_);
  }

  static std::shared_ptr<const Vocabulary> vocabulary_;
  SyntheticScene scene_;
  OrbExtractor extractor_;
  std::shared_ptr<const RgbdRig> rig_;
};
std::shared_ptr<const Vocabulary> PlaceRecognitionTest::vocabulary_;

TEST(OrientationOutliersTest, KeepsTheThreeDominantBinsOnly) {
  std::vector<std::pair<float, int>> rotations;
  int id = 0;
  for (int k = 0; k < 20; ++k) rotations.emplace_back(1.f, id++);    // bin 0 (ids 0..19)
  for (int k = 0; k < 10; ++k) rotations.emplace_back(-2.f, id++);   // 358 deg -> bin 0 (20..29)
  for (int k = 0; k < 5; ++k) rotations.emplace_back(31.f, id++);    // bin 1 (30..34)
  for (int k = 0; k < 4; ++k) rotations.emplace_back(185.f, id++);   // bin 6 (35..38)
  rotations.emplace_back(95.f, id++);                                // bin 3 (39): 4th largest
  rotations.emplace_back(-240.f, id++);                              // 120 deg -> bin 4 (40)
  const std::vector<int> outliers = OrientationOutliers(rotations);
  EXPECT_EQ(outliers, (std::vector<int>{39, 40}));
  // A second bin below 10% of the first is dropped too.
  std::vector<std::pair<float, int>> skewed;
  for (int k = 0; k < 50; ++k) skewed.emplace_back(0.f, k);
  for (int k = 0; k < 4; ++k) skewed.emplace_back(60.f, 50 + k);
  EXPECT_EQ(OrientationOutliers(skewed), (std::vector<int>{50, 51, 52, 53}));
}

TEST_F(PlaceRecognitionTest, DirectIndexMatchingFindsTheShiftedKeypoints) {
  const cv::Mat bgr = scene_.RenderFrame(0).bgr;
  cv::Mat shifted;
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 12, 0, 1, -7);  // +12 px in u, -7 px in v
  cv::warpAffine(bgr, shifted, shift, bgr.size());
  PlaceRecognition places(vocabulary_);
  const auto train = Features(bgr, extractor_, rig_);
  const auto query = Features(shifted, extractor_, rig_);
  const ImageBow train_bow = places.Compute(*train), query_bow = places.Compute(*query);
  const std::vector<int> query_to_train =
      MatchByDirectIndex(*train, train_bow.direct_index, {}, *query, query_bow.direct_index, {}, BowMatchOptions{});
  int matches = 0, correct = 0;
  std::vector<int> used(train->size(), 0);
  for (int q = 0; q < query->size(); ++q) {
    const int t = query_to_train[q];
    if (t < 0) continue;
    ++matches;
    ++used[t];
    const cv::Point2f expected = train->keypoints[t].pt + cv::Point2f(12, -7);
    correct += cv::norm(query->keypoints[q].pt - expected) < 3.0;  // px
  }
  std::printf("direct-index matches: %d of %d keypoints, %d correct\n", matches, query->size(), correct);
  EXPECT_GE(matches, query->size() / 3);
  EXPECT_GE(correct, 0.95 * matches);
  for (int count : used) EXPECT_LE(count, 1);
}

TEST_F(PlaceRecognitionTest, RelocalizationCandidateIsTheNearestKeyFrameInTime) {
  Map map;
  PlaceRecognition places(vocabulary_);
  std::vector<KeyFrame*> keyframes;
  for (int index = 0; index < scene_.num_frames(); index += 60) {
    KeyFrame* keyframe = map.CreateKeyFrame(index, index, FrameFeatures(index), Rigid3::Identity());
    map.AddKeyFrame(keyframe);
    places.AddKeyFrame(keyframe);
    keyframes.push_back(keyframe);
  }
  ASSERT_GE(keyframes.size(), 3u);
  EXPECT_EQ(places.size(), keyframes.size());
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    const int query_index = static_cast<int>(k) * 60 + 3;
    if (query_index >= scene_.num_frames()) break;
    const std::vector<KeyFrame*> candidates = places.RelocalizationCandidates(places.Compute(*FrameFeatures(query_index)));
    ASSERT_FALSE(candidates.empty()) << "query " << query_index;
    EXPECT_EQ(candidates.front(), keyframes[k]) << "query " << query_index;
  }
  // A culled keyframe is never returned again.
  keyframes[1]->SetBad();
  const auto after_cull = places.RelocalizationCandidates(places.Compute(*FrameFeatures(63)));
  for (KeyFrame* candidate : after_cull) EXPECT_NE(candidate, keyframes[1]);
  EXPECT_EQ(places.size(), keyframes.size() - 1);
}

}  // namespace
}  // namespace esdslam
