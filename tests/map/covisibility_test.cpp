// Covisibility weights, ordered connections and the spanning tree on hand-built maps.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "map/core_test_scene.h"
#include "map/keyframe.h"
#include "map/map.h"
#include "map/map_point.h"

namespace esdslam {
namespace {

// Five keyframes; keyframe k observes points [20k, 20k + 60): neighbours share 40, keyframes two
// apart share 20, three apart none.
class CovisibilityTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::vector<Vec3> landmarks = testing::RandomLandmarks(200);
    const cv::Mat descriptors = testing::RandomDescriptors(200);
    std::vector<int> ids;
    auto features = testing::ProjectLandmarks(landmarks, descriptors, Rigid3(), true, &ids);
    ASSERT_EQ(features->size(), 200);
    for (int k = 0; k < 5; ++k) {
      const Rigid3 pose(Quat::Identity(), Vec3(0.05 * k, 0, 0));
      keyframes.push_back(map.CreateKeyFrame(k, k, features, pose));
      map.AddKeyFrame(keyframes.back());
    }
    for (int p = 0; p < 140; ++p) {
      MapPoint* point = map.CreateMapPoint(landmarks[p], nullptr);
      map.AddMapPoint(point);
      points.push_back(point);
    }
    for (int k = 0; k < 5; ++k)
      for (int p = 20 * k; p < 20 * k + 60; ++p) {
        points[p]->AddObservation(keyframes[k], p, true);
        keyframes[k]->AddMapPoint(points[p], p);
      }
    for (KeyFrame* keyframe : keyframes) keyframe->UpdateConnections();
  }

  int SharedPoints(KeyFrame* a, KeyFrame* b) const {
    int shared = 0;
    for (MapPoint* point : a->valid_map_points()) shared += point->IsObservedBy(b);
    return shared;
  }

  Map map;
  std::vector<KeyFrame*> keyframes;
  std::vector<MapPoint*> points;
};

TEST_F(CovisibilityTest, WeightsEqualSharedObservations) {
  for (KeyFrame* a : keyframes)
    for (KeyFrame* b : keyframes) {
      if (a == b) continue;
      EXPECT_EQ(a->Weight(b), SharedPoints(a, b)) << a->id() << "-" << b->id();
      EXPECT_EQ(a->Weight(b), b->Weight(a));
    }
  EXPECT_EQ(keyframes[0]->Weight(keyframes[1]), 40);
  EXPECT_EQ(keyframes[0]->Weight(keyframes[2]), 20);
  EXPECT_EQ(keyframes[0]->Weight(keyframes[3]), 0);
}

TEST_F(CovisibilityTest, OrderedConnectionsByDecreasingWeight) {
  const auto ordered = keyframes[2]->covisible_keyframes();
  ASSERT_EQ(ordered.size(), 4u);
  EXPECT_EQ(keyframes[2]->Weight(ordered[0]), 40);
  EXPECT_EQ(keyframes[2]->Weight(ordered[1]), 40);
  EXPECT_EQ(keyframes[2]->Weight(ordered[2]), 20);
  EXPECT_EQ(keyframes[2]->CovisibleKeyframesWithWeight(30).size(), 2u);
  EXPECT_EQ(keyframes[2]->BestCovisibleKeyframes(1).size(), 1u);
}

TEST_F(CovisibilityTest, WeightsFollowObservationChanges) {
  points[50]->EraseObservation(keyframes[1]);
  keyframes[1]->EraseMapPoint(50);
  keyframes[1]->UpdateConnections();
  keyframes[2]->UpdateConnections();
  EXPECT_EQ(keyframes[1]->Weight(keyframes[2]), 39);
  EXPECT_EQ(keyframes[2]->Weight(keyframes[1]), 39);
  EXPECT_EQ(keyframes[1]->Weight(keyframes[2]), SharedPoints(keyframes[1], keyframes[2]));
}

void ExpectTreeConsistent(Map* map) {
  const auto live = map->keyframes();
  std::set<KeyFrame*> live_set(live.begin(), live.end());
  for (KeyFrame* keyframe : live) {
    if (keyframe->id() == 0) {
      EXPECT_EQ(keyframe->parent(), nullptr);
    } else {
      ASSERT_NE(keyframe->parent(), nullptr) << keyframe->id();
      EXPECT_TRUE(live_set.count(keyframe->parent())) << "parent of " << keyframe->id() << " is culled";
      EXPECT_TRUE(keyframe->parent()->children().count(keyframe)) << keyframe->id();
      // Following parents reaches the root without cycles.
      KeyFrame* node = keyframe;
      int hops = 0;
      while (node->parent() != nullptr && hops < 100) node = node->parent(), ++hops;
      EXPECT_EQ(node->id(), 0);
    }
    for (KeyFrame* child : keyframe->children()) EXPECT_EQ(child->parent(), keyframe);
  }
}

TEST_F(CovisibilityTest, SpanningTreeParentsAreBestCovisibleAtInsertion) {
  for (int k = 1; k < 5; ++k) EXPECT_EQ(keyframes[k]->parent(), keyframes[k - 1]) << k;
  ExpectTreeConsistent(&map);
}

TEST_F(CovisibilityTest, CullingAKeyframeRepairsTreeAndGraph) {
  const Rigid3 cam_from_kf2(Quat(Eigen::AngleAxisd(0.1, Vec3::UnitY())), Vec3(0.01, 0.02, 0.03));
  const Rigid3 expected_cam_from_world = cam_from_kf2 * keyframes[2]->cam_from_world();
  keyframes[2]->SetBad();
  EXPECT_TRUE(keyframes[2]->is_bad());
  EXPECT_EQ(map.num_keyframes(), 4);
  ExpectTreeConsistent(&map);
  EXPECT_EQ(keyframes[3]->parent(), keyframes[1]);  // shares 20 with 1 (the only candidate)
  for (KeyFrame* keyframe : map.keyframes()) EXPECT_EQ(keyframe->Weight(keyframes[2]), 0);
  for (MapPoint* point : map.map_points()) EXPECT_FALSE(point->IsObservedBy(keyframes[2]));
  // A pose stored relative to the culled keyframe still resolves to the same world pose.
  Rigid3 relative = cam_from_kf2;
  KeyFrame* live = LiveAncestor(keyframes[2], &relative);
  EXPECT_EQ(live, keyframes[1]);
  const Rigid3 resolved = relative * live->cam_from_world();
  EXPECT_LT((resolved.translation() - expected_cam_from_world.translation()).norm(), 1e-12);
  EXPECT_LT(RotationAngle(resolved.rotation() * expected_cam_from_world.rotation().conjugate()), 1e-9);
  // The first keyframe is never culled.
  keyframes[0]->SetBad();
  EXPECT_FALSE(keyframes[0]->is_bad());
}

TEST(MapPointTest, ReplaceMovesObservationsAndDescriptor) {
  Map map;
  const std::vector<Vec3> landmarks = testing::RandomLandmarks(10);
  std::vector<int> ids;
  auto features = testing::ProjectLandmarks(landmarks, testing::RandomDescriptors(10), Rigid3(), true, &ids);
  KeyFrame* a = map.CreateKeyFrame(0, 0, features, Rigid3());
  KeyFrame* b = map.CreateKeyFrame(1, 1, features, Rigid3());
  MapPoint* p = map.CreateMapPoint(landmarks[0], a);
  MapPoint* q = map.CreateMapPoint(landmarks[0], b);
  map.AddMapPoint(p), map.AddMapPoint(q);
  p->AddObservation(a, 0, true), a->AddMapPoint(p, 0);
  q->AddObservation(b, 0, true), b->AddMapPoint(q, 0);
  p->Replace(q);
  EXPECT_TRUE(p->is_bad());
  EXPECT_EQ(p->replaced_by(), q);
  EXPECT_EQ(a->map_point(0), q);
  EXPECT_EQ(q->num_observing_keyframes(), 2);
  EXPECT_EQ(q->num_observations(), 4);  // two views with depth
  EXPECT_EQ(map.num_map_points(), 1);
  EXPECT_FALSE(q->descriptor().empty());
}

}  // namespace
}  // namespace esdslam
