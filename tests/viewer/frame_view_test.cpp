#include "viewer/frame_view.h"

#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "system/frame_columns.h"
#include "viewer/map_view.h"
#include "viewer/viewer_test_frames.h"

namespace esdslam {
namespace {

TEST(FrameView, PictureIsScaledWithTheMaskTintedOnlyWhereItIsSet) {
  const FrameReport report = testing::MakeViewerFrame(0);
  const cv::Mat picture = ViewerPicture(report, 0.5);
  ASSERT_EQ(picture.cols, 320);
  ASSERT_EQ(picture.rows, 240);
  const cv::Vec3b masked = picture.at<cv::Vec3b>(120, 50), clear = picture.at<cv::Vec3b>(120, 270);
  EXPECT_EQ(clear, cv::Vec3b(40, 80, 120));
  EXPECT_NEAR(masked[0], (40 + 255) / 2, 1);  // cyan blended at half strength (BGR)
  EXPECT_NEAR(masked[2], 120 / 2, 1);
}

TEST(FrameView, KeypointsKeepTheirKindAndAreThinnedToTheLimit) {
  const FrameReport report = testing::MakeViewerFrame(0, 6, 3, 2);
  const std::vector<ViewerKeypoint> all = ViewerKeypoints(*report.features, 0.5, 100);
  ASSERT_EQ(all.size(), 11u);
  EXPECT_EQ(all[0].kind, KeypointKind::kKept);
  EXPECT_FLOAT_EQ(all[0].u, 50.f);
  EXPECT_FLOAT_EQ(all[0].v, 150.f);
  EXPECT_EQ(all[6].kind, KeypointKind::kSemantic);
  EXPECT_EQ(all[10].kind, KeypointKind::kGeometry);
  EXPECT_EQ(ViewerKeypoints(*report.features, 0.5, 4).size(), 4u);
}

TEST(FrameView, FrameEventCarriesTheColumnTableTheCountsAndADecodableJpeg) {
  const FrameReport report = testing::MakeViewerFrame(41);
  RunCounters counters;
  counters.frames = 42;
  counters.keyframes = 5;
  ViewerOptions options;
  const std::string json = EncodeFrameEvent(report, counters, options);
  EXPECT_EQ(json.find('\n'), std::string::npos);  // one SSE data line
  EXPECT_NE(json.find("\"frames\":42"), std::string::npos);
  EXPECT_NE(json.find("\"keyframes\":5"), std::string::npos);
  EXPECT_NE(json.find("\"state\":\"OK\""), std::string::npos);
  EXPECT_NE(json.find("\"keypoints_dynamic\":5"), std::string::npos);
  for (const FrameColumn& column : FrameColumns())  // every stage time of the table, by name
    if (std::string(column.unit) == "ms") {
      EXPECT_NE(json.find(std::string("\"") + column.name + "\":"), std::string::npos) << column.name;
    }
  EXPECT_NE(json.find("\"extract_ms\":12.50"), std::string::npos);
  EXPECT_NE(json.find("\"image_width\":320"), std::string::npos);
  const std::size_t at = json.find("\"jpeg\":\"");
  ASSERT_NE(at, std::string::npos);
  const std::size_t end = json.find('"', at + 8);
  EXPECT_GT(end - at, 100u);
}

TEST(MapView, DynamicTrailKeepsTheNewestRemovedKeypointsInTheWorldFrame) {
  DynamicPointTrail trail(4);
  FrameReport report = testing::MakeViewerFrame(0, 2, 3, 2);
  trail.Add(report);
  std::vector<Eigen::Vector3f> points = trail.Points();
  ASSERT_EQ(points.size(), 4u);  // 5 dynamic, the oldest gone
  EXPECT_NEAR(points.back().z(), 2.0f, 1e-5);
  EXPECT_NEAR(points.back().x(), (410.f - 320.f) / 500.f * 2.f, 1e-5);  // last geometry keypoint
  report.track.has_pose = false;  // no pose: nothing to place
  trail.Add(report);
  EXPECT_EQ(trail.Points().size(), 4u);
}

TEST(MapView, DecimationBoundsEveryListAndTheEventListsThem) {
  ViewerOptions options;
  options.max_map_points = 10;
  options.max_dense_points = 5;
  MapView view;
  for (int i = 0; i < 100; ++i) {
    view.static_points.emplace_back(static_cast<float>(i), 0.f, 1.f);
    view.dense.push_back(Eigen::Vector3f(0.f, static_cast<float>(i), 0.f), Rgb8{1, 2, 3});
  }
  std::vector<StampedPose> poses(50);
  for (int i = 0; i < 50; ++i) poses[i].world_from_cam = Rigid3(Quat::Identity(), Vec3(i, 0, 0));
  view.trajectory = TrajectoryPositions(poses, 8);
  ASSERT_EQ(view.trajectory.size(), 8u);
  EXPECT_FLOAT_EQ(view.trajectory.back().x(), 49.f);  // the newest position is always there
  DecimateMapView(options, &view);
  EXPECT_EQ(view.static_points.size(), 10u);
  EXPECT_EQ(view.dense.size(), 5u);
  EXPECT_EQ(view.dense.colors.size(), 5u);
  const std::string json = EncodeMapEvent(view);
  EXPECT_NE(json.find("\"static_points\":[0.000,0.000,1.000,10.000,"), std::string::npos) << json.substr(0, 200);
  EXPECT_NE(json.find("\"dense_colors\":[1,2,3,"), std::string::npos);
}

}  // namespace
}  // namespace esdslam
