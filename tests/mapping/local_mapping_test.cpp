// Local mapping steps on small hand-built maps with known geometry.
#include <gtest/gtest.h>

#include "map/core_test_scene.h"
#include "map/keyframe.h"
#include "map/map.h"
#include "map/map_point.h"
#include "mapping/local_mapper.h"
#include "mapping/mapping_steps.h"

namespace esdslam {
namespace {

using Scene = testing::LandmarkScene;

TEST(LocalMappingTest, RecentPointCullingFollowsFoundRatioAndObservations) {
  Scene scene(50, 4, 0.1, true);
  MapPoint* rarely_found = scene.AddPoint(0, {0, 1});
  rarely_found->IncreaseVisible(10);  // found 1 / visible 11
  MapPoint* single_view = scene.AddPoint(1, {0});  // 2 weighted observations (one view with depth)
  MapPoint* two_views = scene.AddPoint(2, {0, 1});  // 4 weighted observations
  MapPoint* young_single = scene.AddPoint(3, {2});  // first keyframe 2
  std::vector<MapPoint*> recent{rarely_found, single_view, two_views, young_single};
  const int culled = CullRecentMapPoints(*scene.keyframes[2], RecentPointCulling{}, &recent);
  EXPECT_EQ(culled, 2);
  EXPECT_TRUE(rarely_found->is_bad());
  EXPECT_TRUE(single_view->is_bad());
  EXPECT_FALSE(two_views->is_bad());
  EXPECT_FALSE(young_single->is_bad());
  EXPECT_EQ(scene.keyframes[0]->map_point(scene.KeypointOf(0, 1)), nullptr);  // removed from keyframes
  EXPECT_EQ(recent.size(), 2u);
  // Three keyframes after creation the survivors leave the recent list.
  KeyFrame* later = scene.map.CreateKeyFrame(9, 9, scene.keyframes[3]->shared_features(), Rigid3());
  std::vector<MapPoint*> recent2{two_views};
  CullRecentMapPoints(*later, RecentPointCulling{}, &recent2);
  EXPECT_TRUE(recent2.empty());
  EXPECT_FALSE(two_views->is_bad());
}

TEST(LocalMappingTest, CreatesPointsAtTheTrueLandmarkPositions) {
  for (const bool with_depth : {true, false}) {
    Scene scene(120, 2, 0.3, with_depth);
    // 40 shared points connect the two keyframes in the covisibility graph.
    for (int l = 0; l < 120 && scene.map.num_map_points() < 40; ++l)
      if (scene.KeypointOf(0, l) >= 0 && scene.KeypointOf(1, l) >= 0) scene.AddPoint(l, {0, 1});
    scene.keyframes[0]->UpdateConnections();
    scene.keyframes[1]->UpdateConnections();
    ASSERT_EQ(scene.keyframes[1]->Weight(scene.keyframes[0]), 40);
    int expected = 0;
    for (int l = 0; l < 120; ++l)
      expected += scene.KeypointOf(0, l) >= 0 && scene.KeypointOf(1, l) >= 0 &&
                  scene.keyframes[1]->map_point(scene.KeypointOf(1, l)) == nullptr;
    std::vector<MapPoint*> recent;
    const int created = CreateMapPointsFromNeighbours(&scene.map, scene.keyframes[1], 10, &recent);
    EXPECT_GE(created, expected * 9 / 10) << "depth " << with_depth;
    EXPECT_LE(created, expected);
    EXPECT_EQ(recent.size(), static_cast<std::size_t>(created));
    for (MapPoint* point : recent) {
      const int index = point->KeypointIndexIn(scene.keyframes[1]);
      ASSERT_GE(index, 0);
      const int landmark = scene.landmark_of_keypoint[1][index];
      EXPECT_LT((point->position() - scene.landmarks[landmark]).norm(), 0.01) << "depth " << with_depth;
      EXPECT_EQ(point->KeypointIndexIn(scene.keyframes[0]), scene.KeypointOf(0, landmark));
    }
  }
}

TEST(LocalMappingTest, FusionMergesDuplicatesIntoThePointWithMoreObservations) {
  Scene scene(60, 3, 0.1, true);
  MapPoint* strong = scene.AddPoint(5, {0, 1});
  MapPoint* duplicate = scene.AddPoint(5, {2}, Vec3(0.002, 0, 0));
  MapPoint* unobserved_in_2 = scene.AddPoint(6, {0, 1});
  const int fused = FusePointsIntoKeyFrame(scene.keyframes[2], {strong, unobserved_in_2}, 3.0);
  EXPECT_EQ(fused, 2);
  EXPECT_TRUE(duplicate->is_bad());
  EXPECT_EQ(duplicate->replaced_by(), strong);
  EXPECT_EQ(scene.keyframes[2]->map_point(scene.KeypointOf(2, 5)), strong);
  EXPECT_EQ(strong->num_observing_keyframes(), 3);
  EXPECT_TRUE(unobserved_in_2->IsObservedBy(scene.keyframes[2]));
}

TEST(LocalMappingTest, CullsKeyframesWhosePointsAreSeenByThreeOthers) {
  Scene scene(80, 5, 0.02, true);
  for (int l = 0; l < 80; ++l) {
    std::vector<int> observers;
    for (int k = 0; k < 5; ++k)
      if (scene.KeypointOf(k, l) >= 0) observers.push_back(k);
    if (observers.size() == 5) scene.AddPoint(l, observers);
  }
  for (KeyFrame* keyframe : scene.keyframes) keyframe->UpdateConnections();
  const int culled = CullRedundantKeyFrames(&scene.map, scene.keyframes[4], RedundantKeyFrameCulling{});
  // Every point is seen by all 5 keyframes. Candidates (covisible with 4, never the first) go in
  // id order while each of their points keeps >= 3 other observers: 1 (others 0,2,3,4), then 2
  // (others 0,3,4); 3 stays (others 0,4 only).
  EXPECT_EQ(culled, 2);
  EXPECT_TRUE(scene.keyframes[1]->is_bad());
  EXPECT_TRUE(scene.keyframes[2]->is_bad());
  EXPECT_FALSE(scene.keyframes[0]->is_bad());
  EXPECT_FALSE(scene.keyframes[3]->is_bad());
  EXPECT_FALSE(scene.keyframes[4]->is_bad());
  EXPECT_EQ(scene.map.num_keyframes(), 3);
}

TEST(LocalMapperTest, SynchronousModeInsertsKeyframesInOrder) {
  Scene scene(60, 2, 0.05, true);
  for (int l = 0; l < 60; ++l)
    if (scene.KeypointOf(0, l) >= 0) scene.AddPoint(l, {0});
  // Keyframe 1 carries associations only (as tracking creates it); local mapping adds observations.
  for (int l = 0; l < 60; ++l) {
    const int i0 = scene.KeypointOf(0, l), i1 = scene.KeypointOf(1, l);
    if (i0 >= 0 && i1 >= 0) scene.keyframes[1]->AddMapPoint(scene.keyframes[0]->map_point(i0), i1);
  }
  LocalMapper mapper(&scene.map, LocalMapperOptions{}, false);
  EXPECT_TRUE(mapper.AcceptsKeyFrames());
  mapper.InsertKeyFrame(scene.keyframes[1]);
  EXPECT_EQ(mapper.QueuedKeyFrames(), 1);
  mapper.ProcessQueued();
  EXPECT_EQ(mapper.QueuedKeyFrames(), 0);
  EXPECT_EQ(mapper.stats().keyframes_processed, 1);
  EXPECT_GT(scene.keyframes[1]->Weight(scene.keyframes[0]), 40);
  EXPECT_EQ(scene.keyframes[1]->parent(), scene.keyframes[0]);
  mapper.Close();
}

// Pause (for loop closing): keyframes reserved before it are finished (and handed downstream)
// when it returns; no reservation is granted until Resume.
TEST(LocalMapperTest, PauseFinishesReservedKeyframesAndRefusesNewOnes) {
  Scene scene(60, 4, 0.05, true);
  for (int l = 0; l < 60; ++l)
    if (scene.KeypointOf(0, l) >= 0) scene.AddPoint(l, {0});
  for (int k = 1; k < 4; ++k)
    for (int l = 0; l < 60; ++l) {
      const int i0 = scene.KeypointOf(0, l), ik = scene.KeypointOf(k, l);
      if (i0 >= 0 && ik >= 0) scene.keyframes[k]->AddMapPoint(scene.keyframes[0]->map_point(i0), ik);
    }
  LocalMapper mapper(&scene.map, LocalMapperOptions{}, true);
  std::vector<long> handed_down;  // written by the mapping thread, read after Pause / Close
  mapper.SetDownstream([&](KeyFrame* keyframe) { handed_down.push_back(keyframe->id()); });
  mapper.Start();
  ASSERT_TRUE(mapper.ReserveKeyFrame());
  mapper.InsertKeyFrame(scene.keyframes[1]);
  ASSERT_TRUE(mapper.ReserveKeyFrame());
  mapper.InsertKeyFrame(scene.keyframes[2]);
  mapper.Pause();
  EXPECT_EQ(handed_down, (std::vector<long>{1, 2}));
  EXPECT_EQ(mapper.stats().keyframes_processed, 2);
  EXPECT_FALSE(mapper.ReserveKeyFrame());
  mapper.Pause();  // nested
  mapper.Resume();
  EXPECT_FALSE(mapper.ReserveKeyFrame());
  mapper.Resume();
  ASSERT_TRUE(mapper.ReserveKeyFrame());
  mapper.InsertKeyFrame(scene.keyframes[3]);
  mapper.Close();
  EXPECT_EQ(handed_down, (std::vector<long>{1, 2, 3}));
  mapper.Pause();  // after Close: returns at once
  mapper.Resume();
}

}  // namespace
}  // namespace esdslam
