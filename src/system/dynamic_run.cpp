#include "system/dynamic_run.h"

#include <cmath>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "common/error.h"
#include "common/timer.h"
#include "tracking/frame.h"

namespace esdslam {

const char* ToString(DynamicMode mode) {
  switch (mode) {
    case DynamicMode::kNone: return "none";
    case DynamicMode::kSemantic: return "semantic";
    case DynamicMode::kGeometry: return "geometry";
    case DynamicMode::kFull: return "full";
  }
  return "?";
}

DynamicMode ParseDynamicMode(const std::string& text) {
  for (DynamicMode mode : {DynamicMode::kNone, DynamicMode::kSemantic, DynamicMode::kGeometry, DynamicMode::kFull})
    if (text == ToString(mode)) return mode;
  throw Error("unknown dynamic mode '" + text + "' (none | semantic | geometry | full)");
}

bool UsesSegmentation(DynamicMode mode) { return mode == DynamicMode::kSemantic || mode == DynamicMode::kFull; }
bool UsesGeometryCheck(DynamicMode mode) { return mode == DynamicMode::kGeometry || mode == DynamicMode::kFull; }

namespace {

// Where the geometry check is not applied: labelled static classes, and the semantic mask
// (already dynamic). Empty when neither exists.
cv::Mat GeometryExempt(const DynamicMaskResult& mask) {
  if (mask.mask.empty()) return mask.static_objects;
  if (mask.static_objects.empty()) return mask.mask;
  return mask.mask | mask.static_objects;
}

cv::Mat Union(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return a | b;
}

}  // namespace

DynamicRun::DynamicRun(const RunSettings& settings, const SlamOptions& slam_options, const DynamicRunOptions& options,
                       const std::vector<FrameEntry>& frames)
    : settings_(settings), options_(options), frames_(frames) {
  SlamOptions slam = slam_options;
  slam.geometry_check = UsesGeometryCheck(options_.mode);
  slam.geometry = settings_.geometry;
  if (UsesSegmentation(options_.mode)) {
    if (options_.realtime) settings_.semantic.mode = SegmentationMode::kNewestWins;
    semantic_ = std::make_unique<SemanticFrontEnd>(settings_.semantic, settings_.region_growing,
                                                   PinholeCamera(settings_.core.camera), settings_.mask_dilation_px);
    // Every-frame mode knows the mask before extraction; real time knows a carried mask.
    slam.frame.mask_extraction = options_.mask_extraction;
  }
  system_ = std::make_unique<SlamSystem>(settings_.core, slam);
  if (options_.dense) {
    dense_poses_ = std::make_unique<SlamKeyframePoses>(&system_->map());
    DenseMapperOptions dense_options;
    dense_options.threaded = options_.threaded_dense;
    dense_options.mask_dir = options_.dense_mask_dir;
    dense_ = std::make_unique<DenseMapper>(PinholeCamera(settings_.core.camera), settings_.dense,
                                           [poses = dense_poses_.get()] { return poses->Poses(); }, dense_options);
  }
  if (!options_.debug_frames_dir.empty()) std::filesystem::create_directories(options_.debug_frames_dir);
}

DynamicRun::~DynamicRun() {
  try {
    if (semantic_) semantic_->Stop();
    if (dense_) dense_->Finish();
  } catch (const std::exception& e) {
    spdlog::error("run: shutdown failed: {}", e.what());
  }
}

RgbdImages DynamicRun::Load(std::size_t i, double* load_ms) {
  Stopwatch watch;
  RgbdImages images = LoadRgbd(frames_[i], settings_.core.depth_map_factor);
  *load_ms += watch.ElapsedMs();
  if (semantic_) semantic_->Submit(static_cast<std::int64_t>(i), frames_[i].timestamp, images.bgr);
  return images;
}

FrameStep DynamicRun::Step(std::size_t i) {
  if (finished_) throw Error("run: Step after Finish");
  FrameStep step;
  step.timestamp = frames_[i].timestamp;
  RgbdImages images;
  if (next_ && next_->first == i) images = std::move(next_->second);
  else images = Load(i, &step.load_ms);
  next_.reset();
  // Look ahead: frame i+1 is segmented while frame i is extracted and tracked.
  if (i + 1 < frames_.size()) next_.emplace(i + 1, Load(i + 1, &step.load_ms));
  if (semantic_) step.mask = semantic_->MaskFor(static_cast<std::int64_t>(i), images.depth_m);
  step.outcome = system_->TrackRgbd(images.bgr, images.depth_m, step.timestamp, step.mask.mask, GeometryExempt(step.mask));
  step.geometry_mask = step.outcome.geometry.mask;
  const FeatureSet& features = system_->last_frame().features();
  step.keypoints = features.size();
  for (std::uint8_t flag : features.is_dynamic) {
    step.dynamic_keypoints += flag != 0;
    step.geometry_keypoints += flag == kDynamicByGeometry;
  }
  if (semantic_) {
    std::optional<Rigid3> pose;
    if (step.outcome.has_pose) pose = step.outcome.world_from_cam;
    semantic_->RecordPose(static_cast<std::int64_t>(i), images.depth_m, pose);
  }
  if (step.outcome.new_keyframe)
    AddDenseKeyframe(i, images, Union(step.mask.mask, step.geometry_mask), step.outcome.keyframe);
  if (!options_.debug_frames_dir.empty()) WriteDebugFrame(step, images);
  return step;
}

void DynamicRun::AddDenseKeyframe(std::size_t i, const RgbdImages& images, const cv::Mat& mask, KeyFrame* keyframe) {
  if (!dense_ || keyframe == nullptr) return;
  dense_poses_->Register(keyframe);
  dense_->AddKeyframe({keyframe->id(), frames_[i].timestamp, keyframe->world_from_cam(), images.bgr, images.depth_m, mask});
}

// Kept keypoints green, removed by the mask red, removed by the geometry check magenta; the
// refined semantic mask tinted cyan, the geometry mask tinted magenta (both outlined).
void DynamicRun::WriteDebugFrame(const FrameStep& step, const RgbdImages& images) const {
  cv::Mat picture = images.bgr.clone();
  const auto tint = [&picture](const cv::Mat& mask, const cv::Scalar& colour) {
    if (mask.empty() || cv::countNonZero(mask) == 0) return;
    cv::Mat blended;
    cv::addWeighted(picture, 0.65, cv::Mat(picture.size(), picture.type(), colour), 0.35, 0, blended);
    blended.copyTo(picture, mask);
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(mask.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    cv::drawContours(picture, contours, -1, colour, 2);
  };
  tint(step.mask.mask, cv::Scalar(255, 255, 0));
  tint(step.geometry_mask, cv::Scalar(255, 0, 255));
  const FeatureSet& features = system_->last_frame().features();
  for (int k = 0; k < features.size(); ++k) {
    const std::uint8_t flag = features.is_dynamic[k];
    const cv::Scalar colour = flag == kDynamicByGeometry ? cv::Scalar(255, 0, 255)
                              : flag != 0                ? cv::Scalar(0, 0, 255)
                                                         : cv::Scalar(0, 255, 0);
    cv::circle(picture, features.keypoints[k].pt, 3, colour, 1, cv::LINE_AA);
  }
  const std::string legend = fmt::format("{} kept (green), {} mask (red), {} geometry (magenta)",
                                         step.keypoints - step.dynamic_keypoints,
                                         step.dynamic_keypoints - step.geometry_keypoints, step.geometry_keypoints);
  cv::putText(picture, legend, cv::Point(8, 18), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
  cv::putText(picture, legend, cv::Point(8, 18), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  const std::string path = fmt::format("{}/{:.6f}.png", options_.debug_frames_dir, step.timestamp);
  if (!cv::imwrite(path, picture)) throw Error("cannot write " + path);
}

void DynamicRun::Finish(const std::string& out_dir) {
  if (finished_) return;
  finished_ = true;
  if (semantic_) semantic_->Stop();
  system_->Shutdown();
  if (!dense_) return;
  dense_->Finish();
  const DenseOutputSummary summary = dense_->WriteOutputs(out_dir);
  WriteTumTrajectory(out_dir + "/dense_keyframes.txt", dense_->map().StampedPoses(dense_->CurrentPoses()));
  const DenseMapperStats stats = dense_->stats();
  spdlog::info("dense: {} points from {} keyframes, {} occupied octomap leaves, final build {:.0f} ms "
               "(cloud {:.0f}, octomap {:.0f}); per keyframe {:.1f} ms (max {:.1f}, reading poses {:.1f}; CPU {:.1f}) on the dense "
               "thread, {} re-indexings ({:.1f} M points); hand-off {:.3f} ms (max {:.3f}); map {:.1f} MB + rays {:.1f} MB",
               summary.points, summary.keyframes, summary.occupied_leaves, summary.build_ms, summary.cloud_ms,
               summary.octomap_ms, stats.mean_keyframe_ms, stats.max_keyframe_ms, stats.mean_pose_ms, stats.mean_keyframe_cpu_ms,
               stats.map.reindexed_anchors, stats.map.reindexed_points / 1e6, stats.mean_handoff_ms, stats.max_handoff_ms, stats.map.point_bytes / 1e6,
               stats.map.ray_bytes / 1e6);
}

}  // namespace esdslam
