#include "dynamic/semantic_front_end.h"

#include <algorithm>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/timer.h"
#include "dynamic/mask_dilation.h"

namespace esdslam {
namespace {

cv::Mat Dilate(const cv::Mat& mask, int radius_px) { return DilateEllipse(mask, radius_px); }

// A full-resolution pixel distance at reduction `scale`, rounded (at least 1 where it was).
int Scaled(int px, int scale) { return px <= 0 ? px : std::max(1, (px + scale / 2) / scale); }

// Region growing decides the boundary band; the network's interior (mask eroded by
// kCoreErosionPx full-resolution pixels) stays dynamic even where growth did not reach it (parts
// split off by an occluder, depth steps inside a person).
constexpr int kCoreErosionPx = 3;
cv::Mat KeepMaskCore(cv::Mat refined, const cv::Mat& raw_mask, int scale) {
  const int radius = Scaled(kCoreErosionPx, scale);
  cv::Mat core;
  cv::erode(raw_mask, core, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * radius + 1, 2 * radius + 1)));
  refined.setTo(255, core);
  return refined;
}

// The growing options' pixel distances and areas for the image reduced by `scale`.
RegionGrowingOptions ScaledGrowing(RegionGrowingOptions options, int scale) {
  options.seed_erosion_px = Scaled(options.seed_erosion_px, scale);
  options.growth_band_px = Scaled(options.growth_band_px, scale);
  options.no_depth_dilation_px = Scaled(options.no_depth_dilation_px, scale);
  options.min_component_px /= scale * scale;
  return options;
}

std::optional<LabelSchedule> MakeSchedule(const SemanticSettings& settings) {
  if (!settings.predicted()) return std::nullopt;
  LabelScheduleOptions options;
  options.segment_every = settings.segment_every;
  options.label_delay_frames = settings.label_delay_frames;
  options.newest_wins = settings.mode == SegmentationMode::kNewestWins;
  return LabelSchedule(options);
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
                                   const MaskRefineOptions& refine, bool wait_for_due_labels)
    : SemanticFrontEnd(MakeSegmenter(settings), settings, growing, refine, wait_for_due_labels) {}

SemanticFrontEnd::SemanticFrontEnd(std::unique_ptr<Segmenter> segmenter, const SemanticSettings& settings,
                                   const RegionGrowingOptions& growing, const MaskRefineOptions& refine,
                                   bool wait_for_due_labels)
    : groups_(settings.groups, settings.onnx.class_names),
      growing_(growing),
      refine_(refine),
      wait_for_due_labels_(wait_for_due_labels),
      schedule_(MakeSchedule(settings)) {
  growing_.Check();
  refine_.Check();
  // The front end submits only the frames it wants labelled, at most one in flight in
  // predicted mode: the worker segments every submitted frame, in order.
  SegmentationWorkerOptions options;
  options.mode = SegmentationMode::kEveryFrame;
  worker_ = std::make_unique<SegmentationWorker>(std::move(segmenter), options);
}

SemanticFrontEnd::~SemanticFrontEnd() { Stop(); }

void SemanticFrontEnd::Stop() {
  if (worker_) worker_->Stop();
}

void SemanticFrontEnd::Submit(std::int64_t id, double timestamp, const cv::Mat& bgr) {
  if (schedule_) {
    std::unique_lock<std::mutex> lock(schedule_mutex_);
    RetireBackLabels(lock, /*wait=*/wait_for_due_labels_);
    if (!schedule_->Submit(id, needs_labels_)) return;
  }
  if (!worker_->Submit({id, timestamp, bgr})) throw Error("semantic: segmentation worker stopped");
}

// The frame in flight, when its labels are back, moved to ready_ (the network is free again).
// wait: waits for them (single-thread runs: the schedule then never finds the network busy, so
// the labelled frames do not depend on timing). schedule_mutex_ held by `lock`; released while
// waiting.
void SemanticFrontEnd::RetireBackLabels(std::unique_lock<std::mutex>& lock, bool wait) {
  const std::optional<std::int64_t> in_flight = schedule_->in_flight();
  if (!in_flight) return;
  std::optional<SegmentedFrame> done;
  if (wait) {
    lock.unlock();
    done = worker_->WaitFor(*in_flight);
    lock.lock();
    if (schedule_->in_flight() != in_flight) return;  // the other thread retired it meanwhile
  } else {
    done = worker_->Latest();  // one frame in flight: the newest result is it once it is back
    if (!done || done->id != *in_flight) return;
  }
  schedule_->Done();
  if (done) ready_.push_back(std::move(*done));  // nullopt: never segmented (stopped)
}

DynamicMaskResult SemanticFrontEnd::MaskFor(std::int64_t id, const cv::Mat& bgr, const cv::Mat& depth_m) {
  DynamicMaskResult out;
  Stopwatch refine;
  SemanticMasks masks;
  if (schedule_) {
    masks = PredictedMasks(id, bgr, depth_m, out);
  } else {
    Stopwatch wait;
    const std::optional<SegmentedFrame> done = worker_->WaitFor(id);
    out.wait_ms = wait.ElapsedMs();
    if (!done) return out;
    out.source_id = done->id;
    out.segment_ms = done->result.segment_ms;
    out.latency_ms = done->latency_ms;
    masks = groups_.Masks(done->result.labels);
  }
  if (out.source_id < 0) return out;  // no labels yet
  Refine(masks, depth_m, out);
  out.refine_ms = refine.ElapsedMs() - out.wait_ms;
  return out;
}

// Predicted mode: the frame added to the predictor, the labels due at this frame added, the
// newest labels carried to it.
SemanticMasks SemanticFrontEnd::PredictedMasks(std::int64_t id, const cv::Mat& bgr, const cv::Mat& depth_m,
                                               DynamicMaskResult& out) {
  Stopwatch predict;
  ThreadCpuStopwatch predict_cpu;
  if (!predictor_) predictor_ = std::make_unique<MaskPredictor>(bgr.size(), MaskPredictorOptions(), ClassGroups(groups_));
  predictor_->AddFrame(id, bgr, depth_m);
  const double add_ms = predict.ElapsedMs(), add_cpu_ms = predict_cpu.ElapsedMs();
  AddDueLabels(id, out);
  predict.Restart();
  predict_cpu.Restart();
  MaskPrediction prediction = predictor_->Predict();
  out.predict_ms = add_ms + predict.ElapsedMs();
  out.predict_cpu_ms = add_cpu_ms + predict_cpu.ElapsedMs();
  {
    std::lock_guard<std::mutex> lock(schedule_mutex_);
    needs_labels_ = prediction.needs_labels;
  }
  out.source_id = prediction.source_id;
  if (out.source_id < 0 && !wait_for_due_labels_) {
    unlabelled_depths_.emplace_back(id, depth_m);
    if (unlabelled_depths_.size() > kMaxUnlabelledFrames) unlabelled_depths_.pop_front();
  }
  out.warped = prediction.label_age > 0;
  out.trust = prediction.trust;
  out.segment_ms = source_segment_ms_;
  out.latency_ms = source_latency_ms_;
  return std::move(prediction.masks);
}

// The labels due at frame id (back, and of a frame at least L frames before it) given to the
// predictor; the run's first labels are due at once (no label delay). A threaded run never waits
// (its first labels, coming after their frame was masked, give that frame's late mask); a
// single-thread run waits for labels due and not back.
void SemanticFrontEnd::AddDueLabels(std::int64_t id, DynamicMaskResult& out) {
  std::vector<SegmentedFrame> due;
  {
    std::unique_lock<std::mutex> lock(schedule_mutex_);
    const bool first_labels = predictor_->source_frame() < 0;
    const int delay = first_labels ? 0 : schedule_->label_delay();
    const std::optional<std::int64_t> in_flight = schedule_->in_flight();
    const bool in_flight_due = in_flight && *in_flight + delay <= id;
    const bool wait = in_flight_due && wait_for_due_labels_;
    Stopwatch wait_watch;
    RetireBackLabels(lock, wait);
    if (wait) out.wait_ms = wait_watch.ElapsedMs();
    while (!ready_.empty() && ready_.front().id + delay <= id) {
      due.push_back(std::move(ready_.front()));
      ready_.pop_front();
    }
  }
  for (const SegmentedFrame& done : due) {
    if (!predictor_->AddLabels(done.id, done.result.labels)) continue;
    source_segment_ms_ = done.result.segment_ms;
    source_latency_ms_ = done.latency_ms;
    AddLateMask(done, out);
  }
}

// The first labels of a threaded run, of a frame already masked without them: that frame's
// refined mask, on its own depth, handed out once (see the header).
void SemanticFrontEnd::AddLateMask(const SegmentedFrame& labelled, DynamicMaskResult& out) {
  const auto unlabelled = std::find_if(unlabelled_depths_.begin(), unlabelled_depths_.end(),
                                       [&](const auto& frame) { return frame.first == labelled.id; });
  if (unlabelled != unlabelled_depths_.end()) {
    DynamicMaskResult late;
    Refine(groups_.Masks(labelled.result.labels), unlabelled->second, late);
    out.late_frame = labelled.id;
    out.late_mask = std::move(late.mask);
  }
  unlabelled_depths_.clear();  // the frames after these labels get them carried
}

// Region growing, core and dilation on the image reduced by refine_.scale; the mask enlarged to
// the image size at the end.
void SemanticFrontEnd::Refine(const SemanticMasks& masks, const cv::Mat& depth_m, DynamicMaskResult& out) const {
  const int scale = refine_.scale;
  Stopwatch grow;
  ThreadCpuStopwatch grow_cpu;
  const cv::Mat class_mask = ReduceMaskAny(masks.dynamic, scale);
  cv::Mat refined = RefineDynamicMask(class_mask, SubsampleDepth(depth_m, scale), ScaledGrowing(growing_, scale));
  out.grow_ms = grow.ElapsedMs();
  out.grow_cpu_ms = grow_cpu.ElapsedMs();
  const cv::Mat small = Dilate(KeepMaskCore(refined, class_mask, scale), Scaled(refine_.dilation_px, scale));
  out.mask = EnlargeNearest(small, scale, masks.dynamic.size());
  out.potentially_dynamic = masks.potentially_dynamic;
  out.static_objects = masks.static_objects;
  out.dynamic_fraction = static_cast<double>(cv::countNonZero(small)) / std::max<int>(1, small.total());
}

}  // namespace esdslam
