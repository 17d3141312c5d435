// A run that ends early (issue 14): the run loop's stop predicate, the files that grow frame by
// frame (LiveOutputs), the outputs written after a stop, frames of the wrong size, and why a map
// never initialised (InitDiagnosis).
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "support/temp_path.h"
#include "system/dynamic_sequence.h"
#include "system/init_diagnosis.h"
#include "system/live_outputs.h"
#include "system/pipeline.h"
#include "system/run_loop.h"
#include "system/run_outputs.h"

namespace esdslam {
namespace {

constexpr int kFrames = 12;

RunConfig Config(const std::string& out_dir) {
  RunFlags flags;
  flags.single_thread = true;
  flags.mode = DynamicMode::kNone;
  flags.run.out_dir = out_dir;
  return ResolveRunConfig(LoadRunSettings(testing::DynamicTestSequence(kFrames) + "/run.yaml"), flags);
}

int PoseLines(const std::string& path) {
  std::ifstream in(path);
  int n = 0;
  for (std::string line; std::getline(in, line);) n += !line.empty() && line[0] != '#';
  return n;
}

TEST(RunStopTest, StopsWhenAskedAndEveryTrackedFrameIsOnDiskAtEachStep) {
  const std::string out = testing::TestTempPath("run_stop");
  std::filesystem::create_directories(out);
  const RunConfig config = Config(out);
  TumFolderSource source(TumSequence::Open(testing::DynamicTestSequence(kFrames)).frames(),
                         config.settings.core.depth_map_factor);
  Pipeline pipeline(config);
  LiveOutputs live(out);
  FrameLog log;
  int tracked = 0;
  const bool stopped = RunFrames(
      source, pipeline,
      [&](const FrameReport& report) {
        log.Add(report);
        live.Add(report, log.row(log.size() - 1));
        tracked += report.track.has_pose;
        EXPECT_EQ(PoseLines(live.trajectory_path()), tracked);  // on disk before the next frame
      },
      [&] { return log.size() == 5; });
  EXPECT_TRUE(stopped);
  EXPECT_EQ(log.size(), 5u);
  ASSERT_GE(tracked, 4);
  WriteRunResults(pipeline, live, out);
  const std::vector<StampedPose> trajectory = ReadTumTrajectory(out + "/trajectory.txt");
  EXPECT_EQ(static_cast<int>(trajectory.size()), tracked);
  EXPECT_EQ(ReadTumTrajectory(out + "/keyframes.txt").size(), static_cast<std::size_t>(pipeline.system().num_keyframes()));
  EXPECT_TRUE(std::filesystem::exists(out + "/settings_used.yaml"));
  FrameReport late;
  late.track.has_pose = true;
  EXPECT_THROW(live.Add(late, log.row(0)), Error);  // the files are final
}

TEST(RunStopTest, AStopBeforeTheFirstFrameTracksNothing) {
  const RunConfig config = Config(testing::TestTempPath("run_stop_first"));
  TumFolderSource source(TumSequence::Open(testing::DynamicTestSequence(kFrames)).frames(),
                         config.settings.core.depth_map_factor);
  Pipeline pipeline(config);
  int reported = 0;
  EXPECT_TRUE(RunFrames(source, pipeline, [&](const FrameReport&) { ++reported; }, [] { return true; }));
  EXPECT_EQ(reported, 0);
}

// Regression (issue 14): images of another size than Camera.width/height ran with wrong
// intrinsics in mode none; the library caller now gets an error naming the keys.
TEST(RunStopTest, AFrameOfAnotherSizeThanTheCameraIsRejected) {
  const RunConfig config = Config(testing::TestTempPath("run_stop_size"));
  TumFolderSource source(TumSequence::Open(testing::DynamicTestSequence(kFrames)).frames(),
                         config.settings.core.depth_map_factor);
  RgbdFrame frame = *source.Next();
  cv::resize(frame.bgr, frame.bgr, cv::Size(), 0.5, 0.5);
  cv::resize(frame.depth_m, frame.depth_m, cv::Size(), 0.5, 0.5, cv::INTER_NEAREST);
  Pipeline pipeline(config);
  try {
    pipeline.Track(frame);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("Camera.width/Camera.height"), std::string::npos) << e.what();
  }
}

// Regression (issue 14): all-zero depth gave 0 poses and not a word.
TEST(RunStopTest, AllZeroDepthIsToldAsNoValidDepth) {
  const RunConfig config = Config(testing::TestTempPath("run_stop_depth"));
  TumFolderSource source(TumSequence::Open(testing::DynamicTestSequence(kFrames)).frames(),
                         config.settings.core.depth_map_factor);
  Pipeline pipeline(config);
  InitDiagnosis init;
  for (int i = 0; i < 3; ++i) {
    RgbdFrame frame = *source.Next();
    frame.depth_m = cv::Mat::zeros(frame.depth_m.size(), CV_32F);
    init.Add(pipeline.Track(frame));
  }
  EXPECT_FALSE(init.initialised());
  EXPECT_NE(init.Reason(500).find("no valid depth"), std::string::npos) << init.Reason(500);
}

TEST(RunStopTest, TooFewKeypointsWithDepthAreTold) {
  const RunConfig config = Config(testing::TestTempPath("run_stop_few"));
  TumFolderSource source(TumSequence::Open(testing::DynamicTestSequence(kFrames)).frames(),
                         config.settings.core.depth_map_factor);
  Pipeline pipeline(config);
  RgbdFrame frame = *source.Next();
  // Depth only in a strip at the top: some keypoints have depth, far fewer than initialising needs.
  cv::Mat corner = cv::Mat::zeros(frame.depth_m.size(), CV_32F);
  const cv::Rect strip(0, 0, frame.depth_m.cols, 60);
  frame.depth_m(strip).copyTo(corner(strip));
  frame.depth_m = corner;
  InitDiagnosis init;
  init.Add(pipeline.Track(frame));
  ASSERT_FALSE(init.initialised());
  EXPECT_NE(init.Reason(500).find("too few keypoints"), std::string::npos) << init.Reason(500);
  EXPECT_EQ(InitDiagnosis().Reason(500), "the map never initialised: no frame was tracked");
}

TEST(RunStopTest, AnInitialisedRunHasNoReason) {
  const RunConfig config = Config(testing::TestTempPath("run_stop_ok"));
  TumFolderSource source(TumSequence::Open(testing::DynamicTestSequence(kFrames)).frames(),
                         config.settings.core.depth_map_factor);
  Pipeline pipeline(config);
  InitDiagnosis init;
  init.Add(pipeline.Track(*source.Next()));
  EXPECT_TRUE(init.initialised());
  EXPECT_EQ(init.Reason(500), "");
}

}  // namespace
}  // namespace esdslam
