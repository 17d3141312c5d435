#include "viewer/run_replay.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "io/trajectory_io.h"
#include "support/temp_path.h"
#include "system/frame_columns.h"
#include "viewer/viewer_test_frames.h"

namespace esdslam {
namespace {

// A run folder as `esdslam run` writes it: `frames` rows of timing.csv (the column table's
// header and rows), a pose per frame, a keyframe every 5 frames.
std::string WriteRunFolder(int frames) {
  const std::string dir = ::esdslam::testing::TestTempPath("run_replay");
  std::filesystem::create_directories(dir);
  std::ofstream timing(dir + "/timing.csv");
  timing << FrameCsvHeader() << "\n";
  std::vector<StampedPose> poses, keyframes;
  for (int i = 0; i < frames; ++i) {
    const FrameReport report = testing::MakeViewerFrame(i);
    timing << FrameCsvRow(ReadFrameColumns(report)) << "\n";
    StampedPose pose{report.timestamp, Rigid3(Quat::Identity(), Vec3(0.1 * i, 0, 0))};
    poses.push_back(pose);
    if (i % 5 == 0) keyframes.push_back(pose);
  }
  timing.close();
  WriteTumTrajectory(dir + "/trajectory.txt", poses);
  WriteTumTrajectory(dir + "/keyframes.txt", keyframes);
  return dir;
}

std::string EventData(const EventHub& hub, const std::string& name) {
  for (const HubEvent& event : hub.Latest())
    if (event.name == name) return event.data;
  return "";
}

TEST(RunReplay, PublishesTheRunsCountsLastRowMapAndTimeline) {
  const std::string dir = WriteRunFolder(12);
  EventHub hub;
  ViewerOptions options;
  const RunFiles files = PublishRun({dir, ""}, options, &hub);
  EXPECT_EQ(files.timing.rows.size(), 12u);
  const std::string frame = EventData(hub, "frame");
  EXPECT_NE(frame.find("\"frames\":12,"), std::string::npos) << frame;
  EXPECT_NE(frame.find("\"keyframes\":3,"), std::string::npos);
  EXPECT_NE(frame.find("\"poses\":12,"), std::string::npos);
  EXPECT_NE(frame.find("\"state\":\"OK\""), std::string::npos);
  EXPECT_NE(frame.find("\"extract_ms\":12.50"), std::string::npos);  // the last row's stage time
  const std::string map = EventData(hub, "map");
  EXPECT_NE(map.find("\"trajectory_count\":12,"), std::string::npos);
  EXPECT_NE(map.find("\"finished\":true"), std::string::npos);
  const std::string timeline = EventData(hub, "timeline");
  EXPECT_NE(timeline.find("\"rows\":[0,1,2,3,4,5,6,7,8,9,10,11]"), std::string::npos) << timeline.substr(0, 200);
  EXPECT_NE(timeline.find("\"state\":[\"OK\","), std::string::npos);
  EXPECT_NE(timeline.find("\"positions\":[0.000,0.000,0.000,0.100,"), std::string::npos);
  EXPECT_NE(EventData(hub, "status").find("\"replay\":true"), std::string::npos);
}

TEST(RunReplay, TimelineIsThinnedToTheLimitAndKeepsTheLastPose) {
  const std::string dir = WriteRunFolder(40);
  const RunFiles files = ReadRunFiles(dir, "");
  ViewerOptions options;
  options.max_trajectory = 4;
  const std::string timeline = EncodeReplayTimeline(files, options);
  EXPECT_NE(timeline.find("\"rows\":[0,10,20,30]"), std::string::npos) << timeline.substr(0, 200);
  EXPECT_NE(timeline.find(",3.900,0.000,0.000]"), std::string::npos);  // the last position (frame 39)
}

TEST(RunReplay, AFolderWithoutTheRunsFilesIsAnInputError) {
  EventHub hub;
  const std::string dir = ::esdslam::testing::TestTempPath("run_replay_empty");
  std::filesystem::create_directories(dir);
  EXPECT_THROW(PublishRun({dir, ""}, ViewerOptions(), &hub), InputError);
}

}  // namespace
}  // namespace esdslam
