// Relocalization on the synthetic static scene: a map tracked from the first frames, then a
// frame far from where tracking left off, with no motion model: BoW candidates, PnP RANSAC and
// pose optimisation find its true pose; an unrelated (noise) image is not relocalized.
#include <memory>

#include <gtest/gtest.h>

#include "place/place_recognition.h"
#include "support/test_paths.h"
#include "synth/synthetic_scene.h"
#include "tracking/frame.h"
#include "tracking/relocalizer.h"
#include "tracking/tracker.h"

namespace esdslam {
namespace {

class RelocalizerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    vocabulary_ = std::make_shared<const Vocabulary>(
        Vocabulary::Load(::esdslam::testing::SourceDir() + "/models/vocabulary/orb_vocabulary.bin"));
  }
  static std::shared_ptr<const Vocabulary> vocabulary_;

  RelocalizerTest()
      : scene_([] {
          SynthOptions options = SynthPreset("static");
          options.num_frames = 40;
          options.supersampling = 1;
          return options;
        }()),
        extractor_(OrbOptions{}),
        rig_(MakeRgbdRig(scene_.camera().intrinsics(), 40.0, 40.0, extractor_)),
        places_(vocabulary_),
        tracker_(&map_, nullptr, TrackerOptions{}) {}

  // Tracks frames [0, count) to build the map (keyframes as the tracker decides).
  void BuildMap(int count) {
    for (int i = 0; i < count; ++i) {
      const SynthFrame image = scene_.RenderFrame(i);
      Frame frame(i, image.timestamp, image.bgr, image.depth_m, cv::Mat(), extractor_, rig_);
      ASSERT_TRUE(tracker_.Track(&frame).has_pose) << "frame " << i;
    }
    ASSERT_GE(map_.num_keyframes(), 2);
  }

  std::unique_ptr<Frame> MakeFrame(int index, bool noise = false) {
    SynthFrame image = scene_.RenderFrame(index);
    if (noise) cv::randu(image.bgr, cv::Scalar::all(0), cv::Scalar::all(255));
    return std::make_unique<Frame>(index, image.timestamp, image.bgr, image.depth_m, cv::Mat(), extractor_, rig_);
  }

  SyntheticScene scene_;
  OrbExtractor extractor_;
  std::shared_ptr<const RgbdRig> rig_;
  PlaceRecognition places_;
  Map map_;
  Tracker tracker_;
};

std::shared_ptr<const Vocabulary> RelocalizerTest::vocabulary_;

TEST_F(RelocalizerTest, FindsTheTruePoseOfAFrameAwayFromTheTrack) {
  BuildMap(20);
  Relocalizer relocalizer(&places_);
  std::unique_ptr<Frame> frame = MakeFrame(24);  // not tracked: no motion model, no reference
  RelocalizationStats stats;
  KeyFrame* candidate = relocalizer.Relocalize(frame.get(), TrackerOptions{}.pose, map_.keyframes(), &stats);
  ASSERT_NE(candidate, nullptr) << "candidates " << stats.candidates << ", tried " << stats.tried;
  EXPECT_GE(stats.inliers, 50);
  // The map's world is the first frame's camera: compare to the truth in that frame.
  const Rigid3 world_from_cam0 = scene_.GroundTruth()[0].world_from_cam;
  const Rigid3 truth = world_from_cam0.inverse() * scene_.GroundTruth()[24].world_from_cam;
  const Rigid3 estimate = frame->cam_from_world.inverse();
  EXPECT_LT((estimate.translation() - truth.translation()).norm(), 0.02);
  EXPECT_LT(estimate.rotation().angularDistance(truth.rotation()), 0.01);  // rad
}

TEST_F(RelocalizerTest, DoesNotRelocalizeAnUnrelatedImage) {
  BuildMap(12);
  Relocalizer relocalizer(&places_);
  std::unique_ptr<Frame> frame = MakeFrame(30, /*noise=*/true);
  RelocalizationStats stats;
  EXPECT_EQ(relocalizer.Relocalize(frame.get(), TrackerOptions{}.pose, map_.keyframes(), &stats), nullptr);
  EXPECT_EQ(stats.inliers, 0);
}

}  // namespace
}  // namespace esdslam
