// The semantic stage in the running system on a synthetic room with walking people whose VOC
// labels (labels/ folder, a perfect "network") come from the folder segmenter: keypoints on the
// movers are removed, no map point is made from a mover, and mode none differs.
#include <filesystem>
#include <algorithm>
#include <map>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "eval/ate.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "map/keyframe.h"
#include "map/map_point.h"
#include "system/dynamic_sequence.h"
#include "system/dynamic_run.h"

namespace esdslam {
namespace {

constexpr int kFrames = 50;

const std::string& SequenceDir() { return testing::DynamicTestSequence(kFrames); }

cv::Mat GroundTruthMoverMask(double timestamp) {
  const std::string path = fmt::format("{}/masks/{:.6f}.png", SequenceDir(), timestamp);
  cv::Mat mask = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (mask.empty()) throw Error("missing " + path);
  return mask;
}

struct RunOutcome {
  int tracked = 0;
  int gt_on_mover = 0, flagged = 0, flagged_on_mover = 0;  // keypoints, over all frames
  int points_from_movers = 0, live_points = 0;             // live map points at the end
  double ate_rmse = 0;
};

// A live map point comes from a mover if most of its keyframe observations lie on a GT mover.
int CountPointsFromMovers(Map& map, int* live) {
  std::map<double, cv::Mat> masks;
  int from_movers = 0;
  const std::vector<MapPoint*> points = map.map_points();
  *live = static_cast<int>(points.size());
  for (MapPoint* point : points) {
    int on = 0, total = 0;
    for (const auto& [keyframe, index] : point->observations()) {
      auto it = masks.find(keyframe->timestamp());
      if (it == masks.end()) it = masks.emplace(keyframe->timestamp(), GroundTruthMoverMask(keyframe->timestamp())).first;
      const cv::Point2f pt = keyframe->features().keypoints[index].pt;
      on += it->second.at<std::uint8_t>(cvRound(pt.y), cvRound(pt.x)) != 0;
      ++total;
    }
    if (2 * on > total && ++from_movers <= 3) {  // details of the first few
      for (const auto& [keyframe, index] : point->observations()) {
        const cv::Point2f pt = keyframe->features().keypoints[index].pt;
        const cv::Mat& gt = masks.at(keyframe->timestamp());
        int inside = 0;  // GT mover pixels in the 5x5 window: < 25 means a silhouette edge
        for (int dv = -2; dv <= 2; ++dv)
          for (int du = -2; du <= 2; ++du) {
            const int u = std::clamp(cvRound(pt.x) + du, 0, gt.cols - 1), v = std::clamp(cvRound(pt.y) + dv, 0, gt.rows - 1);
            inside += gt.at<std::uint8_t>(v, u) != 0;
          }
        std::printf("mover point %ld: keyframe %.6f px (%.1f, %.1f) dynamic %d, 5x5 GT inside %d\n", point->id(),
                    keyframe->timestamp(), pt.x, pt.y, keyframe->features().is_dynamic[index], inside);
      }
    }
  }
  return from_movers;
}

RunOutcome RunMode(DynamicMode mode) {
  const RunSettings settings = LoadRunSettings(SequenceDir() + "/run.yaml");
  const TumSequence sequence = TumSequence::Open(SequenceDir());
  SlamOptions slam;
  slam.single_thread = true;
  DynamicRunOptions options;
  options.mode = mode;
  options.mask_extraction = false;  // extract everywhere: the flags are what we measure
  DynamicRun run(settings, slam, options, sequence.frames());
  RunOutcome out;
  for (std::size_t i = 0; i < sequence.frames().size(); ++i) {
    const FrameStep step = run.Step(i);
    out.tracked += step.outcome.has_pose;
    const cv::Mat gt = GroundTruthMoverMask(step.timestamp);
    const FeatureSet& features = run.system().last_frame().features();
    for (int k = 0; k < features.size(); ++k) {
      const cv::Point2f pt = features.keypoints[k].pt;
      const bool on_mover = gt.at<std::uint8_t>(cvRound(pt.y), cvRound(pt.x)) != 0;
      out.gt_on_mover += on_mover;
      out.flagged += features.is_dynamic[k] != 0;
      out.flagged_on_mover += on_mover && features.is_dynamic[k];
    }
  }
  run.Finish((std::filesystem::temp_directory_path() / "esdslam_dynamic_run_test_out").string());
  out.points_from_movers = CountPointsFromMovers(run.system().map(), &out.live_points);
  out.ate_rmse = ComputeAte(ReadTumTrajectory(SequenceDir() + "/groundtruth.txt"), run.system().Trajectory())
                     .translation_m.rmse;
  return out;
}

TEST(DynamicRunTest, SemanticModeRemovesMoverKeypointsAndKeepsThemOutOfTheMap) {
  const RunOutcome semantic = RunMode(DynamicMode::kSemantic);
  EXPECT_EQ(semantic.tracked, kFrames);
  ASSERT_GT(semantic.gt_on_mover, 200) << "the movers must be visible in the test window";
  const double recall = static_cast<double>(semantic.flagged_on_mover) / semantic.gt_on_mover;
  const double precision = static_cast<double>(semantic.flagged_on_mover) / std::max(1, semantic.flagged);
  std::printf("recall %.3f precision %.3f (%d GT keypoints on movers, %d flagged)\n", recall, precision,
              semantic.gt_on_mover, semantic.flagged);
  EXPECT_GE(recall, 0.9);
  EXPECT_GE(precision, 0.9);
  EXPECT_GT(semantic.live_points, 300);
  EXPECT_EQ(semantic.points_from_movers, 0);
  EXPECT_LT(semantic.ate_rmse, 0.02);
}

TEST(DynamicRunTest, ModeNoneMapsMoversAndFlagsNothing) {
  const RunOutcome none = RunMode(DynamicMode::kNone);
  EXPECT_EQ(none.flagged, 0);
  EXPECT_GT(none.points_from_movers, 0);
}

}  // namespace
}  // namespace esdslam
