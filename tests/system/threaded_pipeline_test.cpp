// Every thread of `esdslam run` at once on a short synthetic dynamic sequence: segmentation
// (folder segmenter, newest-wins hand-off), tracking with the geometry check (mode full), local
// mapping, loop closing and the dense mapper, each on its own thread. Checks that the run tracks
// every frame accurately, keeps movers out of the map and shuts down cleanly; tools/tsan.sh runs
// it under ThreadSanitizer.
#include <gtest/gtest.h>

#include <filesystem>

#include "eval/ate.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "support/temp_path.h"
#include "system/dynamic_sequence.h"
#include "system/pipeline.h"
#include "system/run_loop.h"

namespace esdslam {
namespace {

TEST(ThreadedPipelineTest, AllThreadsTogetherTrackEveryFrameAndShutDownCleanly) {
  constexpr int kFrames = 30;
  const std::string dir = testing::DynamicTestSequence(kFrames);
  RunFlags flags;
  flags.mode = DynamicMode::kFull;
  flags.realtime = true;
  flags.dense = true;
  flags.single_thread = false;
  const RunConfig config = ResolveRunConfig(LoadRunSettings(dir + "/run.yaml"), flags);
  ASSERT_TRUE(config.pipeline.threaded_dense);
  TumFolderSource source(TumSequence::Open(dir).frames(), config.settings.core.depth_map_factor);
  const std::string out = testing::TestTempPath("threaded_pipeline");
  int tracked = 0;
  {
    Pipeline run(config);
    RunFrames(source, run, [&tracked](const FrameReport& report) { tracked += report.track.has_pose; });
    ASSERT_NE(run.dense(), nullptr);
    run.Finish(out);
    const std::vector<StampedPose> trajectory = run.system().Trajectory();
    ASSERT_EQ(trajectory.size(), static_cast<std::size_t>(kFrames));
    const AteResult ate = ComputeAte(ReadTumTrajectory(dir + "/groundtruth.txt"), trajectory);
    std::printf("threaded full pipeline: %d/%d tracked, ATE %.4f m, %d keyframes\n", tracked, kFrames,
                ate.translation_m.rmse, run.system().num_keyframes());
    EXPECT_LT(ate.translation_m.rmse, 0.02);
    EXPECT_GE(run.system().num_keyframes(), 2);
  }
  EXPECT_EQ(tracked, kFrames);
  for (const char* file : {"dense.ply", "octomap.bt", "dense_keyframes.txt"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + file)) << file;
}

}  // namespace
}  // namespace esdslam
