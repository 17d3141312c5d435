// SystemConfig's checks and the public types' conversions (fast; no run).
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "api/api_config.h"
#include "esdslam/esdslam.h"

namespace esdslam {
namespace {

std::string CheckMessage(const SystemConfig& config) {
  try {
    config.Check();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

SystemConfig WithSettings() {
  SystemConfig config;
  config.settings_file = "settings.yaml";
  return config;
}

TEST(SystemConfig, NamesWhatIsWrong) {
  EXPECT_NE(CheckMessage(SystemConfig{}).find("settings_file"), std::string::npos);
  EXPECT_EQ(CheckMessage(WithSettings()), "");
  SystemConfig bad_mode = WithSettings();
  bad_mode.mode = "fast";
  EXPECT_NE(CheckMessage(bad_mode).find("none | semantic | geometry | full"), std::string::npos);
  SystemConfig labels_without_segmentation = WithSettings();
  labels_without_segmentation.label_input = true;
  labels_without_segmentation.mode = "geometry";
  EXPECT_NE(CheckMessage(labels_without_segmentation).find("label_input"), std::string::npos);
  SystemConfig classes_only = WithSettings();
  classes_only.label_classes = {"background", "person"};
  EXPECT_NE(CheckMessage(classes_only).find("label_classes"), std::string::npos);
  SystemConfig every = WithSettings();
  every.segment_every = -1;
  EXPECT_NE(CheckMessage(every).find("segment_every"), std::string::npos);
  SystemConfig viewer = WithSettings();
  viewer.viewer_port = 70000;
  EXPECT_NE(CheckMessage(viewer).find("viewer_port"), std::string::npos);
  SystemConfig localization = WithSettings();
  localization.localization = true;
  EXPECT_NE(CheckMessage(localization).find("load_map"), std::string::npos);
}

TEST(SystemConfig, MissingSettingsFileIsNamed) {
  SystemConfig config;
  config.settings_file = "/nonexistent/esdslam.yaml";
  try {
    System slam(config);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/esdslam.yaml"), std::string::npos) << e.what();
  }
}

TEST(PublicTypes, Matrix4IsRowMajorWorldFromCam) {
  const Rigid3 world_from_cam(Quat(Eigen::AngleAxisd(0.5, Vec3::UnitZ())), Vec3(1, 2, 3));
  const Matrix4 m = ToMatrix4(world_from_cam);
  EXPECT_DOUBLE_EQ(m[3], 1);
  EXPECT_DOUBLE_EQ(m[7], 2);
  EXPECT_DOUBLE_EQ(m[11], 3);
  EXPECT_DOUBLE_EQ(m[15], 1);
  EXPECT_NEAR(m[1], -std::sin(0.5), 1e-12);  // row 0, column 1 of Rz
  EXPECT_NEAR(m[4], std::sin(0.5), 1e-12);
  EXPECT_STREQ(StatusName(ToStatus(TrackingState::kLost)), "LOST");
  EXPECT_STREQ(StatusName(TrackingStatus::kNotInitialized), "NOT_INITIALIZED");
}

}  // namespace
}  // namespace esdslam
