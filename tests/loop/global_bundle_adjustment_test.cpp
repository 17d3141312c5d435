// Global bundle adjustment: the spanning-tree merge of keyframes and points created while it ran,
// and the solve itself on a small perturbed map.
#include "loop/global_bundle_adjustment.h"

#include <gtest/gtest.h>

#include "map/core_test_scene.h"

namespace esdslam {
namespace {

double CentreDistance(const Rigid3& a, const Rigid3& b) {
  return (a.inverse().translation() - b.inverse().translation()).norm();
}

TEST(GlobalBundleAdjustmentTest, SpanningTreeCarriesCorrectionsToUnsolvedKeyframes) {
  // Tree: 0 <- 1 <- 2 <- 3, 1 <- 4; 0 and 1 solved, 2, 3, 4 created meanwhile.
  std::map<long, Rigid3> poses;
  for (long id = 0; id < 5; ++id) poses[id] = Rigid3(ExpSO3(Vec3(0, 0.1 * id, 0)), Vec3(0.2 * id, 0, 0));
  const std::map<long, long> parent_of{{1, 0}, {2, 1}, {3, 2}, {4, 1}};
  const Rigid3 shift(ExpSO3(Vec3(0.02, 0, 0)), Vec3(0, 0.05, 0));
  const std::map<long, Rigid3> optimized{{0, poses[0]}, {1, poses[1] * shift}};
  const std::map<long, Rigid3> out = PropagateThroughSpanningTree(poses, parent_of, optimized);
  ASSERT_EQ(out.size(), 5u);
  EXPECT_LT(CentreDistance(out.at(1), poses[1] * shift), 1e-12);
  for (const long id : {2L, 3L, 4L}) {
    const long parent = parent_of.at(id);
    const Rigid3 before = poses[id] * poses[parent].inverse(), after = out.at(id) * out.at(parent).inverse();
    EXPECT_LT((before.translation() - after.translation()).norm(), 1e-12) << id;
    EXPECT_LT(RotationAngle(before.rotation() * after.rotation().conjugate()), 1e-12) << id;
  }
  // Nothing solved: nothing moves; an unknown parent makes a root.
  const std::map<long, Rigid3> same = PropagateThroughSpanningTree(poses, {{1, 7}}, {});
  for (const auto& [id, pose] : poses) EXPECT_LT(CentreDistance(same.at(id), pose), 1e-15);
}

TEST(GlobalBundleAdjustmentTest, SolveReducesErrorAndMergeCorrectsObjectsCreatedMeanwhile) {
  testing::LandmarkScene scene(120, 4, 0.15, true);
  std::vector<MapPoint*> points;
  std::vector<int> landmark_of_point;
  double error_before = 0;
  for (int l = 0; l < 120; ++l) {
    std::vector<int> observers;
    for (int k = 0; k < 4; ++k)
      if (scene.KeypointOf(k, l) >= 0) observers.push_back(k);
    if (observers.size() < 2) continue;
    const Vec3 offset(0.01 * ((l % 3) - 1), 0.005, 0);
    points.push_back(scene.AddPoint(l, observers, offset));
    landmark_of_point.push_back(l);
    error_before += offset.norm();
  }
  for (KeyFrame* keyframe : scene.keyframes) keyframe->UpdateConnections();
  const Rigid3 true_pose3 = scene.keyframes[3]->cam_from_world();
  scene.keyframes[3]->set_cam_from_world(Rigid3(ExpSO3(Vec3(0, 0.01, 0)), Vec3(0.02, 0, 0)) * true_pose3);

  GlobalBaSnapshot snapshot = BuildGlobalBundleAdjustment(scene.map);
  ASSERT_EQ(snapshot.keyframes.size(), 4u);
  EXPECT_TRUE(snapshot.problem.keyframes[0].fixed);
  EXPECT_EQ(snapshot.points.size(), points.size());
  // Meanwhile local mapping adds a keyframe (child of 3) and a point it references.
  KeyFrame* later = scene.AddKeyFrame(Rigid3(Quat::Identity(), Vec3(-0.6, 0, 0)), true);
  later->ChangeParent(scene.keyframes[3]);
  const Rigid3 later_from_3 = later->cam_from_world() * scene.keyframes[3]->world_from_cam();
  MapPoint* late_point = scene.map.CreateMapPoint(Vec3(0.3, 0.1, 3.0), later);
  scene.map.AddMapPoint(late_point);
  const Vec3 late_in_cam = later->cam_from_world() * late_point->position();

  const BaSummary summary = SolveGlobalBundleAdjustment(GlobalBundleAdjustmentOptions{}, &snapshot, nullptr);
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  const GlobalBaMergeSummary merge = MergeGlobalBundleAdjustment(&scene.map, snapshot);
  EXPECT_EQ(merge.keyframes_solved, 4);
  EXPECT_EQ(merge.keyframes_propagated, 1);
  EXPECT_EQ(merge.points_solved, static_cast<int>(points.size()));
  EXPECT_EQ(merge.points_propagated, 1);
  EXPECT_LT(CentreDistance(scene.keyframes[3]->cam_from_world(), true_pose3), 0.005);
  double error_after = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    error_after += (points[i]->position() - scene.landmarks[landmark_of_point[i]]).norm();
  EXPECT_LT(error_after, 0.2 * error_before) << error_before / points.size() << " -> " << error_after / points.size();
  const Rigid3 later_from_3_after = later->cam_from_world() * scene.keyframes[3]->world_from_cam();
  EXPECT_LT((later_from_3_after.translation() - later_from_3.translation()).norm(), 1e-9);
  EXPECT_LT((later->cam_from_world() * late_point->position() - late_in_cam).norm(), 1e-9);
}

}  // namespace
}  // namespace esdslam
