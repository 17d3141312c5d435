// The public API (include/esdslam/esdslam.h) on the synthetic dynamic sequence, single-threaded:
// the same trajectory as the CLI, a caller's labels give the same trajectory as the folder
// segmenter fed the same labels, a caller's masks the same accuracy, and the callbacks report
// what the results say.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "esdslam/esdslam.h"
#include "eval/ate.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "support/program.h"
#include "support/temp_path.h"
#include "system/dynamic_sequence.h"

namespace esdslam {
namespace {

constexpr int kFrames = 60;

const std::string& Sequence() { return testing::DynamicTestSequence(kFrames); }

struct Input {
  bool labels = false;  // the ground-truth labels (labels/<t>.png) with each frame
  bool masks = false;   // the ground-truth dynamic masks (masks/<t>.png) with each frame
};

// Tracks every frame of the sequence through the API; returns the final trajectory.
std::vector<TimedPose> Track(const SystemConfig& config, Input input, std::vector<TrackResult>* results = nullptr,
                             Callbacks callbacks = {}) {
  const TumSequence sequence = TumSequence::Open(Sequence());
  System slam(config);
  slam.SetCallbacks(std::move(callbacks));
  for (const FrameEntry& entry : sequence.frames()) {
    const std::string stamp = std::filesystem::path(entry.rgb_path).stem().string();
    const cv::Mat bgr = cv::imread(entry.rgb_path, cv::IMREAD_COLOR);
    const cv::Mat depth = cv::imread(entry.depth_path, cv::IMREAD_UNCHANGED);
    const cv::Mat labels = input.labels ? cv::imread(Sequence() + "/labels/" + stamp + ".png", cv::IMREAD_UNCHANGED) : cv::Mat();
    const cv::Mat mask = input.masks ? cv::imread(Sequence() + "/masks/" + stamp + ".png", cv::IMREAD_UNCHANGED) : cv::Mat();
    const TrackResult result = slam.Track(bgr, depth, entry.timestamp, mask, labels);
    if (results) results->push_back(result);
  }
  slam.Shutdown();
  return slam.Trajectory();
}

SystemConfig SingleThread(const std::string& settings) {
  SystemConfig config;
  config.settings_file = settings;
  config.single_thread = true;
  return config;
}

std::vector<StampedPose> Internal(const std::vector<TimedPose>& poses) {
  std::vector<StampedPose> out;
  for (const TimedPose& p : poses) {
    Mat4 m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m(r, c) = p.world_from_cam[static_cast<std::size_t>(4 * r + c)];
    out.push_back({p.timestamp, Rigid3::FromMatrix(m)});
  }
  return out;
}

double Ate(const std::vector<TimedPose>& poses) {
  return ComputeAte(ReadTumTrajectory(Sequence() + "/groundtruth.txt"), Internal(poses)).translation_m.rmse;
}

TEST(ApiSlow, SameTrajectoryAsTheCliSingleThreaded) {
  const std::string out = testing::TestTempPath("api_cli");
  const testing::ShellResult cli = testing::RunShell(testing::EsdslamProgram() + " run --single-thread --settings " +
                                                     Sequence() + "/run.yaml --sequence " + Sequence() + " --out " + out);
  ASSERT_EQ(cli.exit_code, 0) << cli.output;
  SystemConfig config = SingleThread(Sequence() + "/run.yaml");
  config.out_dir = testing::TestTempPath("api_out");
  const std::vector<TimedPose> poses = Track(config, {});
  EXPECT_EQ(poses.size(), static_cast<std::size_t>(kFrames));
  EXPECT_EQ(testing::ReadTextFile(config.out_dir + "/trajectory.txt"), testing::ReadTextFile(out + "/trajectory.txt"));
  EXPECT_TRUE(std::filesystem::exists(config.out_dir + "/timing.csv"));
  EXPECT_TRUE(std::filesystem::exists(config.out_dir + "/settings_used.yaml"));
}

TEST(ApiSlow, CallerLabelsGiveTheFolderSegmentersTrajectory) {
  SystemConfig folder_config = SingleThread(Sequence() + "/run.yaml");
  folder_config.segment_every = 1;  // the caller's labels come with every frame
  const std::vector<TimedPose> folder = Track(folder_config, {});
  SystemConfig config = SingleThread(Sequence() + "/run.yaml");  // Semantic.segmenter: folder is replaced
  config.label_input = true;
  const std::vector<TimedPose> given = Track(config, {/*labels=*/true});
  ASSERT_EQ(given.size(), folder.size());
  for (std::size_t i = 0; i < given.size(); ++i) {
    EXPECT_EQ(given[i].timestamp, folder[i].timestamp);
    EXPECT_EQ(given[i].world_from_cam, folder[i].world_from_cam) << "frame " << i;
  }
  std::printf("ATE with the folder segmenter %.5f m, with the caller's labels %.5f m\n", Ate(folder), Ate(given));
}

TEST(ApiSlow, CallerMasksGiveTheAccuracyOfTheFolderSegmenter) {
  SystemConfig folder_config = SingleThread(Sequence() + "/run.yaml");
  folder_config.segment_every = 1;
  const double folder = Ate(Track(folder_config, {}));
  SystemConfig config = SingleThread(Sequence() + "/settings.yaml");
  config.mode = "geometry";  // no network: the caller's mask is the semantic part
  const double masks = Ate(Track(config, {false, /*masks=*/true}));
  config.mode = "none";
  const double none = Ate(Track(config, {}));
  std::printf("ATE: folder segmenter %.5f m, caller's masks (geometry mode) %.5f m, none %.5f m\n", folder, masks, none);
  EXPECT_LE(masks, folder * 1.1);
  EXPECT_LT(masks, none);
}

TEST(ApiSlow, CallbacksFollowTheResults) {
  int keyframes_added = 0;
  Callbacks callbacks;
  callbacks.keyframe_added = [&](const KeyFrameInfo& keyframe) {
    ++keyframes_added;
    EXPECT_GE(keyframe.id, 0);
  };
  std::vector<TrackResult> results;
  SystemConfig config = SingleThread(Sequence() + "/run.yaml");
  config.segment_every = 1;
  Track(config, {}, &results, callbacks);
  int new_keyframes = 0;
  for (const TrackResult& r : results) new_keyframes += r.new_keyframe;
  EXPECT_GT(new_keyframes, 1);
  EXPECT_EQ(keyframes_added, new_keyframes);
  EXPECT_EQ(results.back().status, TrackingStatus::kOk);
  EXPECT_GT(results.back().stats.keypoints, 0);
  EXPECT_EQ(results.back().stats.label_age, 0);  // labels every frame (the folder segmenter, K = 1)
  EXPECT_EQ(results.back().stats.index, kFrames - 1);
}

TEST(ApiSlow, SettingsTextActsAsTheFile) {
  std::ifstream in(Sequence() + "/run.yaml");
  std::stringstream text;
  text << in.rdbuf();
  SystemConfig config = SingleThread("");
  config.settings_text = text.str();
  System from_text(config);
  System from_file(SingleThread(Sequence() + "/run.yaml"));
  EXPECT_EQ(from_text.EffectiveSettings(), from_file.EffectiveSettings());
}

TEST(ApiSlow, MapAccessorsAndSaveLoad) {
  const TumSequence sequence = TumSequence::Open(Sequence());
  SystemConfig config = SingleThread(Sequence() + "/run.yaml");
  config.viewer_port = 0;  // any free port
  System slam(config);
  EXPECT_EQ(slam.ViewerUrl().rfind("http://127.0.0.1:", 0), 0u) << slam.ViewerUrl();
  for (const FrameEntry& entry : sequence.frames())
    slam.Track(cv::imread(entry.rgb_path, cv::IMREAD_COLOR), cv::imread(entry.depth_path, cv::IMREAD_UNCHANGED),
               entry.timestamp);
  slam.Shutdown();
  EXPECT_THROW(slam.Track(cv::Mat(), cv::Mat(), 0), std::runtime_error);
  const std::vector<KeyFrameInfo> keyframes = slam.KeyFrames();
  const std::vector<MapPointInfo> points = slam.MapPoints();
  ASSERT_GT(keyframes.size(), 1u);
  ASSERT_GT(points.size(), 100u);
  EXPECT_EQ(keyframes.front().world_from_cam[0], 1.0);  // world = the first keyframe's camera
  for (const MapPointInfo& p : points) EXPECT_GE(p.observations, 1);
  const std::string map = testing::TestTempPath("api_map") + ".map";
  slam.SaveMap(map);
  SystemConfig reload = SingleThread(Sequence() + "/run.yaml");
  reload.load_map = map;
  reload.localization = true;
  System again(reload);
  EXPECT_EQ(again.KeyFrames().size(), keyframes.size());
}

}  // namespace
}  // namespace esdslam
