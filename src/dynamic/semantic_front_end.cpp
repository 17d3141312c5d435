#include "dynamic/semantic_front_end.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/timer.h"
#include "dynamic/mask_dilation.h"

namespace esdslam {
namespace {

constexpr std::size_t kPoseHistory = 64;

cv::Mat Dilate(const cv::Mat& mask, int radius_px) { return DilateEllipse(mask, radius_px); }

// Region growing decides the boundary band; the network's interior (mask eroded by
// kCoreErosionPx) stays dynamic even where growth did not reach it (parts split off by an
// occluder, depth steps inside a person).
constexpr int kCoreErosionPx = 3;
cv::Mat KeepMaskCore(cv::Mat refined, const cv::Mat& raw_mask) {
  cv::Mat core;
  cv::erode(raw_mask, core, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * kCoreErosionPx + 1, 2 * kCoreErosionPx + 1)));
  refined.setTo(255, core);
  return refined;
}

}  // namespace

cv::Mat WarpMask(const cv::Mat& mask, const cv::Mat& depth_a, const Rigid3& b_from_a, const PinholeCamera& camera,
                 int dilation_px) {
  if (mask.type() != CV_8U || depth_a.type() != CV_32F || mask.size() != depth_a.size())
    throw Error("WarpMask: expected CV_8U mask and CV_32F depth of the same size");
  cv::Mat warped = cv::Mat::zeros(mask.size(), CV_8U);
  for (int v = 0; v < mask.rows; ++v) {
    const std::uint8_t* m = mask.ptr<std::uint8_t>(v);
    const float* z = depth_a.ptr<float>(v);
    for (int u = 0; u < mask.cols; ++u) {
      if (!m[u]) continue;
      if (!(z[u] > 0)) {  // no depth: cannot be moved, keep in place
        warped.at<std::uint8_t>(v, u) = 255;
        continue;
      }
      const Vec3 p_b = b_from_a * camera.Backproject(Vec2(u, v), z[u]);
      if (p_b.z() <= 0) continue;
      const Vec2 px = camera.Project(p_b);
      const int ub = static_cast<int>(std::lround(px.x())), vb = static_cast<int>(std::lround(px.y()));
      if (ub >= 0 && vb >= 0 && ub < mask.cols && vb < mask.rows) warped.at<std::uint8_t>(vb, ub) = 255;
    }
  }
  // Forward warping leaves pinholes where the surface is magnified: close them, then grow.
  cv::morphologyEx(warped, warped, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  return Dilate(warped, dilation_px);
}

SemanticFrontEnd::SemanticFrontEnd(const SemanticSettings& settings, const RegionGrowingOptions& growing,
                                   const PinholeCamera& camera, int mask_dilation_px, int warp_dilation_px)
    : mode_(settings.mode),
      groups_(settings.groups, settings.onnx.class_names),
      growing_(growing),
      camera_(camera),
      mask_dilation_px_(mask_dilation_px),
      warp_dilation_px_(warp_dilation_px) {
  growing_.Check();
  SegmentationWorkerOptions options;
  options.mode = settings.mode;
  worker_ = std::make_unique<SegmentationWorker>(MakeSegmenter(settings), options);
}

SemanticFrontEnd::~SemanticFrontEnd() { Stop(); }

void SemanticFrontEnd::Stop() {
  if (worker_) worker_->Stop();
}

void SemanticFrontEnd::Submit(std::int64_t id, double timestamp, const cv::Mat& bgr) {
  if (!worker_->Submit({id, timestamp, bgr})) throw Error("semantic: segmentation worker stopped");
}

DynamicMaskResult SemanticFrontEnd::MaskFor(std::int64_t id, const cv::Mat& depth_m) {
  DynamicMaskResult out;
  Stopwatch wait;
  const std::optional<SegmentedFrame> done =
      mode_ == SegmentationMode::kEveryFrame ? worker_->WaitFor(id) : worker_->Latest();
  out.wait_ms = wait.ElapsedMs();
  if (!done) return out;  // real time: nothing segmented yet
  Stopwatch refine;
  out.source_id = done->id;
  out.segment_ms = done->result.segment_ms;
  out.latency_ms = done->latency_ms;
  SemanticMasks masks = groups_.Masks(done->result.labels);
  if (done->id != id) {
    masks.dynamic = CarryToFrame(masks.dynamic, done->id, id);
    masks.potentially_dynamic = CarryToFrame(masks.potentially_dynamic, done->id, id);
    masks.static_objects = CarryToFrame(masks.static_objects, done->id, id);
    out.warped = true;
  }
  Stopwatch grow;
  ThreadCpuStopwatch grow_cpu;
  cv::Mat refined = RefineDynamicMask(masks.dynamic, depth_m, growing_);
  out.grow_ms = grow.ElapsedMs();
  out.grow_cpu_ms = grow_cpu.ElapsedMs();
  out.mask = Dilate(KeepMaskCore(refined, masks.dynamic), mask_dilation_px_);
  out.potentially_dynamic = masks.potentially_dynamic;
  out.static_objects = masks.static_objects;
  out.refine_ms = refine.ElapsedMs();
  out.dynamic_fraction = static_cast<double>(cv::countNonZero(out.mask)) / std::max<int>(1, out.mask.total());
  return out;
}

void SemanticFrontEnd::RecordPose(std::int64_t id, const cv::Mat& depth_m, const std::optional<Rigid3>& world_from_cam) {
  if (mode_ != SegmentationMode::kNewestWins || !world_from_cam) return;
  poses_.push_back({id, depth_m, *world_from_cam});
  if (poses_.size() > kPoseHistory) poses_.pop_front();
}

const SemanticFrontEnd::PoseRecord* SemanticFrontEnd::Record(std::int64_t id) const {
  for (const PoseRecord& record : poses_) {
    if (record.id == id) return &record;
  }
  return nullptr;
}

// The source frame's mask moved to frame `id`: current pose predicted by the constant velocity
// of the last two tracked frames (per frame step), applied from the last tracked frame.
cv::Mat SemanticFrontEnd::CarryToFrame(const cv::Mat& mask, std::int64_t source_id, std::int64_t id) const {
  const PoseRecord* source = Record(source_id);
  if (source == nullptr || poses_.empty()) return Dilate(mask, warp_dilation_px_);
  const PoseRecord& last = poses_.back();
  Rigid3 cam_from_world = last.world_from_cam.inverse();
  if (poses_.size() >= 2) {
    const PoseRecord& before = poses_[poses_.size() - 2];
    const Rigid3 step = last.world_from_cam.inverse() * before.world_from_cam;  // last_from_before
    const std::int64_t gap = std::max<std::int64_t>(1, last.id - before.id);
    if (gap == 1) {
      for (std::int64_t k = last.id; k < id; ++k) cam_from_world = step * cam_from_world;
    }
  }
  return WarpMask(mask, source->depth_m, cam_from_world * source->world_from_cam, camera_, warp_dilation_px_);
}

}  // namespace esdslam
