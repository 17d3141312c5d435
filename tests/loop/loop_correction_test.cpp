// Loop correction steps on hand-built maps: correction propagation over the current keyframe's
// group, loop fusion of duplicated points, essential-graph optimisation.
#include "loop/loop_correction.h"

#include <gtest/gtest.h>

#include "map/core_test_scene.h"

namespace esdslam {
namespace {

double PoseDistance(const Rigid3& a, const Rigid3& b) {
  return (a.inverse().translation() - b.inverse().translation()).norm();
}

TEST(LoopCorrectionTest, PropagationKeepsPosesRelativeToTheCurrentKeyframe) {
  const Rigid3 current(ExpSO3(Vec3(0.1, -0.2, 0.05)), Vec3(0.3, 0.1, -0.2));
  const Rigid3 corrected(ExpSO3(Vec3(0.12, -0.25, 0.0)), Vec3(0.1, 0.0, -0.1));
  const std::map<long, Rigid3> group{{3, current},
                                     {1, Rigid3(ExpSO3(Vec3(0, 0.3, 0)), Vec3(1, 0, 0))},
                                     {2, Rigid3(ExpSO3(Vec3(0.2, 0, 0)), Vec3(0, 2, 0.5))}};
  const std::map<long, Rigid3> out = PropagateCorrection(current, corrected, group);
  EXPECT_LT(PoseDistance(out.at(3), corrected), 1e-12);
  EXPECT_LT(RotationAngle(out.at(3).rotation() * corrected.rotation().conjugate()), 1e-12);
  for (const long id : {1L, 2L}) {
    const Rigid3 before = group.at(id) * current.inverse();  // cam_i from cam_current
    const Rigid3 after = out.at(id) * corrected.inverse();
    EXPECT_LT((before.translation() - after.translation()).norm(), 1e-12) << id;
    EXPECT_LT(RotationAngle(before.rotation() * after.rotation().conjugate()), 1e-12) << id;
  }
}

TEST(LoopCorrectionTest, GroupCorrectionMovesGroupKeyframesAndTheirPointsRigidly) {
  testing::LandmarkScene scene(80, 4, 0.1, true);
  // Keyframes 2 and 3 share points of landmarks 0..39; keyframes 0 and 1 those of 40..79.
  const auto seen_by = [&](int landmark, int a, int b) {
    return scene.KeypointOf(a, landmark) >= 0 && scene.KeypointOf(b, landmark) >= 0;
  };
  std::vector<MapPoint*> group_points, other_points;
  for (int l = 0; l < 40; ++l)
    if (seen_by(l, 2, 3)) group_points.push_back(scene.AddPoint(l, {2, 3}));
  for (int l = 40; l < 80; ++l)
    if (seen_by(l, 0, 1)) other_points.push_back(scene.AddPoint(l, {0, 1}));
  ASSERT_GE(group_points.size(), 20u);
  ASSERT_GE(other_points.size(), 20u);
  for (KeyFrame* keyframe : scene.keyframes) keyframe->UpdateConnections();
  const Rigid3 pose2 = scene.keyframes[2]->cam_from_world();
  const Vec3 point_in_cam2 = pose2 * group_points[5]->position();
  const Vec3 other_before = other_points[0]->position();
  const Rigid3 corrected = Rigid3(ExpSO3(Vec3(0, 0.05, 0)), Vec3(0.02, 0, -0.01)) * scene.keyframes[3]->cam_from_world();

  const GroupCorrection correction = CorrectCurrentGroup(scene.keyframes[3], corrected);
  ASSERT_EQ(correction.group.size(), 2u);
  EXPECT_EQ(correction.group[0], scene.keyframes[2]);
  EXPECT_LT(PoseDistance(scene.keyframes[3]->cam_from_world(), corrected), 1e-12);
  EXPECT_LT(PoseDistance(correction.non_corrected.at(scene.keyframes[2]), pose2), 1e-12);
  // A group point keeps its place in the group's camera frames; the other keyframes do not move.
  EXPECT_LT((scene.keyframes[2]->cam_from_world() * group_points[5]->position() - point_in_cam2).norm(), 1e-9);
  EXPECT_EQ(correction.corrected_by.size(), group_points.size());
  EXPECT_EQ(other_points[0]->position(), other_before);
  EXPECT_LT(PoseDistance(scene.keyframes[0]->cam_from_world(), Rigid3()), 1e-12);
}

TEST(LoopCorrectionTest, LoopFusionMergesDuplicatedPointsIntoTheLoopSide) {
  testing::LandmarkScene scene(60, 4, 0.1, true);
  // The same landmarks mapped twice: by keyframes 0-1 ("before the loop") and, as duplicates
  // 1 cm off, by keyframes 2-3 ("after the drift").
  std::vector<MapPoint*> loop_points, duplicates;
  for (int l = 0; l < 60; ++l) {
    if (scene.KeypointOf(0, l) < 0 || scene.KeypointOf(1, l) < 0 || scene.KeypointOf(2, l) < 0 ||
        scene.KeypointOf(3, l) < 0)
      continue;
    loop_points.push_back(scene.AddPoint(l, {0, 1}));
    duplicates.push_back(scene.AddPoint(l, {2, 3}, Vec3(0.01, 0, 0)));
  }
  ASSERT_GE(loop_points.size(), 30u);
  for (KeyFrame* keyframe : scene.keyframes) keyframe->UpdateConnections();
  EXPECT_EQ(scene.keyframes[3]->Weight(scene.keyframes[0]), 0);

  // Keypoint-level matches for the first half (as verification finds them), projection for the rest.
  std::vector<MapPoint*> matched(scene.keyframes[3]->features().size(), nullptr);
  const std::size_t half = loop_points.size() / 2;
  for (std::size_t i = 0; i < half; ++i) matched[duplicates[i]->KeypointIndexIn(scene.keyframes[3])] = loop_points[i];
  EXPECT_EQ(FuseLoopMatches(scene.keyframes[3], matched), static_cast<int>(half));
  const GroupCorrection correction = CorrectCurrentGroup(scene.keyframes[3], scene.keyframes[3]->cam_from_world());
  FuseLoopPointsIntoGroup(correction, loop_points, 4.0);
  for (std::size_t i = 0; i < loop_points.size(); ++i) {
    EXPECT_TRUE(duplicates[i]->is_bad()) << i;
    EXPECT_EQ(duplicates[i]->replaced_by(), loop_points[i]) << i;
    EXPECT_EQ(loop_points[i]->num_observing_keyframes(), 4) << i;
  }
  // The fusion links the two sides of the loop.
  const auto connections = NewLoopConnections(correction);
  ASSERT_TRUE(connections.count(scene.keyframes[3]));
  EXPECT_TRUE(connections.at(scene.keyframes[3]).count(scene.keyframes[0]));
  EXPECT_GE(scene.keyframes[3]->Weight(scene.keyframes[0]), static_cast<int>(loop_points.size()));
}

// Eight keyframes on a circle looking outwards, chained by the spanning tree and covisibility,
// with odometry drift; the last one closes the loop to the first.
TEST(LoopCorrectionTest, EssentialGraphOptimisationRemovesTheDrift) {
  testing::LandmarkScene scene(10, 0, 0.0, true);
  std::vector<Rigid3> truth;
  Rigid3 drifted;
  const Rigid3 bias(ExpSO3(Vec3(0.0, 0.03, 0.0)), Vec3(0.02, 0.0, 0.0));
  for (int k = 0; k < 8; ++k) {
    const double angle = k * 2 * M_PI / 9;
    truth.push_back(Rigid3(ExpSO3(Vec3(0, -angle, 0)), Vec3(2 * std::sin(angle), 0, 2 * std::cos(angle))).inverse());
    drifted = k == 0 ? truth[0] : bias * truth[k] * truth[k - 1].inverse() * drifted;
    KeyFrame* keyframe = scene.AddKeyFrame(truth[k], true);
    keyframe->set_cam_from_world(drifted);
    if (k > 0) {
      keyframe->ChangeParent(scene.keyframes[k - 1]);
      keyframe->AddConnection(scene.keyframes[k - 1], 50);
      scene.keyframes[k - 1]->AddConnection(keyframe, 50);
    }
  }
  MapPoint* point = scene.map.CreateMapPoint(truth[3].inverse() * Vec3(0.1, 0.2, 2.0), scene.keyframes[3]);
  scene.map.AddMapPoint(point);
  const Vec3 point_in_cam3 = scene.keyframes[3]->cam_from_world() * point->position();
  double error_before = 0;
  for (int k = 0; k < 8; ++k) error_before += PoseDistance(scene.keyframes[k]->cam_from_world(), truth[k]) / 8;

  KeyFrame* current = scene.keyframes[7];
  KeyFrame* loop = scene.keyframes[0];
  const GroupCorrection correction = CorrectCurrentGroup(current, truth[7] * truth[0].inverse() * loop->cam_from_world());
  std::map<KeyFrame*, std::set<KeyFrame*, KeyFrameIdLess>, KeyFrameIdLess> connections;
  connections[current].insert(loop);
  const EssentialGraphInput input{loop, current, &correction, &connections, {}, 100};
  const EssentialGraphSummary summary = OptimizeEssentialGraph(&scene.map, input, PoseGraphOptions{});
  EXPECT_EQ(summary.keyframes, 8);
  EXPECT_EQ(summary.edges, 8);  // 7 tree edges + the loop edge (covisibility 50 < 100 adds none)
  double error_after = 0;
  for (int k = 0; k < 8; ++k) error_after += PoseDistance(scene.keyframes[k]->cam_from_world(), truth[k]) / 8;
  EXPECT_LT(error_after, 0.4 * error_before) << error_before << " -> " << error_after;
  EXPECT_LT(PoseDistance(loop->cam_from_world(), truth[0]), 1e-12);  // fixed
  // The point moved with its reference keyframe.
  EXPECT_LT((scene.keyframes[3]->cam_from_world() * point->position() - point_in_cam3).norm(), 1e-9);
}

}  // namespace
}  // namespace esdslam
