// LoopCloser in synchronous mode, fed as the system feeds it: the synthetic "loop" trajectory
// (a 0.5 m circle looking outwards, 70 frames per turn: 5.1 deg and 4.5 cm per frame) is tracked,
// each keyframe is indexed for place recognition, locally mapped, then handed to loop closing,
// all on the test's thread after every frame (SlamSystem --single-thread). After 1.3 turns the
// first turn's place is seen again: one loop is closed from the second turn back to the first,
// and afterwards the two keyframes' relative pose is the true one. Without a revisit nothing is
// closed; min_keyframes_between_loops keeps detection off for the keyframes below it.
//
// Tracking runs without the last frame's temporary depth points (TrackerOptions::
// last_frame_depth_points): with them, tracking on this fast turn makes its keyframes too late
// and is lost within the first turn (tests/tracking/tracker_state_test.cpp,
// DISABLED_KeyFrameWhenCloseMapPointsRunLowWithTemporaryDepthPoints).
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "common/error.h"
#include "loop/loop_closer.h"
#include "map/keyframe.h"
#include "mapping/local_mapper.h"
#include "place/place_recognition.h"
#include "support/test_paths.h"
#include "synth/synthetic_scene.h"
#include "tracking/frame.h"
#include "tracking/tracker.h"

namespace esdslam {
namespace {

constexpr int kFramesPerTurn = 70;

// In front of local mapping: indexes each new keyframe for place recognition, then forwards it
// (what the system's PlaceIndexingSink does).
class IndexingSink : public KeyFrameSink {
 public:
  IndexingSink(KeyFrameSink* next, PlaceRecognition* places) : next_(next), places_(places) {}
  bool AcceptsKeyFrames() const override { return next_->AcceptsKeyFrames(); }
  int QueuedKeyFrames() const override { return next_->QueuedKeyFrames(); }
  void InterruptBundleAdjustment() override { next_->InterruptBundleAdjustment(); }
  bool ReserveKeyFrame() override { return next_->ReserveKeyFrame(); }
  void InsertKeyFrame(KeyFrame* keyframe) override {
    places_->AddKeyFrame(keyframe);
    next_->InsertKeyFrame(keyframe);
  }

 private:
  KeyFrameSink* next_;
  PlaceRecognition* places_;
};

SynthOptions LoopScene(double turns) {
  SynthOptions options = SynthPreset("loop");
  options.num_frames = static_cast<int>(std::lround(turns * kFramesPerTurn)) + 1;
  options.loop_turns = (options.num_frames - 1) / static_cast<double>(kFramesPerTurn);  // frame 70 = frame 0
  options.supersampling = 1;  // fast rendering
  return options;
}

// Tracking, local mapping and loop closing over the scene, synchronous (one thread, repeatable).
// Member order is teardown order in reverse: the tracker and sink go first, Finish() closes local
// mapping before loop closing (local mapping feeds it), as SlamSystem::Shutdown does.
class LoopPipeline {
 public:
  LoopPipeline(std::shared_ptr<const Vocabulary> vocabulary, double turns, const LoopClosingOptions& options)
      : scene_(LoopScene(turns)),
        extractor_(OrbOptions{}),
        rig_(MakeRgbdRig(scene_.camera().intrinsics(), 40.0, 40.0, extractor_)),
        places_(std::move(vocabulary)),
        mapper_(&map_, LocalMapperOptions{}, /*threaded=*/false),
        closer_(&map_, &places_, &mapper_, options, /*threaded=*/false),
        sink_(&mapper_, &places_),
        tracker_(&map_, &sink_, [] {
          TrackerOptions tracker_options;
          tracker_options.last_frame_depth_points = false;  // see the file comment
          return tracker_options;
        }()) {
    mapper_.SetDownstream([this](KeyFrame* keyframe) { closer_.InsertKeyFrame(keyframe); });
  }
  ~LoopPipeline() { Finish(); }

  // Tracks every frame; returns how many got a pose.
  int TrackAll() {
    int tracked = 0;
    for (int i = 0; i < scene_.num_frames(); ++i) {
      const SynthFrame image = scene_.RenderFrame(i);
      Frame frame(i, image.timestamp, image.bgr, image.depth_m, cv::Mat(), extractor_, rig_);
      tracked += tracker_.Track(&frame).has_pose;
      mapper_.ProcessQueued();
      closer_.ProcessQueued();
    }
    return tracked;
  }
  void Finish() {
    mapper_.Close();
    closer_.Close();
  }

  // The live keyframe with this id (null when culled or unknown).
  KeyFrame* FindKeyFrame(long id) const {
    for (KeyFrame* keyframe : map_.keyframes())
      if (keyframe->id() == id) return keyframe;
    return nullptr;
  }
  // True cam_a_from_cam_b of two keyframes (from the frames they were made from).
  Rigid3 TrueAFromB(const KeyFrame& a, const KeyFrame& b) const {
    return scene_.WorldFromCam(static_cast<int>(a.frame_id())).inverse() *
           scene_.WorldFromCam(static_cast<int>(b.frame_id()));
  }

  const Map& map() const { return map_; }
  LoopCloser& closer() { return closer_; }
  int num_frames() const { return scene_.num_frames(); }

 private:
  SyntheticScene scene_;
  OrbExtractor extractor_;
  std::shared_ptr<const RgbdRig> rig_;
  Map map_;
  PlaceRecognition places_;
  LocalMapper mapper_;
  LoopCloser closer_;
  IndexingSink sink_;
  Tracker tracker_;
};

class LoopCloserTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    vocabulary_ = std::make_shared<const Vocabulary>(
        Vocabulary::Load(::esdslam::testing::SourceDir() + "/models/vocabulary/orb_vocabulary.bin"));
  }
  static std::shared_ptr<const Vocabulary> vocabulary_;
};

std::shared_ptr<const Vocabulary> LoopCloserTest::vocabulary_;

// 1.3 turns: one loop, from a keyframe of the second turn back to one of the first turn at the
// same place (ground truth), and after the correction and global BA their relative pose is the
// true one. Close() is idempotent and keyframes offered after it are ignored.
TEST_F(LoopCloserTest, ClosesTheRevisitOfTheFirstTurnOnce) {
  LoopPipeline pipeline(vocabulary_, 1.3, LoopClosingOptions{});
  ASSERT_EQ(pipeline.TrackAll(), pipeline.num_frames());
  pipeline.Finish();
  const LoopClosingStats stats = pipeline.closer().stats();
  EXPECT_EQ(stats.keyframes_checked, static_cast<int>(pipeline.map().max_keyframe_id()) + 1);
  EXPECT_EQ(stats.loops_detected, 1);
  ASSERT_EQ(stats.loops_closed, 1);
  ASSERT_EQ(stats.events.size(), 1u);
  EXPECT_EQ(stats.global_ba.completed, 1);
  const LoopEvent& event = stats.events.front();
  EXPECT_GE(event.current_id, LoopClosingOptions{}.min_keyframes_between_loops);
  KeyFrame* current = pipeline.FindKeyFrame(event.current_id);
  KeyFrame* loop = pipeline.FindKeyFrame(event.loop_id);
  ASSERT_NE(current, nullptr);
  ASSERT_NE(loop, nullptr);
  EXPECT_GE(current->frame_id(), kFramesPerTurn) << "the current keyframe is in the second turn";
  EXPECT_LT(loop->frame_id(), kFramesPerTurn) << "the loop keyframe is in the first turn";
  EXPECT_DOUBLE_EQ(event.timestamp, current->timestamp());
  EXPECT_DOUBLE_EQ(event.loop_timestamp, loop->timestamp());
  // The same place: the slow system test's bound for a true revisit (0.3 m, 20 deg).
  const Rigid3 true_current_from_loop = pipeline.TrueAFromB(*current, *loop);
  EXPECT_LT(true_current_from_loop.translation().norm(), 0.3);
  EXPECT_LT(Quat::Identity().angularDistance(true_current_from_loop.rotation()), 20 * M_PI / 180);
  EXPECT_GE(event.inliers, LoopClosingOptions{}.verification.min_refined_inliers);
  EXPECT_GE(event.matches, LoopClosingOptions{}.verification.min_total_matches);
  // The drift the loop removed (0.13 m here) is larger than what is left between the loop's ends.
  EXPECT_GT(event.correction_m, 0.02);
  const Rigid3 current_from_loop = current->cam_from_world() * loop->world_from_cam();
  const Rigid3 error = true_current_from_loop.inverse() * current_from_loop;
  EXPECT_LT(error.translation().norm(), 0.02);
  EXPECT_LT(Quat::Identity().angularDistance(error.rotation()), 0.01);  // rad

  pipeline.closer().Close();  // again: nothing left to do
  pipeline.closer().InsertKeyFrame(current);  // ignored after Close()
  pipeline.closer().ProcessQueued();
  const LoopClosingStats after = pipeline.closer().stats();
  EXPECT_EQ(after.keyframes_checked, stats.keyframes_checked);
  EXPECT_EQ(after.loops_closed, 1);
  EXPECT_EQ(after.global_ba.started, stats.global_ba.started);
}

// 0.8 turn: no place is seen twice; with detection on from keyframe 1, nothing is closed.
TEST_F(LoopCloserTest, ClosesNothingWithoutARevisit) {
  LoopClosingOptions options;
  options.min_keyframes_between_loops = 1;
  LoopPipeline pipeline(vocabulary_, 0.8, options);
  ASSERT_EQ(pipeline.TrackAll(), pipeline.num_frames());
  pipeline.Finish();
  const LoopClosingStats stats = pipeline.closer().stats();
  EXPECT_EQ(stats.keyframes_checked, static_cast<int>(pipeline.map().max_keyframe_id()) + 1);
  EXPECT_GE(stats.keyframes_checked, 8);
  EXPECT_EQ(stats.loops_detected, 0);
  EXPECT_EQ(stats.loops_closed, 0);
  EXPECT_TRUE(stats.events.empty());
  EXPECT_EQ(stats.global_ba.started, 0);
}

// The revisit of ClosesTheRevisitOfTheFirstTurnOnce, with min_keyframes_between_loops above every
// keyframe id of the run: no keyframe reaches detection, so the loop stays open.
TEST_F(LoopCloserTest, NoDetectionBelowMinKeyFramesBetweenLoops) {
  LoopClosingOptions options;
  options.min_keyframes_between_loops = 1000;
  LoopPipeline pipeline(vocabulary_, 1.3, options);
  ASSERT_EQ(pipeline.TrackAll(), pipeline.num_frames());
  pipeline.Finish();
  ASSERT_LT(pipeline.map().max_keyframe_id(), options.min_keyframes_between_loops);
  const LoopClosingStats stats = pipeline.closer().stats();
  EXPECT_EQ(stats.keyframes_checked, static_cast<int>(pipeline.map().max_keyframe_id()) + 1);
  EXPECT_EQ(stats.consistent_candidates, 0);
  EXPECT_EQ(stats.loops_detected, 0);
  EXPECT_EQ(stats.loops_closed, 0);
}

// Each limit just outside its range is rejected, by Check and by the constructor; so is a loop
// closer without place recognition.
TEST_F(LoopCloserTest, RejectsOutOfRangeOptionsAndMissingPlaceRecognition) {
  EXPECT_NO_THROW(LoopClosingOptions{}.Check());
  const std::vector<void (*)(LoopClosingOptions*)> breakers = {
      [](LoopClosingOptions* o) { o->min_keyframes_between_loops = 0; },
      [](LoopClosingOptions* o) { o->consistency_threshold = 0; },
      [](LoopClosingOptions* o) { o->fuse_radius_factor = 0; },
      [](LoopClosingOptions* o) { o->fuse_radius_factor = std::nan(""); },
      [](LoopClosingOptions* o) { o->essential_min_covisibility = 0; },
      [](LoopClosingOptions* o) { o->queue_capacity = 0; },
      [](LoopClosingOptions* o) { o->verification.min_total_matches = 2; },
      [](LoopClosingOptions* o) { o->pose_graph.max_iterations = 0; },
      [](LoopClosingOptions* o) { o->global_ba.iterations = 0; },
  };
  Map map;
  PlaceRecognition places(vocabulary_);
  for (std::size_t k = 0; k < breakers.size(); ++k) {
    LoopClosingOptions options;
    breakers[k](&options);
    EXPECT_THROW(options.Check(), Error) << "case " << k;
    const auto construct = [&map, &places, &options] { LoopCloser closer(&map, &places, nullptr, options, false); };
    EXPECT_THROW(construct(), Error) << "case " << k;
  }
  const auto without_places = [&map] { LoopCloser closer(&map, nullptr, nullptr, LoopClosingOptions{}, false); };
  EXPECT_THROW(without_places(), Error);
  LoopClosingOptions smallest;  // the smallest accepted values
  smallest.min_keyframes_between_loops = smallest.consistency_threshold = 1;
  smallest.essential_min_covisibility = smallest.queue_capacity = 1;
  EXPECT_NO_THROW(smallest.Check());
}

}  // namespace
}  // namespace esdslam
