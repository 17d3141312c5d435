// Free-space evidence (dense/free_space.h), its use by the dense map's points, the depth-edge
// filter and the ghost measure, on images with known answers.
#include <gtest/gtest.h>

#include "dense/anchored_voxel_map.h"
#include "dense/depth_backprojector.h"
#include "dense/free_space.h"
#include "dense/ghost_measure.h"

namespace esdslam {
namespace {

PinholeCamera TestCamera() {
  CameraIntrinsics k;
  k.fx = k.fy = 500;
  k.cx = 319.5;
  k.cy = 239.5;
  return PinholeCamera(k);
}

// Depth image: `left` metres for columns < split, `right` metres from there.
cv::Mat StepDepth(float left, float right, int split = 320) {
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(right));
  depth.colRange(0, split).setTo(left);
  return depth;
}

// The world point that pixel (u, v) of the identity camera sees at depth z.
Eigen::Vector3f PointAt(const PinholeCamera& camera, double u, double v, double z) {
  return camera.Backproject(Vec2(u, v), z).cast<float>();
}

TEST(FreeSpaceView, SeenFreeOccludedAndDepthEdges) {
  const PinholeCamera camera = TestCamera();
  DenseOptions options;  // 3 sigma, 3 cm min margin, 2 px window
  const FreeSpaceView view(camera, Rigid3(), StepDepth(2.0f, 2.0f), 1, options);
  EXPECT_EQ(view.Classify(PointAt(camera, 100, 100, 2.0)), FreeSpaceVerdict::kSeen);
  EXPECT_EQ(view.Classify(PointAt(camera, 100, 100, 2.02)), FreeSpaceVerdict::kSeen);   // within the margin
  EXPECT_EQ(view.Classify(PointAt(camera, 100, 100, 1.9)), FreeSpaceVerdict::kFree);    // the ray went past it
  EXPECT_EQ(view.Classify(PointAt(camera, 100, 100, 2.5)), FreeSpaceVerdict::kUnknown); // behind the surface
  EXPECT_EQ(view.Classify(Eigen::Vector3f(0, 0, -1)), FreeSpaceVerdict::kUnknown);      // behind the camera
  EXPECT_EQ(view.Classify(PointAt(camera, 700, 100, 1.5)), FreeSpaceVerdict::kUnknown); // outside the image
  // The margin grows with the depth noise: 3 sigma at 4 m = 7.2 cm.
  const FreeSpaceView far(camera, Rigid3(), StepDepth(4.0f, 4.0f), 1, options);
  EXPECT_EQ(far.Classify(PointAt(camera, 100, 100, 3.95)), FreeSpaceVerdict::kSeen);
  EXPECT_EQ(far.Classify(PointAt(camera, 100, 100, 3.9)), FreeSpaceVerdict::kFree);
  // A foreground edge at column 320 (1 m in front of 3 m): a point at 1 m that lands 2 px into the
  // background is not carved (a pose error of a pixel or two); 3 px in, it is.
  const FreeSpaceView edge(camera, Rigid3(), StepDepth(1.0f, 3.0f), 1, options);
  EXPECT_EQ(edge.Classify(PointAt(camera, 321, 100, 1.0)), FreeSpaceVerdict::kUnknown);
  EXPECT_EQ(edge.Classify(PointAt(camera, 323, 100, 1.0)), FreeSpaceVerdict::kFree);
  // Invalid depth in the window: no evidence.
  cv::Mat holes = StepDepth(2.0f, 2.0f);
  holes.at<float>(101, 101) = 0;
  const FreeSpaceView holed(camera, Rigid3(), holes, 1, options);
  EXPECT_EQ(holed.Classify(PointAt(camera, 100, 100, 1.5)), FreeSpaceVerdict::kUnknown);
}

TEST(FreeSpaceView, CoarseSampleGridAndPose) {
  const PinholeCamera camera = TestCamera();
  DenseOptions options;
  cv::Mat coarse(80, 107, CV_32F, cv::Scalar(2.0f));  // every 6th pixel
  const Rigid3 world_from_cam(Quat::Identity(), Vec3(0, 0, 1));  // camera 1 m along world z
  const FreeSpaceView view(camera, world_from_cam, coarse, 6, options);
  const Eigen::Vector3f on_wall = PointAt(camera, 300, 200, 2.0) + Eigen::Vector3f(0, 0, 1);
  EXPECT_EQ(view.Classify(on_wall), FreeSpaceVerdict::kSeen);
  EXPECT_EQ(view.Classify(on_wall - Eigen::Vector3f(0, 0, 0.5f)), FreeSpaceVerdict::kFree);
  // A cell's extent widens the margin.
  EXPECT_EQ(view.Classify(on_wall - Eigen::Vector3f(0, 0, 0.05f), 0.043f), FreeSpaceVerdict::kSeen);
}

TEST(FreeSpaceView, EvidenceNeedsAsManyFreeViewsAsItWasSeen) {
  std::uint8_t evidence = 1;
  EXPECT_TRUE(UpdateEvidence(FreeSpaceVerdict::kSeen, 2, &evidence));
  EXPECT_TRUE(UpdateEvidence(FreeSpaceVerdict::kSeen, 2, &evidence));  // clamped at 2
  EXPECT_EQ(evidence, 2);
  EXPECT_TRUE(UpdateEvidence(FreeSpaceVerdict::kUnknown, 2, &evidence));
  EXPECT_TRUE(UpdateEvidence(FreeSpaceVerdict::kFree, 2, &evidence));
  EXPECT_FALSE(UpdateEvidence(FreeSpaceVerdict::kFree, 2, &evidence));
}

// A wall at 2 m and a box's face at 1.5 m in front of its left half, seen by a first keyframe;
// then the box is gone: keyframes that see the wall behind carve the box, not the wall.
TEST(AnchoredVoxelMap, FreeSpaceRemovesWhatLaterViewsSeeThroughAndKeepsTheRest) {
  const PinholeCamera camera = TestCamera();
  DenseOptions options;
  AnchoredVoxelMap map(options.voxel_size, options.depth_noise_at_1m);
  PointCloud first;
  for (int v = 100; v < 380; v += 4)
    for (int u = 100; u < 540; u += 4) first.push_back(PointAt(camera, u, v, u < 300 ? 1.5 : 2.0), Rgb8{});
  map.Integrate(0, Rigid3(), first);
  const std::size_t before = map.num_points();
  const std::size_t wall = std::count_if(first.points.begin(), first.points.end(), [](const auto& p) { return p.z() > 1.9f; });
  ASSERT_GT(wall, 1000u);
  const FreeSpaceView empty(camera, Rigid3(), StepDepth(2.0f, 2.0f), 1, options);
  const std::size_t removed = map.CarveFreeSpace(empty, options.free_space_max_evidence);
  EXPECT_GT(removed, 0.9 * (first.size() - wall));
  EXPECT_EQ(map.num_points(), before - removed);
  EXPECT_EQ(map.CountIndexErrors(), 0u);
  const PointCloud kept = map.Extract({});
  EXPECT_GE(std::count_if(kept.points.begin(), kept.points.end(), [](const auto& p) { return p.z() > 1.9f; }),
            static_cast<long>(0.95 * wall));
  EXPECT_EQ(std::count_if(kept.points.begin(), kept.points.end(), [](const auto& p) { return p.z() < 1.9f; }), 0);
  EXPECT_EQ(map.num_carved_points(), removed);
}

TEST(DepthBackprojector, DepthEdgesMarkTheNearSideOfASilhouetteOnly) {
  DenseOptions options;  // 2 px, 5 % of the depth
  const DepthBackprojector backprojector(TestCamera(), options);
  const cv::Mat edges = backprojector.DepthEdges(StepDepth(1.0f, 3.0f));
  EXPECT_EQ(edges.at<std::uint8_t>(100, 317), 0);
  EXPECT_EQ(edges.at<std::uint8_t>(100, 318), 1);
  EXPECT_EQ(edges.at<std::uint8_t>(100, 319), 1);
  EXPECT_EQ(edges.at<std::uint8_t>(100, 320), 0);  // the background beside it stays
  cv::Mat shadow = StepDepth(1.0f, 3.0f);
  shadow.colRange(320, 330).setTo(0.0f);  // an invalid shadow between foreground and background
  const cv::Mat shadowed = backprojector.DepthEdges(shadow);
  EXPECT_EQ(shadowed.at<std::uint8_t>(100, 319), 0);
  EXPECT_EQ(shadowed.at<std::uint8_t>(100, 330), 0);
  // A slanted plane (depth 2 m + 1 cm per pixel) has no edge.
  cv::Mat slant(480, 640, CV_32F);
  for (int u = 0; u < 640; ++u) slant.col(u).setTo(2.0f + 0.001f * u);
  EXPECT_EQ(cv::countNonZero(backprojector.DepthEdges(slant)), 0);
}

TEST(GhostMeasure, CountsProjectionsSeenThroughByTheMargin) {
  const PinholeCamera camera = TestCamera();
  // Three points on the optical axis region: one on the wall, one 10 cm and one 30 cm in front.
  GhostMeasure measure(camera, {PointAt(camera, 100, 100, 2.0), PointAt(camera, 200, 100, 1.9), PointAt(camera, 300, 100, 1.7)});
  measure.AddFrame(Rigid3(), StepDepth(2.0f, 2.0f));
  measure.AddFrame(Rigid3(), StepDepth(2.0f, 2.0f));
  const GhostStats stats = measure.stats();
  EXPECT_EQ(stats.frames, 2u);
  EXPECT_EQ(stats.projections, 6u);
  EXPECT_EQ(stats.seen_through, 2u);  // only the point 30 cm in front, by both frames
  EXPECT_NEAR(stats.fraction(), 1.0 / 3.0, 1e-12);
  EXPECT_EQ(measure.seen_through_counts()[2], 2);
  GhostMeasureOptions bad;
  bad.margin_m = 0;
  EXPECT_THROW(bad.Check(), Error);
}

}  // namespace
}  // namespace esdslam
