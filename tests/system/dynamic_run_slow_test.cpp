// The dynamic stages in the running system on a synthetic room with walking people whose VOC
// labels come from the folder segmenter: perfect labels (labels/), or coarse ones (labels_coarse/:
// person masks dilated or eroded, as a network's masks bleed onto the background or lose limbs).
// In every mode but none, keypoints on the movers are removed (precision and recall against the
// ground-truth masks) and no live map point lies on a mover; refined masks match the ground truth
// better than the coarse labels; mode none differs.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "eval/ate.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "map/keyframe.h"
#include "map/map_point.h"
#include "system/dynamic_sequence.h"
#include "system/pipeline.h"
#include "system/run_loop.h"
#include "support/temp_path.h"

namespace esdslam {
namespace {

constexpr int kFrames = 50;
constexpr int kVocPerson = 15;

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
  int geometry_flagged = 0, geometry_culled = 0;
  int points_from_movers = 0, live_points = 0;             // live map points at the end
  double ate_rmse = 0;
  double refined_iou = 0, raw_iou = 0;                     // mean over frames with a person mask
};

double IoU(const cv::Mat& a, const cv::Mat& b) {
  const int inter = cv::countNonZero(a & b), uni = cv::countNonZero(a | b);
  return uni == 0 ? 1.0 : static_cast<double>(inter) / uni;
}

// labels_coarse/: each frame's person pixels dilated by 8 px (even frames) or eroded by 6 px
// (odd frames); everything else keeps its label. Returns the settings file that uses them.
std::string CoarseLabelSettings() {
  const std::string dir = SequenceDir() + "/labels_coarse";
  const std::string settings = SequenceDir() + "/run_coarse.yaml";
  if (std::filesystem::exists(settings)) return settings;
  std::filesystem::create_directories(dir);
  int index = 0;
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(SequenceDir() + "/labels")) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const auto& file : files) {
    cv::Mat labels = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
    const cv::Mat person = labels == kVocPerson;
    const int radius = index % 2 == 0 ? 8 : 6;
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
    cv::Mat coarse;
    if (index++ % 2 == 0) cv::dilate(person, coarse, kernel);
    else cv::erode(person, coarse, kernel);
    labels.setTo(0, person);
    labels.setTo(kVocPerson, coarse);
    cv::imwrite(dir + "/" + file.filename().string(), labels);
  }
  std::ifstream in(SequenceDir() + "/run.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  yaml.replace(yaml.find("/labels\n"), 8, "/labels_coarse\n");
  std::ofstream(settings) << yaml;
  return settings;
}

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

// Fraction of each frame's person mask (from the labels used) that the refined mask improves on.
void ScoreMasks(const FrameReport& report, const cv::Mat& gt, const std::string& labels_dir, RunOutcome* out,
                int* scored) {
  if (report.mask.mask.empty() || cv::countNonZero(gt) == 0) return;
  const cv::Mat labels = cv::imread(fmt::format("{}/{:.6f}.png", labels_dir, report.timestamp), cv::IMREAD_UNCHANGED);
  if (labels.empty()) return;
  out->refined_iou += IoU(report.mask.mask != 0, gt != 0);
  out->raw_iou += IoU(labels == kVocPerson, gt != 0);
  ++*scored;
}

// segment_every: 0 = the default label schedule (predicted masks between network frames); 1 =
// every frame's own labels.
RunOutcome RunMode(DynamicMode mode, const std::string& settings_path = SequenceDir() + "/run.yaml",
                   int segment_every = 0) {
  RunFlags flags;
  flags.segment_every = segment_every;
  flags.single_thread = true;
  flags.mode = mode;
  flags.mask_extraction = false;  // extract everywhere: the flags are what we measure
  const RunConfig config = ResolveRunConfig(LoadRunSettings(settings_path), flags);
  const RunSettings& settings = config.settings;
  TumFolderSource source(TumSequence::Open(SequenceDir()).frames(), settings.core.depth_map_factor);
  Pipeline run(config);
  RunOutcome out;
  int scored = 0;
  RunFrames(source, run, [&](const FrameReport& report) {
    out.tracked += report.track.has_pose;
    out.geometry_flagged += report.keypoints.by_geometry;
    out.geometry_culled += report.track.geometry.points_culled;
    const cv::Mat gt = GroundTruthMoverMask(report.timestamp);
    ScoreMasks(report, gt, settings.semantic.folder.folder, &out, &scored);
    const FeatureSet& features = *report.features;
    for (int k = 0; k < features.size(); ++k) {
      const cv::Point2f pt = features.keypoints[k].pt;
      const bool on_mover = gt.at<std::uint8_t>(cvRound(pt.y), cvRound(pt.x)) != 0;
      out.gt_on_mover += on_mover;
      out.flagged += features.is_dynamic[k] != 0;
      out.flagged_on_mover += on_mover && features.is_dynamic[k];
    }
  });
  run.Finish(testing::TestTempPath("dynamic_run_test_out"));
  out.points_from_movers = CountPointsFromMovers(run.system().map(), &out.live_points);
  out.ate_rmse = ComputeAte(ReadTumTrajectory(SequenceDir() + "/groundtruth.txt"), run.system().Trajectory())
                     .translation_m.rmse;
  if (scored > 0) out.refined_iou /= scored, out.raw_iou /= scored;
  std::printf("mode %s (%s): tracked %d, recall %.3f precision %.3f (%d GT keypoints on movers, %d flagged, %d by "
              "geometry), %d points culled by geometry, %d live points (%d from movers), ATE %.4f m, mask IoU refined "
              "%.3f raw %.3f\n",
              ToString(mode), settings_path.c_str(), out.tracked,
              static_cast<double>(out.flagged_on_mover) / std::max(1, out.gt_on_mover),
              static_cast<double>(out.flagged_on_mover) / std::max(1, out.flagged), out.gt_on_mover, out.flagged,
              out.geometry_flagged, out.geometry_culled, out.live_points, out.points_from_movers, out.ate_rmse,
              out.refined_iou, out.raw_iou);
  return out;
}

double Recall(const RunOutcome& out) { return static_cast<double>(out.flagged_on_mover) / std::max(1, out.gt_on_mover); }
double Precision(const RunOutcome& out) { return static_cast<double>(out.flagged_on_mover) / std::max(1, out.flagged); }

// Keypoints on the movers removed (recall, precision >= 0.9 over all frames), none of their
// points in the map (at most max_mover_point_share_percent % of the live points), every frame tracked
// accurately.
void ExpectMoversRemoved(const RunOutcome& out, double min_precision = 0.9, int max_mover_point_share_percent = 0) {
  EXPECT_EQ(out.tracked, kFrames);
  ASSERT_GT(out.gt_on_mover, 200) << "the movers must be visible in the test window";
  EXPECT_GE(Recall(out), 0.9);
  EXPECT_GE(Precision(out), min_precision);
  EXPECT_GT(out.live_points, 300);
  EXPECT_LE(out.points_from_movers, out.live_points * max_mover_point_share_percent / 100);
  EXPECT_LT(out.ate_rmse, 0.02);
}

// Every frame's own labels: almost nothing of the movers reaches the map.
// (At most 1 % of the live points: with the depth prior (Tracking.depthPrior) the keyframes fall
// on other frames, and 2 of 1266 points came from one keypoint on a mover's edge, outside its
// refined mask, that no keyframe used before.)
TEST(DynamicRunTest, SemanticModeRemovesMoverKeypointsAndKeepsThemOutOfTheMap) {
  ExpectMoversRemoved(RunMode(DynamicMode::kSemantic, SequenceDir() + "/run.yaml", 1), 0.9, 1);
}

// Predicted masks (labels every 4th frame) without the geometry check behind them: the carried
// mask misses a sliver of a mover now and then, so a few of its points can reach the map
// (measured: 3 of 1288); full mode (the default) culls them (next test: 0).
TEST(DynamicRunTest, SemanticModeWithPredictedMasksKeepsAlmostAllMoversOut) {
  ExpectMoversRemoved(RunMode(DynamicMode::kSemantic), 0.9, 1);
}

TEST(DynamicRunTest, FullModeRemovesMoverKeypointsAndKeepsThemOutOfTheMap) {
  ExpectMoversRemoved(RunMode(DynamicMode::kFull));
}

// No network: the geometry check alone. It cannot know anything in the first frames (the movers
// are mapped at initialisation) and misses a mover until it uncovers what the keyframes saw
// behind it, so it does not reach the 0.9 of the modes with semantics (measured: recall 0.63,
// precision 0.998, 207 live points from movers of 2005, ATE 0.017 m). What it does: flags almost only mover
// keypoints, culls mover points, and keeps the trajectory near the semantic modes' accuracy
// where mode none drifts (0.099 m).
TEST(DynamicRunTest, GeometryModeFindsMostMoverKeypointsAndCullsTheirMapPoints) {
  const RunOutcome geometry = RunMode(DynamicMode::kGeometry);
  const RunOutcome none = RunMode(DynamicMode::kNone);
  EXPECT_EQ(geometry.tracked, kFrames);
  EXPECT_GE(Recall(geometry), 0.55);
  EXPECT_GE(Precision(geometry), 0.9);
  EXPECT_GT(geometry.geometry_culled, 50);
  EXPECT_LT(geometry.points_from_movers, none.points_from_movers / 3);
  EXPECT_LT(geometry.ate_rmse, 0.03);
  EXPECT_LT(geometry.ate_rmse, none.ate_rmse / 2);
}

// Coarse person masks (bleeding onto the background, or missing limbs): region growing follows the
// depth silhouette, so the refined masks match the ground truth better, and full mode still
// removes the movers' keypoints and keeps them out of the map. Precision is lower (measured 0.885):
// the refined mask keeps the network mask's interior (eroded by 3 px), which for masks dilated by
// 8 px still covers 5 px of background around the person. Every frame's own labels: the raw
// IoU compares the labels of the frame the refined mask is made for.
TEST(DynamicRunTest, RefinedMasksBeatCoarseLabelsAndFullModeStillRemovesMovers) {
  const RunOutcome full = RunMode(DynamicMode::kFull, CoarseLabelSettings(), 1);
  EXPECT_GT(full.refined_iou, full.raw_iou);
  EXPECT_GT(full.refined_iou, 0.9);
  ExpectMoversRemoved(full, 0.85);
}

TEST(DynamicRunTest, ModeNoneMapsMoversAndFlagsNothing) {
  const RunOutcome none = RunMode(DynamicMode::kNone);
  EXPECT_EQ(none.flagged, 0);
  EXPECT_GT(none.points_from_movers, 0);
}

}  // namespace
}  // namespace esdslam
