// The Tracker's state machine and keyframe rules on the synthetic static scene (40 frames along
// the 2.6 m-radius arc: 6.7 cm and 1.5 deg per frame), with known answers: initialisation from
// the first frame with enough depth, localization-only tracking, BoW relocalization of a LOST
// frame and the keyframe pause after it, a tracker started in an existing map, the keyframe
// limit max_frames_between_keyframes, and TrackerOptions::Check. The close-points keyframe rule
// is checked on a fast turn of the "loop" trajectory, where it decides when keyframes come.
//
// Keyframes go to a sink that stands in for local mapping's insertion step (observations,
// covisibility), so map points gain the observations the keyframe decision counts; without it
// (sink = null) every point keeps the one observation of the keyframe that created it.
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "common/error.h"
#include "map/keyframe.h"
#include "map/map_point.h"
#include "place/place_recognition.h"
#include "support/test_paths.h"
#include "synth/synthetic_scene.h"
#include "tracking/frame.h"
#include "tracking/relocalizer.h"
#include "tracking/tracker.h"

namespace esdslam {
namespace {

// What local mapping's insertion step does to a keyframe from tracking, synchronously: each
// point it holds gains the keyframe's observation, the covisibility graph is updated and the
// keyframe joins the map. No point creation, fusion, BA or culling. Always idle.
class ObservingSink : public KeyFrameSink {
 public:
  explicit ObservingSink(Map* map) : map_(map) {}
  bool AcceptsKeyFrames() const override { return true; }
  int QueuedKeyFrames() const override { return 0; }
  void InterruptBundleAdjustment() override {}
  void InsertKeyFrame(KeyFrame* keyframe) override {
    const std::vector<MapPoint*> points = keyframe->map_points();  // indexed by keypoint
    for (int i = 0; i < static_cast<int>(points.size()); ++i) {
      MapPoint* point = points[i];
      if (point == nullptr || point->is_bad() || point->IsObservedBy(keyframe)) continue;
      point->AddObservation(keyframe, i, keyframe->features().has_depth(i));
      point->UpdateNormalAndDepth();
      point->ComputeDistinctiveDescriptor();
    }
    keyframe->UpdateConnections();
    map_->AddKeyFrame(keyframe);
  }

 private:
  Map* map_;
};

class TrackerStateTest : public ::testing::Test {
 protected:
  static constexpr int kNumFrames = 40;

  static void SetUpTestSuite() {
    vocabulary_ = std::make_shared<const Vocabulary>(
        Vocabulary::Load(::esdslam::testing::SourceDir() + "/models/vocabulary/orb_vocabulary.bin"));
  }
  static std::shared_ptr<const Vocabulary> vocabulary_;

  TrackerStateTest()
      : scene_([] {
          SynthOptions options = SynthPreset("static");
          options.num_frames = kNumFrames;
          options.supersampling = 1;  // fast rendering
          return options;
        }()),
        extractor_(OrbOptions{}),
        rig_(MakeRgbdRig(scene_.camera().intrinsics(), 40.0, 40.0, extractor_)),
        sink_(&map_) {}

  // Frame `index` of the sequence with id `index`; `noise` replaces the colour image by noise.
  std::unique_ptr<Frame> MakeFrame(int index, bool noise = false) const {
    SynthFrame image = scene_.RenderFrame(index);
    if (noise) cv::randu(image.bgr, cv::Scalar::all(0), cv::Scalar::all(255));
    return std::make_unique<Frame>(index, image.timestamp, image.bgr, image.depth_m, cv::Mat(), extractor_, rig_);
  }

  TrackingResult Track(Tracker* tracker, int index, bool noise = false) const {
    std::unique_ptr<Frame> frame = MakeFrame(index, noise);
    return tracker->Track(frame.get());
  }

  // Tracks frames [first, end) and returns the indices of the frames that made a keyframe.
  std::vector<int> TrackRange(Tracker* tracker, int first, int end) const {
    std::vector<int> keyframe_frames;
    for (int i = first; i < end; ++i) {
      const TrackingResult result = Track(tracker, i);
      EXPECT_EQ(result.state, TrackingState::kOk) << "frame " << i;
      if (result.new_keyframe != nullptr) keyframe_frames.push_back(i);
    }
    return keyframe_frames;
  }

  // The true cam_from_world of frame `index` in the map's world (the first frame's camera).
  Rigid3 TrueCamFromMap(int index) const {
    const Rigid3 world_from_cam0 = scene_.WorldFromCam(0);
    return (world_from_cam0.inverse() * scene_.WorldFromCam(index)).inverse();
  }

  // Position error (m) and rotation error (rad) of an estimated cam_from_world against frame `index`.
  std::pair<double, double> PoseError(const Rigid3& cam_from_world, int index) const {
    const Rigid3 estimate = cam_from_world.inverse(), truth = TrueCamFromMap(index).inverse();
    return {(estimate.translation() - truth.translation()).norm(), estimate.rotation().angularDistance(truth.rotation())};
  }

  SyntheticScene scene_;
  OrbExtractor extractor_;
  std::shared_ptr<const RgbdRig> rig_;
  Map map_;
  ObservingSink sink_;
};

std::shared_ptr<const Vocabulary> TrackerStateTest::vocabulary_;

// Keypoints with depth and not dynamic: those the map is initialised from.
int UsableDepthKeypoints(const Frame& frame) {
  int usable = 0;
  for (int i = 0; i < frame.size(); ++i) usable += frame.features().has_depth(i) && !frame.features().is_dynamic[i];
  return usable;
}

TEST_F(TrackerStateTest, FirstFrameWithEnoughDepthMakesTheMapOfOneKeyFrame) {
  Tracker tracker(&map_, &sink_, TrackerOptions{});
  EXPECT_EQ(tracker.state(), TrackingState::kNotInitialized);
  std::unique_ptr<Frame> frame = MakeFrame(0);
  const int usable = UsableDepthKeypoints(*frame);
  ASSERT_GT(usable, TrackerOptions{}.min_initial_depth_keypoints);
  const TrackingResult result = tracker.Track(frame.get());
  EXPECT_EQ(result.state, TrackingState::kOk);
  EXPECT_EQ(tracker.state(), TrackingState::kOk);
  ASSERT_TRUE(result.has_pose);
  EXPECT_TRUE(result.cam_from_world.matrix().isIdentity(0.0));  // the first camera is the world
  ASSERT_NE(result.new_keyframe, nullptr);
  EXPECT_EQ(result.reference_keyframe, result.new_keyframe);
  EXPECT_EQ(result.new_keyframe->frame_id(), 0);
  EXPECT_EQ(map_.num_keyframes(), 1);
  // One point per usable keypoint, at its back-projected depth, held by the keyframe.
  EXPECT_EQ(map_.num_map_points(), usable);
  EXPECT_EQ(static_cast<int>(result.new_keyframe->valid_map_points().size()), usable);
  EXPECT_EQ(result.inliers, usable);
  for (int i = 0; i < frame->size(); ++i) {
    MapPoint* point = result.new_keyframe->map_point(i);
    if (!frame->features().has_depth(i)) {
      EXPECT_EQ(point, nullptr) << "keypoint " << i;
      continue;
    }
    ASSERT_NE(point, nullptr) << "keypoint " << i;
    EXPECT_LT((point->position() - frame->features().BackprojectCam(i)).norm(), 1e-9) << "keypoint " << i;
  }
}

// Initialisation needs more than min_initial_depth_keypoints usable keypoints (strictly).
TEST_F(TrackerStateTest, InitialisationNeedsMoreThanMinInitialDepthKeypoints) {
  const int usable = UsableDepthKeypoints(*MakeFrame(0));
  TrackerOptions options;
  options.min_initial_depth_keypoints = usable;
  Tracker strict(&map_, &sink_, options);
  const TrackingResult refused = Track(&strict, 0);
  EXPECT_EQ(refused.state, TrackingState::kNotInitialized);
  EXPECT_FALSE(refused.has_pose);
  EXPECT_EQ(refused.new_keyframe, nullptr);
  EXPECT_EQ(map_.num_keyframes(), 0);
  EXPECT_EQ(map_.num_map_points(), 0);

  options.min_initial_depth_keypoints = usable - 1;
  Tracker tracker(&map_, &sink_, options);
  EXPECT_EQ(Track(&tracker, 0).state, TrackingState::kOk);
  EXPECT_EQ(map_.num_keyframes(), 1);
}

// Localization only: the map keeps its one keyframe while every frame is tracked; the same
// frames make keyframes in a normal run.
TEST_F(TrackerStateTest, LocalizationOnlyTracksWithoutCreatingKeyFrames) {
  constexpr int kFrames = 20;
  TrackerOptions options;
  options.localization_only = true;
  Tracker localizer(&map_, &sink_, options);
  ASSERT_EQ(Track(&localizer, 0).state, TrackingState::kOk);  // initialisation still makes the map
  EXPECT_TRUE(TrackRange(&localizer, 1, kFrames).empty());
  EXPECT_EQ(localizer.state(), TrackingState::kOk);
  EXPECT_EQ(map_.num_keyframes(), 1);
  const int points = map_.num_map_points();

  Map mapping_map;
  ObservingSink mapping_sink(&mapping_map);
  Tracker mapping(&mapping_map, &mapping_sink, TrackerOptions{});
  ASSERT_EQ(Track(&mapping, 0).state, TrackingState::kOk);
  EXPECT_FALSE(TrackRange(&mapping, 1, kFrames).empty());
  EXPECT_GT(mapping_map.num_map_points(), points);
}

// A noise image makes tracking LOST (no pose, no relocalization); the next frame, 6 frames after
// the last tracked one (0.4 m and about 9 deg further along the arc), is relocalized through BoW
// to its true pose (the relocalizer test's bound: 2 cm, 0.01 rad); for max_frames_between_keyframes
// frames (ids) after it no keyframe is made, and then keyframes resume at once (mapping is idle
// and min_frames_between_keyframes is 0).
TEST_F(TrackerStateTest, LostFrameFarAlongIsRelocalizedAndKeyFramesPauseAfterIt) {
  TrackerOptions options;
  options.max_frames_between_keyframes = 8;  // the pause after a relocalization, frames
  Tracker tracker(&map_, &sink_, options);
  PlaceRecognition places(vocabulary_);
  Relocalizer relocalizer(&places);
  tracker.set_relocalizer(&relocalizer);
  ASSERT_EQ(Track(&tracker, 0).state, TrackingState::kOk);
  ASSERT_FALSE(TrackRange(&tracker, 1, 19).empty());
  const int keyframes_before = map_.num_keyframes();

  const TrackingResult lost = Track(&tracker, 19, /*noise=*/true);
  EXPECT_EQ(lost.state, TrackingState::kLost);
  EXPECT_FALSE(lost.has_pose);
  EXPECT_EQ(tracker.relocalizations(), 0);

  const int relocalized_index = 24;
  const TrackingResult relocalized = Track(&tracker, relocalized_index);
  ASSERT_EQ(relocalized.state, TrackingState::kOk);
  ASSERT_TRUE(relocalized.has_pose);
  EXPECT_EQ(tracker.relocalizations(), 1);
  EXPECT_EQ(relocalized.new_keyframe, nullptr);
  EXPECT_GE(relocalized.inliers, options.relocalized_min_inliers);
  const auto [position_error_m, rotation_error_rad] = PoseError(relocalized.cam_from_world, relocalized_index);
  EXPECT_LT(position_error_m, 0.02);
  EXPECT_LT(rotation_error_rad, 0.01);

  const int pause_end = relocalized_index + options.max_frames_between_keyframes;  // first id allowed again
  EXPECT_TRUE(TrackRange(&tracker, relocalized_index + 1, pause_end).empty());
  EXPECT_EQ(map_.num_keyframes(), keyframes_before);
  const std::vector<int> after = TrackRange(&tracker, pause_end, pause_end + 4);
  ASSERT_FALSE(after.empty());
  EXPECT_EQ(after.front(), pause_end);
  EXPECT_EQ(tracker.relocalizations(), 1);  // tracked frames are not relocalized again
}

// A blocked sensor (black image, no depth: no keypoint at all) after OK tracking: the blind
// frames get the constant-velocity prediction as their pose, make no keyframe and stay OK; the
// next real frame is tracked without a relocalization. Past max_coasted_frames the frame is LOST.
TEST_F(TrackerStateTest, BlindFramesCoastOnTheMotionModelAndTrackingResumes) {
  const auto blind_frame = [this](int index) {
    SynthFrame image = scene_.RenderFrame(index);
    image.bgr.setTo(cv::Scalar::all(0));
    image.depth_m.setTo(0.0f);
    return std::make_unique<Frame>(index, image.timestamp, image.bgr, image.depth_m, cv::Mat(), extractor_, rig_);
  };
  TrackerOptions options;
  options.max_coasted_frames = 3;
  Tracker tracker(&map_, &sink_, options);
  ASSERT_EQ(Track(&tracker, 0).state, TrackingState::kOk);
  TrackRange(&tracker, 1, 14);
  const Rigid3 before_last = tracker.last_frame().cam_from_world;
  const Rigid3 last = Track(&tracker, 14).cam_from_world;
  const Rigid3 velocity = last * before_last.inverse();  // cam_14 from cam_13
  Rigid3 predicted = last;
  const int keyframes_before = map_.num_keyframes();
  for (int i = 15; i < 18; ++i) {
    std::unique_ptr<Frame> frame = blind_frame(i);
    ASSERT_EQ(frame->size(), 0);
    const TrackingResult coasted = tracker.Track(frame.get());
    EXPECT_EQ(coasted.state, TrackingState::kOk) << i;
    ASSERT_TRUE(coasted.has_pose) << i;
    EXPECT_TRUE(coasted.coasted) << i;
    EXPECT_EQ(coasted.inliers, 0);
    EXPECT_EQ(coasted.new_keyframe, nullptr);
    predicted = velocity * predicted;  // constant velocity from the last two tracked frames
    EXPECT_LT((coasted.cam_from_world.translation() - predicted.translation()).norm(), 1e-9) << i;
    EXPECT_LT(coasted.cam_from_world.rotation().angularDistance(predicted.rotation()), 1e-9) << i;
  }
  EXPECT_EQ(map_.num_keyframes(), keyframes_before);
  const TrackingResult resumed = Track(&tracker, 18);
  ASSERT_EQ(resumed.state, TrackingState::kOk);
  EXPECT_FALSE(resumed.coasted);
  EXPECT_EQ(tracker.relocalizations(), 0);
  EXPECT_LT(PoseError(resumed.cam_from_world, 18).first, 0.02);

  TrackRange(&tracker, 19, 22);
  for (int i = 22; i < 25; ++i) EXPECT_TRUE(tracker.Track(blind_frame(i).get()).coasted) << i;
  const TrackingResult fourth = tracker.Track(blind_frame(25).get());
  EXPECT_EQ(fourth.state, TrackingState::kLost);
  EXPECT_FALSE(fourth.has_pose);
  EXPECT_FALSE(fourth.coasted);
}

// A tracker started in an existing map is LOST from the start: it never makes a map of its own;
// without a relocalizer it finds no pose, with one the first frame is located in the old map.
TEST_F(TrackerStateTest, StartInExistingMapIsLostUntilRelocalizedInThatMap) {
  Tracker builder(&map_, &sink_, TrackerOptions{});
  ASSERT_EQ(Track(&builder, 0).state, TrackingState::kOk);
  TrackRange(&builder, 1, 16);
  const int keyframes = map_.num_keyframes(), points = map_.num_map_points();

  Tracker tracker(&map_, &sink_, TrackerOptions{});
  tracker.StartInExistingMap();
  EXPECT_EQ(tracker.state(), TrackingState::kLost);
  const TrackingResult unlocated = Track(&tracker, 10);
  EXPECT_EQ(unlocated.state, TrackingState::kLost);
  EXPECT_FALSE(unlocated.has_pose);
  EXPECT_EQ(map_.num_keyframes(), keyframes);
  EXPECT_EQ(map_.num_map_points(), points);

  PlaceRecognition places(vocabulary_);
  Relocalizer relocalizer(&places);
  tracker.set_relocalizer(&relocalizer);
  const TrackingResult located = Track(&tracker, 10);
  ASSERT_EQ(located.state, TrackingState::kOk);
  ASSERT_TRUE(located.has_pose);
  EXPECT_EQ(tracker.relocalizations(), 1);
  const auto [position_error_m, rotation_error_rad] = PoseError(located.cam_from_world, 10);
  EXPECT_LT(position_error_m, 0.02);
  EXPECT_LT(rotation_error_rad, 0.01);
  EXPECT_EQ(Track(&tracker, 11).state, TrackingState::kOk);  // tracking goes on from there
}

// With min_frames_between_keyframes out of reach, a keyframe comes at the latest
// max_frames_between_keyframes frames after the previous one on the moving camera (here: exactly
// then, tracking never weakens enough to ask for one earlier).
TEST_F(TrackerStateTest, KeyFrameAtTheLatestAfterMaxFramesBetweenKeyFrames) {
  TrackerOptions options;
  options.max_frames_between_keyframes = 8;
  options.min_frames_between_keyframes = 1000;
  Tracker tracker(&map_, &sink_, options);
  std::vector<int> keyframe_frames = {0};
  ASSERT_NE(Track(&tracker, 0).new_keyframe, nullptr);
  for (int i : TrackRange(&tracker, 1, kNumFrames)) keyframe_frames.push_back(i);
  keyframe_frames.push_back(kNumFrames);  // the gap to the end counts too
  for (std::size_t k = 1; k < keyframe_frames.size(); ++k)
    EXPECT_LE(keyframe_frames[k] - keyframe_frames[k - 1], options.max_frames_between_keyframes)
        << "keyframes at frames " << keyframe_frames[k - 1] << " and " << keyframe_frames[k];
  EXPECT_EQ(map_.num_keyframes(), static_cast<int>(keyframe_frames.size()) - 1);
}

// ORB-SLAM2's RGB-D "need close" rule: a tracked frame that holds fewer than 100 close map points
// (depth < th_depth, points with map observations) and sees more than 70 close keypoints without
// one asks for a keyframe; with local mapping idle and min_frames_between_keyframes 0 it gets one.
// Tracks the first kFrames frames of the "loop" trajectory at 70 frames per turn (5.1 deg per
// frame: the view changes fast, so the rule decides) and returns the frames that broke the rule.
std::vector<int> FramesMissingACloseKeyFrame(const OrbExtractor& extractor, const std::shared_ptr<const RgbdRig>& rig,
                                             const TrackerOptions& options) {
  constexpr int kFrames = 35, kFramesPerTurn = 70;
  SynthOptions scene_options = SynthPreset("loop");
  scene_options.num_frames = kFrames;
  scene_options.loop_turns = (kFrames - 1) / static_cast<double>(kFramesPerTurn);
  scene_options.supersampling = 1;
  const SyntheticScene scene(scene_options);
  Map map;
  ObservingSink sink(&map);
  Tracker tracker(&map, &sink, options);
  std::vector<int> broken;
  for (int i = 0; i < kFrames; ++i) {
    const SynthFrame image = scene.RenderFrame(i);
    Frame frame(i, image.timestamp, image.bgr, image.depth_m, cv::Mat(), extractor, rig);
    const TrackingResult result = tracker.Track(&frame);
    EXPECT_TRUE(result.has_pose) << "frame " << i;
    if (!result.has_pose || result.new_keyframe != nullptr) continue;
    // After Track the frame holds its inlier map points only (temporary depth points dropped).
    int tracked_close = 0, untracked_close = 0;
    for (int k = 0; k < frame.size(); ++k) {
      if (!frame.features().is_close(k)) continue;
      (frame.map_points[k] != nullptr ? tracked_close : untracked_close) += 1;
    }
    if (tracked_close < 100 && untracked_close > 70 && result.inliers > 15) broken.push_back(i);
  }
  return broken;
}

TEST_F(TrackerStateTest, KeyFrameWhenCloseMapPointsRunLowWithoutTemporaryDepthPoints) {
  TrackerOptions options;
  options.last_frame_depth_points = false;
  EXPECT_EQ(FramesMissingACloseKeyFrame(extractor_, rig_, options), std::vector<int>{});
}

// Fails today (6 of the 35 frames break the rule; the last one is lost): NeedNewKeyFrame runs
// before Finish() drops the last frame's temporary depth points from the frame, so it counts them
// as tracked close points and the keyframe comes too late; ORB-SLAM2 drops them ("clean VO
// matches") before the decision. Counting only points with map observations makes it pass, but
// was not kept (2026-12-06, single-thread runs, ATE before -> after): loop preset 0.014 -> 0.031 m
// (full) and 0.024 -> 0.031 (none), corridor none 0.0081 -> 0.0105, fr1_rpy none 0.0241 -> 0.0244,
// Bonn full unchanged, corridor full 0.0081 -> 0.0044, fr1 full 0.0264 -> 0.0251: more keyframes,
// not better on balance. Enable with a keyframe rule that is better on the presets and both windows.
TEST_F(TrackerStateTest, DISABLED_KeyFrameWhenCloseMapPointsRunLowWithTemporaryDepthPoints) {
  TrackerOptions options;
  options.last_frame_depth_points = true;
  EXPECT_EQ(FramesMissingACloseKeyFrame(extractor_, rig_, options), std::vector<int>{});
}

// Each limit just outside its range is rejected, by Check and by the Tracker's constructor.
TEST(TrackerOptionsTest, CheckRejectsOutOfRangeValues) {
  EXPECT_NO_THROW(TrackerOptions{}.Check());
  const std::vector<void (*)(TrackerOptions*)> breakers = {
      [](TrackerOptions* o) { o->min_initial_depth_keypoints = 0; },
      [](TrackerOptions* o) { o->max_frames_between_keyframes = 0; },
      [](TrackerOptions* o) { o->min_frames_between_keyframes = -1; },
      [](TrackerOptions* o) { o->motion_search_radius_px = 0; },
      [](TrackerOptions* o) { o->local_search_radius_factor = -1; },
      [](TrackerOptions* o) { o->min_local_map_inliers = 2; },
      [](TrackerOptions* o) { o->min_pose_matches = 2; },
      [](TrackerOptions* o) { o->relocalized_min_inliers = 2; },
      [](TrackerOptions* o) { o->relocalized_search_radius_factor = 0; },
      [](TrackerOptions* o) { o->motion_search_radius_px = std::nan(""); },
      [](TrackerOptions* o) { o->pose.rounds = 0; },
      [](TrackerOptions* o) { o->min_motion_matches = 2; },
      [](TrackerOptions* o) { o->max_local_keyframes = 0; },
      [](TrackerOptions* o) { o->max_depth_points = -1; },
  };
  Map map;
  for (std::size_t k = 0; k < breakers.size(); ++k) {
    TrackerOptions options;
    breakers[k](&options);
    EXPECT_THROW(options.Check(), Error) << "case " << k;
    const auto construct = [&map, &options] { Tracker tracker(&map, nullptr, options); };
    EXPECT_THROW(construct(), Error) << "case " << k;
  }
  TrackerOptions boundary;  // the smallest accepted values
  boundary.min_initial_depth_keypoints = 1;
  boundary.max_frames_between_keyframes = 1;
  boundary.min_local_map_inliers = boundary.min_pose_matches = boundary.relocalized_min_inliers = 3;
  boundary.min_motion_matches = 3;
  boundary.max_local_keyframes = 1;
  boundary.max_depth_points = 0;
  EXPECT_NO_THROW(boundary.Check());
}

}  // namespace
}  // namespace esdslam
