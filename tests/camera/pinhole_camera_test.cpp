// The pinhole + radial-tangential camera model against answers known in closed form and against
// OpenCV's own model (cv::projectPoints).
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "camera/pinhole_camera.h"
#include "common/setting_error.h"

namespace esdslam {
namespace {

CameraIntrinsics Bonn() {  // config/bonn.yaml
  CameraIntrinsics c;
  c.fx = 542.822841, c.fy = 542.576870, c.cx = 315.593520, c.cy = 237.756098;
  c.k1 = 0.039903, c.k2 = -0.099343, c.p1 = -0.000730, c.p2 = -0.000144;
  return c;
}

CameraIntrinsics Ideal() {
  CameraIntrinsics c;
  c.fx = 500, c.fy = 400, c.cx = 320, c.cy = 240;
  return c;
}

TEST(PinholeCamera, ProjectsAndBackprojectsInClosedForm) {
  const PinholeCamera camera(Ideal());
  const Vec2 pixel = camera.Project(Vec3(0.2, -0.3, 2.0));
  EXPECT_DOUBLE_EQ(pixel.x(), 500 * 0.1 + 320);
  EXPECT_DOUBLE_EQ(pixel.y(), 400 * -0.15 + 240);
  const Vec3 back = camera.Backproject(pixel, 2.0);
  EXPECT_NEAR((back - Vec3(0.2, -0.3, 2.0)).norm(), 0, 1e-12);
  EXPECT_EQ(camera.Project(Vec3(0, 0, 5)), Vec2(320, 240));  // the optical axis hits the principal point
}

TEST(PinholeCamera, WithoutDistortionTheBoundsAreTheImage) {
  const PinholeCamera camera(Ideal());
  EXPECT_DOUBLE_EQ(camera.min_u(), 0);
  EXPECT_DOUBLE_EQ(camera.max_u(), 640);
  EXPECT_DOUBLE_EQ(camera.min_v(), 0);
  EXPECT_DOUBLE_EQ(camera.max_v(), 480);
  EXPECT_TRUE(camera.InImage(Vec2(0, 0)));
  EXPECT_FALSE(camera.InImage(Vec2(640, 10)));
  EXPECT_FALSE(camera.InImage(Vec2(10, -0.5)));
}

TEST(PinholeCamera, DistortionMatchesOpenCV) {
  const PinholeCamera camera(Bonn());
  std::vector<cv::Point3d> points;
  for (double x = -0.6; x <= 0.6; x += 0.3)
    for (double y = -0.45; y <= 0.45; y += 0.15) points.emplace_back(x, y, 1.0);
  std::vector<cv::Point2d> expected;
  cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), Bonn().CameraMatrix(), Bonn().DistortionCoeffs(),
                    expected);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec2 distorted = camera.Distort(camera.Project(Vec3(points[i].x, points[i].y, points[i].z)));
    EXPECT_NEAR(distorted.x(), expected[i].x, 1e-6) << i;
    EXPECT_NEAR(distorted.y(), expected[i].y, 1e-6) << i;
  }
}

TEST(PinholeCamera, UndistortInvertsDistort) {
  const PinholeCamera camera(Bonn());
  std::vector<cv::Point2f> raw;
  std::vector<Vec2> ideal;
  for (double u = 20; u < 640; u += 75)
    for (double v = 15; v < 480; v += 60) {
      ideal.emplace_back(u, v);
      const Vec2 d = camera.Distort(ideal.back());
      raw.emplace_back(static_cast<float>(d.x()), static_cast<float>(d.y()));
    }
  const std::vector<cv::Point2f> undistorted = camera.Undistort(raw);
  ASSERT_EQ(undistorted.size(), ideal.size());
  for (std::size_t i = 0; i < ideal.size(); ++i) {
    EXPECT_NEAR(undistorted[i].x, ideal[i].x(), 0.01) << i;  // float input, iterative inverse
    EXPECT_NEAR(undistorted[i].y, ideal[i].y(), 0.01) << i;
  }
  // Barrel/pincushion moves the corners: the undistorted bounds are no longer the image.
  EXPECT_NE(camera.min_u(), 0);
}

TEST(CameraIntrinsics, CheckNamesTheKey) {
  CameraIntrinsics c = Ideal();
  EXPECT_NO_THROW(c.Check());
  c.fx = 0;
  try {
    c.Check();
    FAIL() << "fx = 0 accepted";
  } catch (const SettingError& e) {
    EXPECT_NE(std::string(e.what()).find("Camera.fx"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace esdslam
