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
  if (options_.dense)
    dense_ = std::make_unique<DenseMapper>(PinholeCamera(settings_.core.camera), settings_.dense, options_.threaded_dense);
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
  if (const GeometryFilter* geometry = system_->geometry_filter()) step.geometry_mask = geometry->last().mask;
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
  if (step.outcome.new_keyframe) AddDenseKeyframe(i, images, Union(step.mask.mask, step.geometry_mask));
  if (!options_.debug_frames_dir.empty()) WriteDebugFrame(step, images);
  return step;
}

void DynamicRun::AddDenseKeyframe(std::size_t i, const RgbdImages& images, const cv::Mat& mask) {
  if (!dense_) return;
  const cv::Mat final_mask = mask.empty() ? cv::Mat::zeros(images.depth_m.size(), CV_8U) : mask;
  dense_->AddKeyframe(static_cast<long>(i), images.bgr, images.depth_m, final_mask);
  dense_timestamps_[static_cast<long>(i)] = frames_[i].timestamp;
  keyframe_masks_[static_cast<long>(i)] = final_mask;
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
  // Final poses of the live keyframes; culled keyframes are removed from the dense map.
  std::map<double, Rigid3> live;
  for (const StampedPose& pose : system_->KeyFrameTrajectory()) live[pose.timestamp] = pose.world_from_cam;
  std::map<long, Rigid3> world_from_keyframe;
  const std::string masks_dir = out_dir + "/masks";
  std::filesystem::create_directories(masks_dir);
  for (const auto& [id, timestamp] : dense_timestamps_) {
    const auto it = live.find(timestamp);
    if (it == live.end()) {
      dense_->RemoveKeyframe(id);
      continue;
    }
    world_from_keyframe[id] = it->second;
    const std::string path = fmt::format("{}/{:.6f}.png", masks_dir, timestamp);
    if (!cv::imwrite(path, keyframe_masks_.at(id))) throw Error("cannot write " + path);
  }
  const DenseOutputSummary summary = WriteDenseOutputs(dense_->map(), world_from_keyframe, out_dir);
  spdlog::info("dense: {} points from {} keyframes, {} occupied octomap leaves, build {:.0f} ms", summary.points,
               summary.keyframes, summary.occupied_leaves, summary.build_ms);
}

}  // namespace esdslam
