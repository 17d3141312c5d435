#include "loop/pose_graph.h"

#include <gtest/gtest.h>

#include "common/error.h"

namespace esdslam {
namespace {

// Ground truth: 36 keyframes on a circle of radius 2 m, looking outwards, one per 10 degrees.
std::map<long, Rigid3> CircleTruth() {
  std::map<long, Rigid3> cam_from_world;
  for (long i = 0; i < 36; ++i) {
    const double angle = i * 10.0 * M_PI / 180.0;
    const Mat3 world_rotation_cam = ExpSO3(Vec3(0, -angle, 0));  // yaw about the y (down) axis
    const Vec3 centre(2.0 * std::sin(angle), 0.0, 2.0 * std::cos(angle));
    cam_from_world[i] = Rigid3(world_rotation_cam, centre).inverse();
  }
  return cam_from_world;
}

double MeanPositionError(const std::map<long, Rigid3>& estimate, const std::map<long, Rigid3>& truth) {
  double sum = 0.0;
  for (const auto& [id, pose] : truth) sum += (estimate.at(id).inverse().translation() - pose.inverse().translation()).norm();
  return sum / truth.size();
}

TEST(PoseGraphTest, LoopEdgeRemovesAccumulatedDrift) {
  const std::map<long, Rigid3> truth = CircleTruth();
  // Odometry with a constant bias (0.4 deg yaw, 1 cm lateral per step), chained from node 0.
  const Rigid3 bias(ExpSO3(Vec3(0.0, 0.4 * M_PI / 180.0, 0.0)), Vec3(0.01, 0.0, 0.0));
  std::vector<PoseGraphEdge> edges;
  std::map<long, Rigid3> drifted{{0, truth.at(0)}};
  for (long i = 1; i < 36; ++i) {
    const Rigid3 measured = bias * truth.at(i - 1) * truth.at(i).inverse();  // cam_{i-1} from cam_i
    edges.push_back({i - 1, i, measured, 1.0});
    drifted[i] = measured.inverse() * drifted.at(i - 1);
  }
  // Loop edge 35 -> 0, measured exactly (as geometric verification would).
  edges.push_back(RelativePoseEdge(35, 0, truth.at(35), truth.at(0), 1.0));
  const double error_before = MeanPositionError(drifted, truth);
  ASSERT_GT(error_before, 0.1);

  const PoseGraphResult result = OptimizePoseGraph(drifted, edges, {0});
  const double error_after = MeanPositionError(result.cam_from_world, truth);
  EXPECT_LT(error_after, 0.5 * error_before) << "before " << error_before << " after " << error_after;
  EXPECT_LT(result.final_cost, result.initial_cost);
  EXPECT_EQ(result.cam_from_world.at(0).translation(), drifted.at(0).translation());
  EXPECT_EQ(result.cam_from_world.at(0).rotation().coeffs(), drifted.at(0).rotation().coeffs());
}

TEST(PoseGraphTest, ConsistentGraphStaysPut) {
  const std::map<long, Rigid3> truth = CircleTruth();
  std::vector<PoseGraphEdge> edges;
  for (long i = 1; i < 36; ++i) edges.push_back(RelativePoseEdge(i - 1, i, truth.at(i - 1), truth.at(i)));
  const PoseGraphResult result = OptimizePoseGraph(truth, edges, {0});
  EXPECT_LT(MeanPositionError(result.cam_from_world, truth), 1e-9);
  EXPECT_LT(result.initial_cost, 1e-20);
}

TEST(PoseGraphTest, RejectsUnknownNodesAndMissingGauge) {
  const std::map<long, Rigid3> poses{{0, Rigid3()}, {1, Rigid3()}};
  EXPECT_THROW(OptimizePoseGraph(poses, {{0, 7, Rigid3(), 1.0}}, {0}), Error);
  EXPECT_THROW(OptimizePoseGraph(poses, {{0, 1, Rigid3(), 1.0}}, {}), Error);
  EXPECT_THROW(OptimizePoseGraph(poses, {{0, 1, Rigid3(), 0.0}}, {0}), Error);
}

TEST(EssentialGraphTest, TreeStrongCovisibilityAndLoopEdges) {
  std::map<long, Rigid3> poses;
  for (long i = 0; i < 5; ++i) poses[i] = Rigid3(Quat::Identity(), Vec3(0.1 * i, 0, 0));
  const std::map<long, long> parents{{1, 0}, {2, 1}, {3, 2}, {4, 3}};
  const std::vector<CovisibilityLink> covisibility{{0, 2, 150}, {1, 3, 99}, {2, 1, 300}, {4, 9, 500}};
  const std::vector<PoseGraphEdge> loops{{4, 0, Rigid3(), 2.0}};
  const std::vector<PoseGraphEdge> edges = EssentialGraphEdges(poses, parents, covisibility, loops);
  // 4 tree edges + (0,2) (>= 100, new) + loop; (1,3) too weak, (2,1) already a tree edge, 9 unknown.
  ASSERT_EQ(edges.size(), 6u);
  EXPECT_EQ(edges[4].from, 0);
  EXPECT_EQ(edges[4].to, 2);
  EXPECT_LT((edges[4].from_from_to.translation() - Vec3(-0.2, 0, 0)).norm(), 1e-12);
  EXPECT_EQ(edges[5].weight, 2.0);
}

TEST(CorrectMapPointsTest, PointsMoveWithTheirReferenceKeyframe) {
  const Rigid3 old_pose(ExpSO3(Vec3(0.1, 0.2, 0.3)), Vec3(1, 2, 3));
  const Rigid3 new_pose(ExpSO3(Vec3(0.0, 0.25, 0.3)), Vec3(1.1, 2, 2.9));
  const Vec3 in_camera(0.3, -0.2, 2.0);
  const Vec3 old_world = old_pose.inverse() * in_camera;
  const std::vector<Vec3> corrected =
      CorrectMapPoints({old_world, Vec3(5, 5, 5)}, {3, 8}, {{3, old_pose}}, {{3, new_pose}});
  EXPECT_LT((new_pose * corrected[0] - in_camera).norm(), 1e-12);  // same place in its keyframe
  EXPECT_EQ(corrected[1], Vec3(5, 5, 5));                          // unknown reference: unchanged
}

}  // namespace
}  // namespace esdslam
