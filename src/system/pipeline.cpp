#include "system/pipeline.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common/error.h"
#include "io/trajectory_io.h"
#include "tracking/frame.h"

namespace esdslam {
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

// The frame's images must have the size the camera settings describe (else the intrinsics do
// not fit them).
void CheckImageSize(const RgbdFrame& frame, const CameraIntrinsics& camera) {
  if (frame.bgr.cols == camera.width && frame.bgr.rows == camera.height) return;
  throw Error(fmt::format("frame {:.6f}: image is {}x{}, but the settings' Camera.width/Camera.height are {}x{}",
                          frame.timestamp, frame.bgr.cols, frame.bgr.rows, camera.width, camera.height));
}

// The caller's dynamic mask (RgbdFrame::dynamic_mask): empty, or CV_8U of the image's size.
cv::Mat CheckedMask(const RgbdFrame& frame) {
  const cv::Mat& mask = frame.dynamic_mask;
  if (mask.empty()) return mask;
  if (mask.type() != CV_8UC1 || mask.size() != frame.bgr.size())
    throw Error(fmt::format("frame {:.6f}: the dynamic mask must be CV_8UC1 of the image's size {}x{}, got type {} "
                            "size {}x{}",
                            frame.timestamp, frame.bgr.cols, frame.bgr.rows, mask.type(), mask.cols, mask.rows));
  return mask;
}

const RunConfig& Checked(const RunConfig& config) {
  config.Check();
  return config;
}

}  // namespace

KeypointCounts CountKeypoints(const FeatureSet& features) {
  KeypointCounts counts;
  counts.total = features.size();
  for (const std::uint8_t flag : features.is_dynamic) {
    counts.dynamic += flag != 0;
    counts.by_geometry += flag == kDynamicByGeometry;
  }
  return counts;
}

Pipeline::Pipeline(const RunConfig& config) : config_(Checked(config)) {
  const RunSettings& settings = config_.settings;
  if (UsesSegmentation(config_.pipeline.mode)) {
    std::unique_ptr<Segmenter> segmenter;
    if (settings.semantic.kind == SemanticSettings::Kind::kProvided) {
      provided_labels_ = std::make_shared<ProvidedLabels>();
      segmenter = std::make_unique<ProvidedLabelsSegmenter>(provided_labels_);
    } else {
      segmenter = MakeSegmenter(settings.semantic);
    }
    masks_ = std::make_unique<MaskAhead>(
        std::make_unique<SemanticFrontEnd>(std::move(segmenter), settings.semantic, settings.region_growing,
                                           settings.mask_refine, config_.slam.single_thread),
        ThreadedOrInline(!config_.slam.single_thread));
  }
  system_ = std::make_unique<SlamSystem>(settings.core, config_.slam);
  if (config_.pipeline.dense) {
    dense_poses_ = std::make_unique<SlamKeyframePoses>(&system_->map());
    DenseMapperOptions dense_options;
    dense_options.threaded = config_.pipeline.threaded_dense;
    dense_options.mask_dir = config_.pipeline.dense_mask_dir;
    dense_ = std::make_unique<DenseMapper>(PinholeCamera(settings.core.camera), settings.dense,
                                           [poses = dense_poses_.get()] { return poses->Poses(); }, dense_options);
  }
}

Pipeline::~Pipeline() {
  try {
    if (masks_) masks_->Stop();
    if (dense_) dense_->Finish();
  } catch (const std::exception& e) {
    spdlog::error("run: shutdown failed: {}", e.what());
  }
}

void Pipeline::SubmitAhead(const RgbdFrame& frame) {
  if (slam_stopped_) throw Error("pipeline: frame submitted after Finish");
  if (!frame.labels.empty() && !provided_labels_)
    throw Error(fmt::format("frame {:.6f}: labels given, but the run does not take them (mode {}, Semantic.segmenter "
                            "is not provided)",
                            frame.timestamp, ToString(config_.pipeline.mode)));
  if (provided_labels_ && frame.labels.empty())
    throw Error(fmt::format("frame {:.6f}: no labels given (Semantic.segmenter: provided needs each frame's labels)",
                            frame.timestamp));
  if (provided_labels_) provided_labels_->Put(frame.timestamp, frame.labels);
  if (masks_) masks_->Label(next_id_, frame.timestamp, frame.bgr);
  ++next_id_;
  ahead_.push_back(frame);
}

// The masks of the frames up to `last_id` that are submitted ahead queued on the mask stage.
void Pipeline::QueueMasks(std::int64_t last_id) {
  if (!masks_) return;
  const std::int64_t first_ahead = next_id_ - static_cast<std::int64_t>(ahead_.size());
  for (; next_masked_ <= last_id && next_masked_ < next_id_; ++next_masked_) {
    const RgbdFrame& frame = ahead_[static_cast<std::size_t>(next_masked_ - first_ahead)];
    masks_->Submit(next_masked_, frame.timestamp, frame.bgr, frame.depth_m);
  }
}

FrameReport Pipeline::Track(const RgbdFrame& frame) {
  if (slam_stopped_) throw Error("pipeline: Track after Finish");
  CheckImageSize(frame, config_.settings.core.camera);
  if (ahead_.empty()) SubmitAhead(frame);
  if (ahead_.front().timestamp != frame.timestamp)
    throw Error(fmt::format("pipeline: frame {:.6f} tracked, but frame {:.6f} was submitted first", frame.timestamp,
                            ahead_.front().timestamp));
  FrameReport report;
  report.index = next_id_ - static_cast<std::int64_t>(ahead_.size());
  QueueMasks(report.index + 1);  // this frame's mask and the next one's, made while this one is tracked
  ahead_.pop_front();
  report.timestamp = frame.timestamp;
  report.bgr = frame.bgr;
  if (masks_) {
    MaskAheadResult made = masks_->MaskFor(report.index, frame.bgr, frame.depth_m);
    report.mask = std::move(made.mask);
    report.mask_wait_ms = made.wait_ms;
    labels_seen_ = labels_seen_ || report.mask.source_id >= 0;
    if (report.mask.late_frame >= 0) ApplyLateMask(report.mask.late_frame, report.mask.late_mask);
  }
  report.mask.mask = Union(report.mask.mask, CheckedMask(frame));
  report.track = system_->TrackRgbd(frame.bgr, frame.depth_m, frame.timestamp, report.mask.mask,
                                    GeometryExempt(report.mask));
  report.features = system_->last_frame().shared_features();
  report.keypoints = CountKeypoints(*report.features);
  if (report.track.new_keyframe) {
    const cv::Mat dense_mask = Union(report.mask.mask, report.geometry_mask());
    if (masks_ && !labels_seen_ && report.track.keyframe != nullptr)
      unlabelled_keyframes_.push_back({report.index, frame, dense_mask, report.track.keyframe});
    else
      AddDenseKeyframe(frame, dense_mask, report.track.keyframe);
  }
  return report;
}

// The first labels came for frame `frame_index`, which was tracked without them: the map points
// its keyframe (if it made one) placed on the dynamic mask are removed, and the held keyframes go
// to the dense mapper, that one with the late mask.
void Pipeline::ApplyLateMask(std::int64_t frame_index, const cv::Mat& late_mask) {
  for (UnlabelledKeyframe& held : unlabelled_keyframes_) {
    if (held.index != frame_index) continue;
    held.mask = Union(held.mask, late_mask);
    const int removed = system_->RemovePointsUnder(held.keyframe, late_mask);
    spdlog::info("semantic: the first labels (frame {}) came after their frame was tracked: {} map points of its "
                 "keyframe on the dynamic mask removed",
                 frame_index, removed);
  }
  ReleaseUnlabelledKeyframes();
}

void Pipeline::ReleaseUnlabelledKeyframes() {
  for (const UnlabelledKeyframe& held : unlabelled_keyframes_) AddDenseKeyframe(held.frame, held.mask, held.keyframe);
  unlabelled_keyframes_.clear();
}

void Pipeline::AddDenseKeyframe(const RgbdFrame& frame, const cv::Mat& mask, KeyFrame* keyframe) {
  if (!dense_ || keyframe == nullptr) return;
  dense_poses_->Register(keyframe);
  dense_->AddKeyframe({keyframe->id(), frame.timestamp, keyframe->world_from_cam(), frame.bgr, frame.depth_m, mask});
}

void Pipeline::StopSlam() {
  if (slam_stopped_) return;
  slam_stopped_ = true;
  if (masks_) masks_->Stop();
  ReleaseUnlabelledKeyframes();  // no labels came: the dense map takes them as they are
  system_->Shutdown();
}

void Pipeline::Finish(const std::string& out_dir) {
  if (finished_) return;
  finished_ = true;
  StopSlam();
  if (!dense_) return;
  std::string dense_error;  // the keyframes integrated so far are still written
  try {
    dense_->Finish();
  } catch (const Error& e) {
    dense_error = e.what();
  }
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
  if (!dense_error.empty()) throw Error(dense_error);
}

}  // namespace esdslam
