// Known-answer tests of the synthetic rolling shutter (SynthOptions::readout_time_s) and of the
// fast-turning "rpy" trajectory of the "rolling" preset: readout 0 renders as before, a still
// camera in a still scene renders the same with any readout, and each row of a rolling render is
// the same row of a global render at that row's exposure time.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>

#include "common/error.h"
#include "io/settings.h"
#include "synth/sequence_writer.h"
#include "synth/synthetic_scene.h"
#include "support/temp_path.h"
#include "support/small_synth.h"

namespace esdslam {
namespace {

SynthOptions SmallOptions(const std::string& preset) { return ::esdslam::testing::SmallSynthOptions(preset); }

// Largest absolute difference of any image of the two frames (0 = bit-identical images).
double MaxImageDifference(const SynthFrame& a, const SynthFrame& b) {
  return std::max({cv::norm(a.bgr, b.bgr, cv::NORM_INF), cv::norm(a.depth_m, b.depth_m, cv::NORM_INF),
                   cv::norm(a.mover_mask, b.mover_mask, cv::NORM_INF), cv::norm(a.surface_id, b.surface_id, cv::NORM_INF)});
}

// Largest absolute difference of row `row` of every image of the two frames.
double MaxRowDifference(const SynthFrame& a, const SynthFrame& b, int row) {
  return std::max({cv::norm(a.bgr.row(row), b.bgr.row(row), cv::NORM_INF),
                   cv::norm(a.depth_m.row(row), b.depth_m.row(row), cv::NORM_INF),
                   cv::norm(a.mover_mask.row(row), b.mover_mask.row(row), cv::NORM_INF),
                   cv::norm(a.surface_id.row(row), b.surface_id.row(row), cv::NORM_INF)});
}

TEST(RollingShutter, ReadoutZeroRendersAsWithoutTheOption) {
  SynthOptions options = SmallOptions("dynamic");  // moving camera and movers
  options.depth_noise_at_1m = 0.002;
  options.image_noise_sigma = 2.0;
  const SyntheticScene without(options);
  options.readout_time_s = 0.0;
  const SyntheticScene with_zero(options);
  for (const int index : {0, 57}) {
    const SynthFrame a = without.RenderFrame(index), b = with_zero.RenderFrame(index);
    EXPECT_EQ(MaxImageDifference(a, b), 0.0) << index;
    // The row-by-row renderer at readout 0 gives the global shutter's images bit for bit.
    const SynthFrame rows = with_zero.RenderRolling(
        [&](double time) { return CameraPoseAt(options, time); }, with_zero.FrameTime(index), 12345u);
    const SynthFrame global = with_zero.Render(with_zero.WorldFromCam(index), with_zero.FrameTime(index), 12345u);
    EXPECT_EQ(MaxImageDifference(rows, global), 0.0) << index;
  }
}

TEST(RollingShutter, StillCameraInAStillSceneLooksTheSameWithAnyReadout) {
  SynthOptions options = SmallOptions("static");
  options.depth_noise_at_1m = 0.002;
  const SyntheticScene global_scene(options);
  options.readout_time_s = 0.03;
  const SyntheticScene rolling_scene(options);
  const Rigid3 still = global_scene.WorldFromCam(40);
  const double time = global_scene.FrameTime(40);
  const SynthFrame global = global_scene.Render(still, time, 7u);
  const SynthFrame rolling = rolling_scene.RenderRolling([&](double) { return still; }, time, 7u);
  EXPECT_EQ(MaxImageDifference(global, rolling), 0.0);
}

// Every checked row of frame `index` of `scene` (readout > 0, no noise) equals that row of a
// global render from the trajectory's pose at the row's exposure time. With `expect_visible`,
// the first and last rows differ from the global render at the frame's own time (the shutter's
// effect shows).
void ExpectRowsAtTheirOwnTimes(const SyntheticScene& scene, int index, bool expect_visible) {
  const SynthFrame rolling = scene.RenderFrame(index);
  const double time = scene.FrameTime(index);
  // The frame's pose and timestamp stay the middle row's (the frame time's).
  EXPECT_EQ(rolling.world_from_cam.translation(), scene.WorldFromCam(index).translation());
  EXPECT_EQ(rolling.world_from_cam.rotation().coeffs(), scene.WorldFromCam(index).rotation().coeffs());
  EXPECT_DOUBLE_EQ(rolling.timestamp, scene.Timestamp(index));
  const int last = scene.camera().height() - 1;
  EXPECT_DOUBLE_EQ(scene.RowTime(time, 0), time - 0.5 * scene.options().readout_time_s);
  EXPECT_DOUBLE_EQ(scene.RowTime(time, last), time + 0.5 * scene.options().readout_time_s);
  const SynthFrame at_frame_time = scene.Render(scene.WorldFromCam(index), time, 0u);
  for (const int row : {0, last / 3, last}) {
    const double row_time = scene.RowTime(time, row);
    const SynthFrame global = scene.Render(CameraPoseAt(scene.options(), row_time), row_time, 0u);
    EXPECT_EQ(MaxRowDifference(rolling, global, row), 0.0) << "frame " << index << " row " << row;
  }
  if (!expect_visible) return;
  EXPECT_GT(cv::norm(rolling.bgr.row(0), at_frame_time.bgr.row(0), cv::NORM_L1) / rolling.bgr.cols, 10.0)
      << "frame " << index;
  EXPECT_GT(cv::norm(rolling.bgr.row(last), at_frame_time.bgr.row(last), cv::NORM_L1) / rolling.bgr.cols, 10.0)
      << "frame " << index;
}

TEST(RollingShutter, EachRowIsTheGlobalRenderAtItsExposureTime) {
  SynthOptions options = SmallOptions("rolling");
  ASSERT_GT(options.readout_time_s, 0.0);
  options.depth_noise_at_1m = 0;  // noise is drawn over the whole image: rows compare exactly without
  const SyntheticScene turning(options);
  for (const int index : {10, 95}) ExpectRowsAtTheirOwnTimes(turning, index, /*expect_visible=*/true);
  // Movers are rendered where they are at the row's time too.
  SynthOptions dynamic = SmallOptions("dynamic");
  dynamic.readout_time_s = 0.03;
  ExpectRowsAtTheirOwnTimes(SyntheticScene(dynamic), 30, /*expect_visible=*/false);
}

TEST(RollingShutter, SettingsCarryTheReadoutOnlyWhenThereIsOne) {
  SynthOptions options = SynthPreset("rolling");
  const std::string yaml = SynthSettingsYaml(options);
  EXPECT_NE(yaml.find("Camera.readoutTime: 0.025\n"), std::string::npos) << yaml;
  const std::filesystem::path path = testing::TestTempPath("rolling_settings.yaml");
  std::ofstream(path) << yaml;
  EXPECT_DOUBLE_EQ(LoadSettings(path.string()).readout_time_s, 0.025);
  std::filesystem::remove(path);
  options.readout_time_s = 0;
  EXPECT_EQ(SynthSettingsYaml(options).find("readoutTime"), std::string::npos);
}

TEST(RollingShutter, ReadoutAndTrajectoryAreChecked) {
  SynthOptions options;
  options.readout_time_s = -0.001;
  EXPECT_THROW(options.Check(), Error);
  options.readout_time_s = 1.0 / 30 + 1e-6;  // longer than the frame period
  EXPECT_THROW(options.Check(), Error);
  options.readout_time_s = 1.0 / 30;
  EXPECT_NO_THROW(options.Check());
  options.fps = 5;
  options.readout_time_s = 0.15;  // within the frame period, beyond Camera.readoutTime's 0.1 s
  EXPECT_THROW(options.Check(), Error);
  options = SynthPreset("rolling");
  EXPECT_EQ(options.trajectory, "rpy");
  EXPECT_EQ(options.num_movers, 0);
  options.num_movers = 1;
  EXPECT_THROW(options.Check(), Error);
}

// The rpy path turns like TUM fr1_rpy (rates between frames at 30 fps) without walking away,
// and keeps textured surfaces 1.5-4 m in front of the camera.
TEST(RollingShutter, RpyTrajectoryTurnsFastOnTheSpot) {
  const SyntheticScene scene(SynthPreset("rolling"));
  std::vector<double> rates;  // deg/s
  double max_offset = 0, min_depth = 1e9, max_depth = 0;
  const Vec3 first = scene.WorldFromCam(0).translation();
  for (int i = 0; i < scene.num_frames(); ++i) {
    const Rigid3 pose = scene.WorldFromCam(i);
    max_offset = std::max(max_offset, (pose.translation() - first).norm());
    const Vec3 axis = pose.rotation() * Vec3::UnitZ();
    const double depth = scene.CastRay(pose.translation(), axis, scene.FrameTime(i)).t;  // axis: unit, z = 1
    min_depth = std::min(min_depth, depth), max_depth = std::max(max_depth, depth);
    if (i == 0) continue;
    const Rigid3 delta = scene.WorldFromCam(i - 1).inverse() * pose;
    rates.push_back(RotationAngle(delta.rotation()) * 180 / M_PI * scene.options().fps);
  }
  std::sort(rates.begin(), rates.end());
  const double median = rates[rates.size() / 2], peak = rates.back();
  std::printf("rpy: rotation rate median %.1f deg/s, peak %.1f deg/s; position within %.3f m; optical axis "
              "meets a surface at %.2f-%.2f m\n",
              median, peak, max_offset, min_depth, max_depth);
  EXPECT_GT(median, 55.0);
  EXPECT_LT(median, 75.0);
  EXPECT_GT(peak, 100.0);
  EXPECT_LT(peak, 150.0);
  EXPECT_LT(max_offset, 0.06);
  EXPECT_GT(min_depth, 1.5);
  EXPECT_LT(max_depth, 4.0);
}

}  // namespace
}  // namespace esdslam
