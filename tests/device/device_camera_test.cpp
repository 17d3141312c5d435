// The camera-to-settings mapping: the pinhole model a device's fields of view imply, the device's
// model replacing the settings' (baseline kept), and the settings' calibration checked against the
// device.
#include <cmath>

#include <gtest/gtest.h>

#include "common/error.h"
#include "device/device_camera.h"

namespace esdslam {
namespace {

// An Xtion-like colour stream: 640x480 at 30 fps, 58 x 45 degrees.
DeviceCameraInfo Xtion() {
  constexpr double kDeg = 3.14159265358979323846 / 180;
  DeviceCameraInfo device;
  device.uri = "1d27/0601@3/4";
  device.colour = {640, 480, 30, 58 * kDeg, 45 * kDeg};
  device.depth = device.colour;
  return device;
}

Settings CalibratedSettings() {
  Settings settings;
  settings.camera.fx = 535.4;
  settings.camera.fy = 539.2;
  settings.camera.cx = 320.1;
  settings.camera.cy = 247.6;
  settings.camera.k1 = 0.1;
  settings.bf = 40;  // 40 / 535.4 = 0.0747 m baseline
  return settings;
}

TEST(DeviceCameraTest, FieldOfViewGivesThePinholeModel) {
  const CameraIntrinsics camera = IntrinsicsFromFieldOfView(Xtion().colour);
  EXPECT_NEAR(camera.fx, 320 / std::tan(29 * 3.14159265358979323846 / 180), 1e-9);  // 577.3 px
  EXPECT_NEAR(camera.fx, 577.3, 0.1);
  EXPECT_NEAR(camera.fy, 240 / std::tan(22.5 * 3.14159265358979323846 / 180), 1e-9);
  EXPECT_EQ(camera.cx, 320);
  EXPECT_EQ(camera.cy, 240);
  EXPECT_FALSE(camera.HasDistortion());
  EXPECT_EQ(camera.width, 640);
  DeviceStreamInfo bad = Xtion().colour;
  bad.horizontal_fov_rad = 0;
  EXPECT_THROW(IntrinsicsFromFieldOfView(bad), Error);
  bad = Xtion().colour;
  bad.fps = 0;
  EXPECT_THROW(IntrinsicsFromFieldOfView(bad), Error);
}

TEST(DeviceCameraTest, TheDevicesModelReplacesTheSettingsAndKeepsTheBaseline) {
  DeviceCameraInfo device = Xtion();
  device.colour.fps = 25;
  const Settings settings = SettingsForDevice(CalibratedSettings(), device, CameraModelFrom::kDevice);
  const CameraIntrinsics expected = IntrinsicsFromFieldOfView(device.colour);
  EXPECT_EQ(settings.camera.fx, expected.fx);
  EXPECT_EQ(settings.camera.cy, expected.cy);
  EXPECT_EQ(settings.camera.k1, 0);  // the device reports no distortion
  EXPECT_EQ(settings.fps, 25);
  EXPECT_NEAR(settings.bf / settings.camera.fx, 40 / 535.4, 1e-12);  // same baseline in metres
  EXPECT_EQ(settings.th_depth, CalibratedSettings().th_depth);     // the rest is the file's
}

TEST(DeviceCameraTest, TheSettingsCalibrationIsKeptWhenItFitsTheDevice) {
  const Settings settings = SettingsForDevice(CalibratedSettings(), Xtion(), CameraModelFrom::kSettings);
  EXPECT_EQ(settings.camera.fx, 535.4);
  EXPECT_EQ(settings.camera.k1, 0.1);
  DeviceCameraInfo smaller = Xtion();
  smaller.colour.width = 320;
  smaller.colour.height = 240;
  try {
    SettingsForDevice(CalibratedSettings(), smaller, CameraModelFrom::kSettings);
    FAIL() << "size mismatch accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("640x480"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("320x240"), std::string::npos) << e.what();
  }
  DeviceCameraInfo faster = Xtion();
  faster.colour.fps = 60;
  EXPECT_THROW(SettingsForDevice(CalibratedSettings(), faster, CameraModelFrom::kSettings), Error);
  EXPECT_EQ(ParseCameraModelFrom("settings"), CameraModelFrom::kSettings);
  EXPECT_THROW(ParseCameraModelFrom("factory"), Error);
}

}  // namespace
}  // namespace esdslam
