// Frame::CompensateRollingShutter on a synthetic image: the keypoints move to where a camera
// turning at a known rate would have seen them at the middle row's time.
#include <gtest/gtest.h>

#include <algorithm>

#include "common/error.h"
#include "synth/synthetic_scene.h"
#include "tracking/frame.h"

namespace esdslam {
namespace {

constexpr double kReadoutS = 0.03;

struct StaticImage {
  SyntheticScene scene;
  SynthFrame image;
  OrbExtractor extractor{OrbOptions{}};
  StaticImage() : scene(Options()), image(scene.RenderFrame(0)) {}
  static SynthOptions Options() {
    SynthOptions options = SynthPreset("static");
    options.num_frames = 1;
    options.supersampling = 1;
    return options;
  }
  Frame MakeFrame(double readout_s) const {
    const auto rig = MakeRgbdRig(scene.camera().intrinsics(), 40.0, 40.0, extractor, readout_s);
    return Frame(0, image.timestamp, image.bgr, image.depth_m, cv::Mat(), extractor, rig);
  }
};

// The pixel of direction `ray` (camera frame) on the ideal camera.
cv::Point2f Pixel(const PinholeCamera& camera, const Vec3& ray) {
  const Vec2 p = camera.Project(ray);
  return {static_cast<float>(p.x()), static_cast<float>(p.y())};
}

TEST(RollingShutter, KeypointsMoveToTheMiddleRowTime) {
  const StaticImage setup;
  const Frame extracted = setup.MakeFrame(kReadoutS);
  Frame frame = setup.MakeFrame(kReadoutS);
  ASSERT_GT(frame.size(), 300);
  const Vec3 angular_velocity_cam(0.4, -1.5, 0.2);  // rad/s: mostly yaw, as a hand-held turn
  frame.CompensateRollingShutter(angular_velocity_cam);
  const PinholeCamera& camera = frame.rig().camera;
  const double last_row = camera.height() - 1;
  double largest_shift_px = 0;
  for (int i = 0; i < frame.size(); ++i) {
    const cv::Point2f seen = extracted.features().undistorted[i];
    const cv::Point2f middle = frame.features().undistorted[i];
    // Forward model: the point seen at the middle row's time turned by exp([w]x tau) by the time
    // its row was exposed, so projecting that must give back where it was seen.
    const double tau_s = (frame.features().keypoints[i].pt.y / last_row - 0.5) * kReadoutS;
    const Vec3 middle_ray((middle.x - camera.cx()) / camera.fx(), (middle.y - camera.cy()) / camera.fy(), 1.0);
    const cv::Point2f predicted = Pixel(camera, ExpSO3(tau_s * angular_velocity_cam) * middle_ray);
    EXPECT_NEAR(predicted.x, seen.x, 1e-3);
    EXPECT_NEAR(predicted.y, seen.y, 1e-3);
    // The depth reading turns with the ray (the point, not only its direction, is moved to the
    // middle row's camera), and the virtual right coordinate follows the corrected u and depth.
    EXPECT_EQ(frame.features().has_depth(i), extracted.features().has_depth(i));
    if (frame.features().has_depth(i)) {
      const Vec3 point_at_row = extracted.features().BackprojectCam(i);
      const Vec3 expected = ExpSO3(-tau_s * angular_velocity_cam) * point_at_row;
      EXPECT_LT((frame.features().BackprojectCam(i) - expected).norm(), 1e-4 * expected.norm());
      EXPECT_NEAR(frame.features().right_u[i], middle.x - 40.0 / frame.features().depth[i], 1e-3);
    }
    largest_shift_px = std::max(largest_shift_px, static_cast<double>(cv::norm(middle - seen)));
  }
  // 1.5 rad/s over half of 30 ms at f = 525 px: about 12 px at the top and bottom rows.
  EXPECT_GT(largest_shift_px, 8.0);
  EXPECT_LT(largest_shift_px, 16.0);
}

TEST(RollingShutter, GlobalShutterRigChangesNothing) {
  const StaticImage setup;
  const Frame extracted = setup.MakeFrame(0.0);
  Frame frame = setup.MakeFrame(0.0);
  frame.CompensateRollingShutter(Vec3(0.4, -1.5, 0.2));
  for (int i = 0; i < frame.size(); ++i) {
    EXPECT_EQ(frame.features().undistorted[i], extracted.features().undistorted[i]);
    EXPECT_EQ(frame.features().right_u[i], extracted.features().right_u[i]);
    EXPECT_EQ(frame.features().depth[i], extracted.features().depth[i]);
  }
}

TEST(RollingShutter, ASecondCallReplacesTheFirst) {
  const StaticImage setup;
  Frame once = setup.MakeFrame(kReadoutS);
  once.CompensateRollingShutter(Vec3(0.0, 1.0, 0.0));
  Frame twice = setup.MakeFrame(kReadoutS);
  twice.CompensateRollingShutter(Vec3(2.0, 0.0, 0.5));
  twice.CompensateRollingShutter(Vec3(0.0, 1.0, 0.0));
  for (int i = 0; i < once.size(); ++i) {
    EXPECT_EQ(once.features().undistorted[i], twice.features().undistorted[i]);
    EXPECT_EQ(once.features().right_u[i], twice.features().right_u[i]);
    EXPECT_EQ(once.features().depth[i], twice.features().depth[i]);
  }
  // The grid follows the corrected positions: a keypoint is found where it now is.
  const cv::Point2f p = twice.features().undistorted[0];
  const std::vector<int> near = twice.features().grid->FeaturesInArea(p.x, p.y, 1.0);
  EXPECT_NE(std::find(near.begin(), near.end(), 0), near.end());
}

TEST(RollingShutter, RefusedOnceTheFeaturesAreShared) {
  const StaticImage setup;
  Frame frame = setup.MakeFrame(kReadoutS);
  const Frame copy = frame;  // shares the features, as a keyframe made from the frame does
  EXPECT_THROW(frame.CompensateRollingShutter(Vec3(0.0, 1.0, 0.0)), Error);
}

}  // namespace
}  // namespace esdslam
