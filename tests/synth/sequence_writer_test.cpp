// The written sequence reads back through the project's TUM reader and settings loader with
// the same images, poses and masks as the in-memory renderer.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "io/settings.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "synth/sequence_writer.h"
#include "synth/synthetic_scene.h"
#include "support/temp_path.h"

namespace esdslam {
namespace {

namespace fs = std::filesystem;

TEST(SequenceWriter, WritesTumLayoutThatReadsBackExactly) {
  SynthOptions options = SynthPreset("dynamic");
  options.num_frames = 4;
  options.intrinsics.width = 160;
  options.intrinsics.height = 120;
  options.intrinsics.fx = options.intrinsics.fy = 131.25;
  options.intrinsics.cx = 79.5;
  options.intrinsics.cy = 59.5;
  options.depth_time_offset = 0.005;
  const SyntheticScene scene(options);
  const fs::path dir = testing::TestTempPath("synth_writer_test");
  fs::remove_all(dir);
  int progress_calls = 0;
  WriteSynthSequence(scene, dir.string(), [&](int done, int total) {
    EXPECT_EQ(total, 4);
    EXPECT_EQ(done, ++progress_calls);
  });
  EXPECT_EQ(progress_calls, 4);

  const TumSequence sequence = TumSequence::Open(dir.string());
  ASSERT_EQ(sequence.frames().size(), 4u);
  const auto groundtruth = ReadTumTrajectory(sequence.groundtruth_path());
  ASSERT_EQ(groundtruth.size(), 4u);
  const Settings settings = LoadSettings((dir / "settings.yaml").string());
  EXPECT_DOUBLE_EQ(settings.camera.fx, 131.25);
  EXPECT_EQ(settings.camera.width, 160);
  EXPECT_DOUBLE_EQ(settings.depth_map_factor, 5000.0);
  EXPECT_EQ(settings.orb.num_features, 1000);

  for (int i = 0; i < 4; ++i) {
    const SynthFrame frame = scene.RenderFrame(i);
    const FrameEntry& entry = sequence.frames()[i];
    EXPECT_NEAR(entry.timestamp, frame.timestamp, 1e-6);
    EXPECT_NEAR(entry.depth_timestamp - entry.timestamp, 0.005, 1e-6);
    const RgbdImages images = LoadRgbd(entry, settings.depth_map_factor);
    EXPECT_EQ(cv::norm(images.bgr, frame.bgr, cv::NORM_INF), 0.0);
    EXPECT_LE(cv::norm(images.depth_m, frame.depth_m, cv::NORM_INF), 0.5 / 5000 + 1e-6);
    EXPECT_NEAR(groundtruth[i].timestamp, frame.timestamp, 1e-6);
    EXPECT_LT((groundtruth[i].world_from_cam.translation() - frame.world_from_cam.translation()).norm(), 1e-6);
    const std::string stamp = fmt::format("{:.6f}", frame.timestamp);
    const cv::Mat mask = cv::imread((dir / "masks" / (stamp + ".png")).string(), cv::IMREAD_UNCHANGED);
    const cv::Mat labels = cv::imread((dir / "labels" / (stamp + ".png")).string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(mask.type(), CV_8U);
    EXPECT_EQ(cv::norm(mask, frame.mover_mask, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::countNonZero(labels == kVocPersonClass), cv::countNonZero(frame.mover_mask));
    EXPECT_EQ(cv::countNonZero(labels), cv::countNonZero(frame.mover_mask));
  }
  std::ifstream masks_list(dir / "masks.txt");
  std::string line;
  int entries = 0;
  while (std::getline(masks_list, line)) entries += (!line.empty() && line[0] != '#');
  EXPECT_EQ(entries, 4);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace esdslam
