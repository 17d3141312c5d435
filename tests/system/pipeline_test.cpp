// The pipeline on a short synthetic dynamic sequence (mode full, folder segmenter on perfect
// labels, single thread): one report per frame from the run loop, the frames given as images,
// the look-ahead order, and the same trajectory with or without look-ahead.
#include <algorithm>
#include <filesystem>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/error.h"
#include "io/memory_frame_source.h"
#include "io/tum_sequence.h"
#include "support/temp_path.h"
#include "system/dynamic_sequence.h"
#include "system/pipeline.h"
#include "system/run_loop.h"
#include "system/run_outputs.h"

namespace esdslam {
namespace {

constexpr int kFrames = 12;

// segment_every 1: every frame's labels (waited for); K > 1: predicted masks between.
RunConfig Config(int segment_every = 1, bool single_thread = true) {
  RunFlags flags;
  flags.single_thread = single_thread;
  flags.mode = DynamicMode::kFull;
  flags.segment_every = segment_every;
  return ResolveRunConfig(LoadRunSettings(testing::DynamicTestSequence(kFrames) + "/run.yaml"), flags);
}

std::vector<RgbdFrame> Frames(const RunConfig& config) {
  TumFolderSource source(TumSequence::Open(testing::DynamicTestSequence(kFrames)).frames(),
                         config.settings.core.depth_map_factor);
  std::vector<RgbdFrame> frames;
  while (std::optional<RgbdFrame> frame = source.Next()) frames.push_back(std::move(*frame));
  return frames;
}


TEST(PipelineTest, RunLoopReportsEveryFrameOnce) {
  const RunConfig config = Config();
  const std::vector<RgbdFrame> frames = Frames(config);
  ASSERT_EQ(frames.size(), static_cast<std::size_t>(kFrames));
  MemoryFrameSource source(frames);
  Pipeline pipeline(config);
  std::vector<FrameReport> reports;
  const std::string debug_dir = testing::TestTempPath("pipeline_debug");
  std::filesystem::create_directories(debug_dir);
  RunFrames(source, pipeline, [&](const FrameReport& report) {
    reports.push_back(report);
    WriteDebugFrame(debug_dir, report);
  });
  ASSERT_EQ(reports.size(), frames.size());
  int masked = 0;
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const FrameReport& r = reports[i];
    EXPECT_EQ(r.index, static_cast<std::int64_t>(i));
    EXPECT_EQ(r.timestamp, frames[i].timestamp);
    EXPECT_TRUE(r.track.has_pose) << i;
    EXPECT_EQ(r.label_age(), 0) << i;  // every-frame labels
    EXPECT_GE(r.load_ms, 0);
    ASSERT_NE(r.features, nullptr);
    const KeypointCounts counts = CountKeypoints(*r.features);
    EXPECT_EQ(r.keypoints.total, counts.total);
    EXPECT_EQ(r.keypoints.dynamic, counts.dynamic);
    EXPECT_EQ(r.keypoints.by_geometry, static_cast<int>(r.track.geometry.flagged_keypoints.size())) << i;
    EXPECT_EQ(r.bgr.data, frames[i].bgr.data);  // shared, not copied
    masked += r.mask.dynamic_fraction > 0;
    EXPECT_TRUE(std::filesystem::exists(fmt::format("{}/{:.6f}.png", debug_dir, r.timestamp)));
  }
  EXPECT_EQ(masked, kFrames);  // the people are in view from the first frame (perfect labels)
  EXPECT_EQ(reports.back().track.geometry.ran, true);
}

std::vector<FrameReport> RunAll(const RunConfig& config, const std::vector<RgbdFrame>& frames,
                                std::vector<StampedPose>* trajectory) {
  MemoryFrameSource source(frames);
  Pipeline pipeline(config);
  std::vector<FrameReport> reports;
  RunFrames(source, pipeline, [&](const FrameReport& report) { reports.push_back(report); });
  pipeline.StopSlam();
  *trajectory = pipeline.system().Trajectory();
  return reports;
}

// Labels every 4th frame, used from their own frame on, predicted masks between: frame j has those
// of the newest 4k <= j; a single-thread run repeats exactly, and does not depend on how far the
// run loop reads ahead (Semantic.lookAhead: 8 by default, 1 as on a camera).
TEST(PipelineTest, PredictedMasksFollowTheScheduleAndRepeatInASingleThreadRun) {
  const RunConfig config = Config(4);
  ASSERT_EQ(config.pipeline.look_ahead_frames, 8);
  RunConfig one_ahead = config;
  one_ahead.pipeline.look_ahead_frames = 1;
  const std::vector<RgbdFrame> frames = Frames(config);
  std::vector<StampedPose> first, second;
  const std::vector<FrameReport> a = RunAll(config, frames, &first), b = RunAll(one_ahead, frames, &second);
  ASSERT_EQ(a.size(), frames.size());
  for (std::size_t j = 0; j < a.size(); ++j) {
    const long expected_source = static_cast<long>(j / 4 * 4);  // labels used at their own frame
    EXPECT_EQ(a[j].mask.source_id, expected_source) << j;
    EXPECT_GT(a[j].mask.dynamic_fraction, 0.01) << j;  // the people, carried
    ASSERT_EQ(a[j].mask.mask.empty(), b[j].mask.mask.empty()) << j;
    if (!a[j].mask.mask.empty()) {
      EXPECT_EQ(cv::countNonZero(a[j].mask.mask != b[j].mask.mask), 0) << j;
    }
  }
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].world_from_cam.translation(), second[i].world_from_cam.translation()) << i;
    EXPECT_EQ(first[i].world_from_cam.rotation().coeffs(), second[i].world_from_cam.rotation().coeffs()) << i;
  }
}

// Threaded: tracking never waits for the network (labels are taken when they are back), the
// first frame's included. If frame 0's labels came after it was masked, one later frame hands out
// frame 0's late mask, and the first keyframe keeps no point on it.
TEST(PipelineTest, PredictedMasksNeverWaitInAThreadedRun) {
  const RunConfig config = Config(4, false);
  const std::vector<RgbdFrame> frames = Frames(config);
  MemoryFrameSource source(frames);
  Pipeline pipeline(config);
  std::vector<FrameReport> reports;
  RunFrames(source, pipeline, [&](const FrameReport& report) { reports.push_back(report); });
  pipeline.StopSlam();
  const std::vector<StampedPose> trajectory = pipeline.system().Trajectory();
  ASSERT_EQ(reports.size(), frames.size());
  int labelled = 0, late_masks = 0;
  std::int64_t last_source = -1;
  for (const FrameReport& r : reports) {
    EXPECT_EQ(r.mask.wait_ms, 0) << r.index;
    if (r.mask.late_frame >= 0) {
      ++late_masks;
      EXPECT_EQ(r.mask.late_frame, 0) << r.index;
      EXPECT_LT(reports.front().mask.source_id, 0);  // frame 0 was masked without labels
      KeyFrame* first_keyframe = reports.front().track.keyframe;
      ASSERT_NE(first_keyframe, nullptr);
      EXPECT_EQ(pipeline.system().RemovePointsUnder(first_keyframe, r.mask.late_mask), 0);  // none left
    }
    // Labels of earlier frames (or the frame's own), never of later ones, never going back. A
    // K-th frame that finds the network busy is owed to the next one, so sources need not be
    // multiples of 4.
    EXPECT_LE(r.mask.source_id, r.index) << r.index;
    EXPECT_GE(r.mask.source_id, last_source) << r.index;
    last_source = std::max(last_source, r.mask.source_id);
    labelled += r.mask.source_id >= 0;
  }
  EXPECT_GT(labelled, 0);
  EXPECT_LE(late_masks, 1);
  if (reports.front().mask.source_id < 0) {
    EXPECT_EQ(late_masks, 1);
  }
  EXPECT_EQ(trajectory.size(), frames.size());
}

// A caller without look-ahead (one Track per frame) gets the same trajectory: every-frame mode
// waits for each frame's labels either way.
TEST(PipelineTest, TrackWithoutLookAheadGivesTheSameTrajectory) {
  const RunConfig config = Config();
  const std::vector<RgbdFrame> frames = Frames(config);
  Pipeline ahead(config), direct(config);
  MemoryFrameSource source(frames);
  RunFrames(source, ahead, [](const FrameReport&) {});
  for (const RgbdFrame& frame : frames) direct.Track(frame);
  ahead.Finish(testing::TestTempPath("pipeline_ahead"));
  direct.Finish(testing::TestTempPath("pipeline_direct"));
  const std::vector<StampedPose> a = ahead.system().Trajectory(), b = direct.system().Trajectory();
  ASSERT_EQ(a.size(), frames.size());
  ASSERT_EQ(b.size(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].world_from_cam.translation(), b[i].world_from_cam.translation()) << i;
    EXPECT_EQ(a[i].world_from_cam.rotation().coeffs(), b[i].world_from_cam.rotation().coeffs()) << i;
  }
}

TEST(PipelineTest, FramesAreTrackedInSubmissionOrder) {
  const RunConfig config = Config();
  const std::vector<RgbdFrame> frames = Frames(config);
  Pipeline pipeline(config);
  pipeline.SubmitAhead(frames[0]);
  pipeline.SubmitAhead(frames[1]);
  EXPECT_THROW(pipeline.Track(frames[1]), Error);  // frame 0 waits first
  EXPECT_EQ(pipeline.Track(frames[0]).index, 0);
  EXPECT_EQ(pipeline.Track(frames[1]).index, 1);
  EXPECT_EQ(pipeline.Track(frames[2]).index, 2);  // not submitted ahead: submitted by Track
  pipeline.Finish(testing::TestTempPath("pipeline_order"));
  EXPECT_THROW(pipeline.Track(frames[3]), Error);
  EXPECT_THROW(pipeline.SubmitAhead(frames[3]), Error);
}

TEST(PipelineTest, SourceErrorsReachTheCallerAfterTheFramesBefore) {
  const RunConfig config = Config();
  std::vector<FrameEntry> entries = TumSequence::Open(testing::DynamicTestSequence(kFrames)).frames();
  entries.resize(4);
  entries[3].depth_path += ".missing";
  FolderSourceOptions strict;  // the first bad frame fails (default: skipped, see io/frame_source_test.cpp)
  strict.max_consecutive_bad_frames = 1;
  TumFolderSource source(entries, config.settings.core.depth_map_factor, strict);
  EXPECT_EQ(source.frame_count(), 4u);
  Pipeline pipeline(config);
  int reported = 0;
  EXPECT_THROW(RunFrames(source, pipeline, [&reported](const FrameReport&) { ++reported; }), InputError);
  EXPECT_EQ(reported, 3);  // frame 3 is read ahead; the frames read before it are tracked first
}

}  // namespace
}  // namespace esdslam
