#include <atomic>
#include <filesystem>
#include <random>
#include <string>

#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include "common/error.h"
#include "dense/cloud_io.h"
#include "dense/dense_map.h"
#include "dense/dense_mapper.h"
#include "dense/depth_backprojector.h"
#include "dense/map_render.h"
#include "dense/octomap_writer.h"
#include "dense/outlier_filter.h"
#include "dense/voxel_grid.h"
#include "support/temp_path.h"

#include <octomap/OcTree.h>

namespace esdslam {
namespace {

CameraIntrinsics TestIntrinsics() {
  CameraIntrinsics k;
  k.fx = k.fy = 500;
  k.cx = 319.5;
  k.cy = 239.5;
  return k;
}

TEST(VoxelGrid, KeepsOneMeanPointPerVoxel) {
  PointCloud cloud;
  cloud.push_back({0.001f, 0.001f, 0.001f}, {10, 20, 30});
  cloud.push_back({0.003f, 0.005f, 0.007f}, {30, 40, 50});
  cloud.push_back({0.015f, 0.001f, 0.001f}, {0, 0, 0});
  cloud.push_back({-0.001f, 0.001f, 0.001f}, {0, 0, 0});  // negative side: its own voxel
  const PointCloud out = VoxelDownsample(cloud, 0.01);
  ASSERT_EQ(out.size(), 3u);
  bool found_mean = false;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if ((out.points[i] - Eigen::Vector3f(0.002f, 0.003f, 0.004f)).norm() < 1e-6) {
      found_mean = true;
      EXPECT_EQ(out.colors[i].r, 20);
      EXPECT_EQ(out.colors[i].b, 40);
    }
  }
  EXPECT_TRUE(found_mean);
}

TEST(VoxelGrid, MemoryBoundedByVolumeNotByInsertions) {
  VoxelGrid grid(0.1);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (int round = 0; round < 20; ++round)
    for (int i = 0; i < 5000; ++i) grid.Insert({u(rng), u(rng), u(rng)}, {});
  EXPECT_LE(grid.num_voxels(), 1000u);  // a 1 m cube holds at most 10^3 voxels of 10 cm
}

TEST(DepthBackprojector, PlaneAtKnownDepthAndMaskExcluded) {
  const PinholeCamera camera(TestIntrinsics());
  DenseOptions options;
  options.voxel_size = 0.005;
  options.pixel_stride = 1;
  options.mask_dilation_px = 0;
  const DepthBackprojector backprojector(camera, options);
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(2.0f));
  cv::Mat bgr(480, 640, CV_8UC3, cv::Scalar(0, 0, 255));
  cv::Mat mask = cv::Mat::zeros(480, 640, CV_8U);
  mask(cv::Rect(0, 0, 320, 480)).setTo(255);  // left half dynamic
  const PointCloud cloud = backprojector.Backproject(bgr, depth, mask);
  ASSERT_FALSE(cloud.empty());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_NEAR(cloud.points[i].z(), 2.0f, 1e-5);
    EXPECT_GT(cloud.points[i].x(), -0.001f);  // only the right half (x >= 0) survives
    EXPECT_EQ(cloud.colors[i].r, 255);
  }
}

TEST(DepthBackprojector, DropsInvalidAndFarDepth) {
  const PinholeCamera camera(TestIntrinsics());
  DenseOptions options;
  options.max_depth = 3.0;
  const DepthBackprojector backprojector(camera, options);
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(0.0f));
  depth(cv::Rect(0, 0, 100, 100)).setTo(5.0f);
  const PointCloud cloud = backprojector.Backproject(cv::Mat(480, 640, CV_8UC3, cv::Scalar::all(0)), depth, cv::Mat());
  EXPECT_TRUE(cloud.empty());
}

TEST(OutlierFilter, RemovesIsolatedPointsKeepsSurface) {
  PointCloud cloud;
  for (int i = 0; i < 50; ++i)
    for (int j = 0; j < 50; ++j) cloud.push_back({i * 0.01f, j * 0.01f, 1.0f}, {});
  cloud.push_back({0.25f, 0.25f, 1.3f}, {});  // isolated, far from the plane
  cloud.push_back({2.0f, 2.0f, 2.0f}, {});
  OutlierFilterOptions options;
  options.search_radius = 0.05;
  const PointCloud kept = RemoveStatisticalOutliers(cloud, options);
  // The plane's border points have sparser neighbourhoods and may go; the interior stays.
  EXPECT_GE(kept.size(), 2200u);
  for (const auto& p : kept.points) EXPECT_FLOAT_EQ(p.z(), 1.0f);
}

TEST(CloudIo, PlyRoundTrip) {
  PointCloud cloud;
  cloud.push_back({1.5f, -2.f, 3.25f}, {1, 2, 3});
  cloud.push_back({0.f, 0.f, 0.f}, {255, 128, 0});
  const std::string path = testing::TestTempPath("dense_roundtrip", ".ply");
  WritePly(path, cloud);
  const PointCloud back = ReadPly(path);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back.points[0], cloud.points[0]);
  EXPECT_EQ(back.colors[1].g, 128);
}

// A keyframe 2.025 m (mid OctoMap cell) in front of a fronto-parallel wall, grey.
DenseKeyframe WallKeyframe(long id, const Rigid3& world_from_cam) {
  DenseKeyframe keyframe;
  keyframe.id = id;
  keyframe.timestamp = id;
  keyframe.world_from_cam = world_from_cam;
  keyframe.bgr = cv::Mat(480, 640, CV_8UC3, cv::Scalar::all(128));
  keyframe.depth_m = cv::Mat(480, 640, CV_32F, cv::Scalar(2.025f));
  return keyframe;
}

Eigen::Vector3f Mean(const PointCloud& cloud) {
  Eigen::Vector3f mean = Eigen::Vector3f::Zero();
  for (const auto& p : cloud.points) mean += p / static_cast<float>(cloud.size());
  return mean;
}

TEST(DenseMap, GlobalCloudFollowsKeyframePoses) {
  DenseOptions options;
  options.outlier_removal = false;
  options.pixel_stride = 4;
  DenseMap map(PinholeCamera(TestIntrinsics()), options);
  map.Integrate(WallKeyframe(7, Rigid3(Quat::Identity(), Vec3(1, 0, 0))), {});
  PointCloud global = map.BuildGlobalCloud({});  // hand-off pose
  ASSERT_GT(global.size(), 1000u);
  EXPECT_NEAR(Mean(global).x(), 1.0f, 0.01f);
  EXPECT_NEAR(Mean(global).z(), 2.025f, 0.01f);
  global = map.BuildGlobalCloud({{7, Rigid3(Quat::Identity(), Vec3(0, 2, 0))}});  // e.g. after loop closure
  EXPECT_NEAR(Mean(global).x(), 0.0f, 0.01f);
  EXPECT_NEAR(Mean(global).y(), 2.0f, 0.01f);
  const DenseMapStats stats = map.stats();
  EXPECT_EQ(stats.keyframes, 1u);
  EXPECT_GT(stats.ray_bytes, 0u);
  EXPECT_GT(stats.point_bytes, stats.points * 24);
}

TEST(DenseMap, DynamicPixelsLeaveNoPointsAndNoRays) {
  DenseOptions options;
  options.outlier_removal = false;
  options.mask_dilation_px = 0;
  DenseMap map(PinholeCamera(TestIntrinsics()), options);
  DenseKeyframe keyframe = WallKeyframe(1, Rigid3());
  keyframe.dynamic_mask = cv::Mat::zeros(480, 640, CV_8U);
  keyframe.dynamic_mask(cv::Rect(0, 0, 320, 480)).setTo(255);  // left half: a person
  map.Integrate(keyframe, {});
  for (const auto& p : map.BuildGlobalCloud({}).points) EXPECT_GT(p.x(), 0.0f);
  const std::vector<PosedRays> rays = map.RaysAt({});
  ASSERT_EQ(rays.size(), 1u);
  for (const Eigen::Vector3f& end : map.RayEndpoints(rays[0].rays)) EXPECT_GT(end.x(), 0.0f);
}

DenseOptions FastOptions() {
  DenseOptions options;
  options.outlier_removal = false;
  options.pixel_stride = 4;
  return options;
}

// The pose source fails when the second keyframe is integrated: that keyframe is skipped, the
// others go into the map, and the owner gets the error (it used to be logged and dropped).
void ExpectKeyframeErrorReachesTheOwner(bool threaded) {
  std::atomic<int> calls{0};
  KeyframePoseSource poses = [&calls]() -> KeyframePoses {
    if (++calls == 2) throw Error("no poses");
    return {};
  };
  DenseMapperOptions options;
  options.threaded = threaded;
  DenseMapper mapper(PinholeCamera(TestIntrinsics()), FastOptions(), poses, options);
  mapper.AddKeyframe(WallKeyframe(1, Rigid3()));
  mapper.AddKeyframe(WallKeyframe(2, Rigid3()));
  if (!threaded) {
    EXPECT_THROW(mapper.AddKeyframe(WallKeyframe(3, Rigid3())), Error);  // the next hand-off reports it
  }
  try {
    mapper.Finish();
    ADD_FAILURE() << "Finish did not throw";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "dense mapping failed: no poses");
  }
  EXPECT_EQ(mapper.stats().keyframes, 1);
  EXPECT_THROW(mapper.AddKeyframe(WallKeyframe(4, Rigid3())), Error);
  EXPECT_EQ(mapper.stats().keyframes, 1);
}

TEST(DenseMapper, KeyframeErrorReachesTheOwnerThreaded) { ExpectKeyframeErrorReachesTheOwner(true); }

TEST(DenseMapper, KeyframeErrorReachesTheOwnerInline) { ExpectKeyframeErrorReachesTheOwner(false); }

TEST(DenseMapper, FinishIntegratesEveryQueuedKeyframe) {
  DenseMapperOptions options;
  options.queue_capacity = 2;
  DenseMapper mapper(PinholeCamera(TestIntrinsics()), FastOptions(), {}, options);
  for (long id = 1; id <= 6; ++id) mapper.AddKeyframe(WallKeyframe(id, Rigid3()));
  mapper.Finish();
  EXPECT_EQ(mapper.stats().keyframes, 6);
  EXPECT_EQ(mapper.map().stats().keyframes, 6u);
  mapper.Finish();  // idempotent
}

TEST(Octomap, WallOccupiedAndSpaceInFrontFree) {
  DenseOptions options;
  DenseMap map(PinholeCamera(TestIntrinsics()), options);
  map.Integrate(WallKeyframe(0, Rigid3()), {});
  const std::string path = testing::TestTempPath("octomap", ".bt");
  const OctomapStats stats = WriteOctomap(path, map, {});
  EXPECT_GT(stats.occupied_leaves, 0u);
  EXPECT_GT(stats.free_leaves, stats.occupied_leaves);
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(path));  // OctoMap's own reader
  EXPECT_DOUBLE_EQ(tree.getResolution(), options.octomap_resolution);
  const octomap::OcTreeNode* on_wall = tree.search(0.0, 0.0, 2.025);
  ASSERT_NE(on_wall, nullptr);
  EXPECT_TRUE(tree.isNodeOccupied(on_wall));
  const octomap::OcTreeNode* in_front = tree.search(0.0, 0.0, 1.0);
  ASSERT_NE(in_front, nullptr);
  EXPECT_FALSE(tree.isNodeOccupied(in_front));
  EXPECT_EQ(tree.search(0.0, 0.0, 3.0), nullptr);  // behind the wall: unknown
}

// Dense.octomapMinPoints: occupied cells without enough cloud points are set free; the ones that
// hold points stay.
TEST(Octomap, CellsWithoutCloudPointsAreFreedWhenAsked) {
  DenseOptions options;
  options.octomap_min_points = 1;
  DenseMap map(PinholeCamera(TestIntrinsics()), options);
  map.Integrate(WallKeyframe(0, Rigid3()), {});
  PointCloud cloud;  // only the wall's left half (x < 0) keeps points
  for (float x = -0.5f; x < 0.f; x += 0.01f)
    for (float y = -0.3f; y <= 0.3f; y += 0.01f) cloud.push_back({x, y, 2.025f}, {0, 0, 0});
  const std::string path = testing::TestTempPath("octomap_support", ".bt");
  const OctomapStats stats = WriteOctomap(path, map, {}, &cloud);
  EXPECT_GT(stats.unsupported_cells, 0u);
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(path));
  const octomap::OcTreeNode* left = tree.search(-0.2, 0.0, 2.025);
  const octomap::OcTreeNode* right = tree.search(0.2, 0.0, 2.025);
  ASSERT_NE(left, nullptr);
  ASSERT_NE(right, nullptr);
  EXPECT_TRUE(tree.isNodeOccupied(left));
  EXPECT_FALSE(tree.isNodeOccupied(right));
  // Off (the default): the same cloud frees nothing.
  DenseMap plain{PinholeCamera(TestIntrinsics()), DenseOptions{}};
  plain.Integrate(WallKeyframe(0, Rigid3()), {});
  EXPECT_EQ(WriteOctomap(path, plain, {}, &cloud).unsupported_cells, 0u);
}

TEST(MapRender, TopViewDrawsPointsAndCameraPath) {
  PointCloud floor;
  for (float x = -1.f; x <= 1.f; x += 0.02f)
    for (float z = 0.f; z <= 2.f; z += 0.02f) floor.push_back({x, 1.0f, z}, {200, 200, 200});  // y down: floor below
  const std::vector<Rigid3> cams{Rigid3(), Rigid3(Quat::Identity(), Vec3(0.5, 0, 0.5))};
  const cv::Mat top = RenderTopView(floor, cams);
  const cv::Mat persp = RenderPerspectiveView(floor, cams);
  ASSERT_EQ(top.type(), CV_8UC3);
  const auto drawn = [](const cv::Mat& image) {
    cv::Mat differs;
    cv::reduce((image.reshape(1, static_cast<int>(image.total())) != 30), differs, 1, cv::REDUCE_MAX);
    return cv::countNonZero(differs);
  };
  EXPECT_GT(drawn(top), static_cast<int>(top.total() / 3));  // the 2 x 2 m floor fills most of the view
  EXPECT_GT(drawn(persp), static_cast<int>(persp.total() / 20));
}

}  // namespace
}  // namespace esdslam
