// Geometric verification of loop candidates on rendered views of the synthetic room: a keyframe
// whose map drifted (its pose and points shifted by a known transform) is verified against a
// keyframe of the same place, and the corrected pose is the true one; an unrelated view fails.
#include "loop/loop_verification.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "feature/orb_extractor.h"
#include "map/map.h"
#include "synth/synthetic_scene.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

const std::string kVocabularyPath = ::esdslam::testing::SourceDir() + "/models/vocabulary/orb_vocabulary.bin";

class LoopVerificationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { vocabulary_ = std::make_shared<const Vocabulary>(Vocabulary::Load(kVocabularyPath)); }

  LoopVerificationTest() : scene_([] {
    SynthOptions options = SynthPreset("static");
    options.supersampling = 1;
    return options;
  }()), extractor_(OrbOptions{}) {
    auto rig = std::make_shared<RgbdRig>();
    rig->camera = scene_.camera();
    rig->bf = 40.0;
    rig->th_depth_m = 40.0 * 40.0 / scene_.camera().fx();
    rig->pyramid.num_levels = extractor_.num_levels();
    rig->pyramid.scale_factor = 1.2;
    rig->pyramid.log_scale_factor = std::log(1.2);
    rig->pyramid.scale_factors = extractor_.scale_factors();
    rig->pyramid.level_sigma2 = extractor_.level_sigma2();
    rig->pyramid.inv_level_sigma2 = extractor_.inv_level_sigma2();
    rig_ = rig;
  }

  // A keyframe of the rendered view at `true_world_from_cam`, placed in the map at
  // map_from_world * true pose, with one map point per keypoint with depth.
  KeyFrame* MakeKeyFrame(const Rigid3& true_world_from_cam, const Rigid3& map_from_world) {
    const SynthFrame frame = scene_.Render(true_world_from_cam, 0.0, 1);
    auto features = std::make_shared<FeatureSet>();
    features->rig = rig_;
    cv::Mat gray;
    cv::cvtColor(frame.bgr, gray, cv::COLOR_BGR2GRAY);
    extractor_.Extract(gray, cv::Mat(), &features->keypoints, &features->descriptors);
    std::vector<int> levels;
    for (const cv::KeyPoint& keypoint : features->keypoints) {
      features->undistorted.push_back(keypoint.pt);
      const float z = frame.depth_m.at<float>(cvRound(keypoint.pt.y), cvRound(keypoint.pt.x));
      features->depth.push_back(z);
      features->right_u.push_back(z > 0 ? keypoint.pt.x - static_cast<float>(rig_->bf / z) : -1.f);
      features->is_dynamic.push_back(0);
      levels.push_back(keypoint.octave);
    }
    const PinholeCamera& camera = rig_->camera;
    features->grid = std::make_unique<FeatureGrid>(features->undistorted, levels, camera.min_u(), camera.max_u(),
                                                   camera.min_v(), camera.max_v());
    const Rigid3 map_from_cam = map_from_world * true_world_from_cam;
    KeyFrame* keyframe = map_.CreateKeyFrame(next_id_, next_id_, features, map_from_cam.inverse());
    ++next_id_;
    map_.AddKeyFrame(keyframe);
    for (int i = 0; i < features->size(); ++i) {
      if (!features->has_depth(i)) continue;
      MapPoint* point = map_.CreateMapPoint(map_from_cam * features->BackprojectCam(i), keyframe);
      point->AddObservation(keyframe, i, true);
      keyframe->AddMapPoint(point, i);
      point->ComputeDistinctiveDescriptor();
      point->UpdateNormalAndDepth();
      map_.AddMapPoint(point);
    }
    return keyframe;
  }

  static std::shared_ptr<const Vocabulary> vocabulary_;
  SyntheticScene scene_;
  OrbExtractor extractor_;
  std::shared_ptr<const RgbdRig> rig_;
  Map map_;
  long next_id_ = 0;
};
std::shared_ptr<const Vocabulary> LoopVerificationTest::vocabulary_;

TEST_F(LoopVerificationTest, RecoversTheDriftOfARevisitedPlace) {
  PlaceRecognition places(vocabulary_);
  const Rigid3 world_from_a = scene_.WorldFromCam(0);
  const Rigid3 world_from_b = scene_.WorldFromCam(12);  // 5 cm and a few degrees further
  const Rigid3 drift(ExpSO3(Vec3(0.0, 0.0, 0.05)), Vec3(0.15, -0.08, 0.03));  // map_from_world of the drifted side
  KeyFrame* loop = MakeKeyFrame(world_from_a, Rigid3());
  KeyFrame* current = MakeKeyFrame(world_from_b, drift);
  places.AddKeyFrame(loop);
  places.AddKeyFrame(current);
  LoopMatch match;
  ASSERT_TRUE(VerifyLoopCandidate(current, loop, places, LoopVerificationOptions{}, 1, &match))
      << match.bow_matches << " BoW, " << match.ransac_inliers << " RANSAC, " << match.refined_inliers << " refined, "
      << match.total_matches << " total";
  const Rigid3 truth = world_from_b.inverse();
  EXPECT_LT((match.corrected_cam_from_world.inverse().translation() - world_from_b.translation()).norm(), 0.01);
  EXPECT_LT(RotationAngle(match.corrected_cam_from_world.rotation() * truth.rotation().conjugate()), 0.2 * M_PI / 180);
  EXPECT_GE(match.refined_inliers, 100);
  EXPECT_GE(match.total_matches, match.refined_inliers);
  int on_loop_keyframe = 0;
  for (MapPoint* point : match.matched_points) on_loop_keyframe += point != nullptr && point->IsObservedBy(loop);
  EXPECT_EQ(on_loop_keyframe, match.total_matches);  // no covisible keyframes: all loop points are its own
}

TEST_F(LoopVerificationTest, RejectsAnUnrelatedView) {
  PlaceRecognition places(vocabulary_);
  const Rigid3 world_from_a = scene_.WorldFromCam(0);
  // The same position looking the other way.
  const Rigid3 world_from_b = world_from_a * Rigid3(ExpSO3(Vec3(0, M_PI, 0)), Vec3::Zero());
  KeyFrame* loop = MakeKeyFrame(world_from_a, Rigid3());
  KeyFrame* current = MakeKeyFrame(world_from_b, Rigid3());
  places.AddKeyFrame(loop);
  places.AddKeyFrame(current);
  LoopMatch match;
  EXPECT_FALSE(VerifyLoopCandidate(current, loop, places, LoopVerificationOptions{}, 1, &match))
      << match.bow_matches << " BoW, " << match.ransac_inliers << " RANSAC, " << match.refined_inliers << " refined";
}

}  // namespace
}  // namespace esdslam
