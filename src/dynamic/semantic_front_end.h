#pragma once
// The semantic stage of a run: what the network labels, and each frame's dynamic mask.
//
// Two hand-offs (SemanticSettings::segment_every, ::mode):
//   every frame (segment_every 1): every frame's image goes to the SegmentationWorker as soon as
//     it is loaded (the run loop submits frame i+1 before tracking frame i, so the network works
//     while frame i is extracted and tracked), and MaskFor(id) waits for frame id's labels.
//   predicted (segment_every K > 1, or --realtime): the network labels only some frames, on its
//     own thread, by the LabelSchedule (dynamic/label_schedule.h: every K-th frame, earlier when
//     the predicted mask is no longer trusted, one frame in flight). Every frame gets the newest
//     labels carried to it along dense optical flow (MaskPredictor, dynamic/mask_predictor.h:
//     the people's own motion and the camera's). Labels are used from L frames after their
//     frame on (Semantic.labelDelay, default 0: the run loop hands each frame to the schedule
//     Semantic.lookAhead frames before its mask is made, which hides the network's latency); a
//     threaded run takes them when they are back (never waits), a single-thread run
//     (wait_for_due_labels) waits for them at exactly that frame, so its masks repeat exactly.
//     A threaded run does not wait for its first labels either: the frames masked before they
//     are back get no mask, and when they come, the refined mask of their own frame is handed
//     out once (DynamicMaskResult::late_mask) so that what was built from that frame unmasked
//     (the map's first keyframe, its dense integration) is corrected (system/pipeline.h). A
//     single-thread run waits for them at their frame, as for all labels.
// Either way the mask goes through the same refinement: dynamic mask = RefineDynamicMask(dynamic-
// class mask, current depth) plus the class mask's interior (eroded by 3 px), dilated by
// MaskRefineOptions::dilation_px (Dynamic.maskDilation), all of it on the image reduced by
// MaskRefineOptions::scale (Dynamic.refineScale) and enlarged back at the end. A predicted mask steers the extractor's keypoint
// budget exactly as a fresh one does (it is the same DynamicMaskResult).
//
// Threading: Submit may be called from one thread (the tracking thread: the run loop hands frames
// to the network several frames ahead of their masks, Semantic.lookAhead) and MaskFor from
// another (the mask thread of dynamic/mask_ahead.h), or both from the tracking thread with
// --single-thread; Stats() is thread-safe; the SegmentationWorker owns the network's thread.

#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <utility>

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "common/geometry.h"
#include "dynamic/label_schedule.h"
#include "dynamic/mask_predictor.h"
#include "dynamic/mask_refine.h"
#include "dynamic/region_growing.h"
#include "semantic/class_groups.h"
#include "semantic/segmentation_worker.h"
#include "semantic/semantic_settings.h"

namespace esdslam {

struct DynamicMaskResult {
  cv::Mat mask;                    // CV_8U, 255 = dynamic (refined); empty if no labels yet
  cv::Mat potentially_dynamic;     // CV_8U, 255 = potentially dynamic class; empty if none
  cv::Mat static_objects;          // CV_8U, 255 = labelled static class (not background); empty if none
  std::int64_t source_id = -1;     // frame whose labels were used (-1: none)
  bool warped = false;             // labels of an older frame carried to this one
  double trust = 1;                // predicted masks: MaskPrediction::trust; 1 for fresh labels
  double wait_ms = 0;              // time MaskFor blocked on the network
  double segment_ms = 0;           // network time of the source frame
  double latency_ms = 0;           // submit -> result of the source frame
  double predict_ms = 0;           // mask prediction (flow + carrying), wall time
  double predict_cpu_ms = 0;       // the same, CPU time of the calling thread
  double refine_ms = 0;            // class masks + prediction + region growing + dilation
  double grow_ms = 0;              // region growing alone (RefineDynamicMask)
  double grow_cpu_ms = 0;          // the same, CPU time of the calling thread
  double dynamic_fraction = 0;     // of the image area
  // Once per threaded run, when its first labels come back: the refined dynamic mask of their
  // own frame late_frame (earlier than this one, masked without labels). -1 / empty otherwise.
  std::int64_t late_frame = -1;
  cv::Mat late_mask;
};

class SemanticFrontEnd {
 public:
  // wait_for_due_labels: predicted mode waits for due labels (single-thread runs: deterministic).
  SemanticFrontEnd(const SemanticSettings& settings, const RegionGrowingOptions& growing,
                   const MaskRefineOptions& refine = {}, bool wait_for_due_labels = false);
  // The same with a given segmenter (tests).
  SemanticFrontEnd(std::unique_ptr<Segmenter> segmenter, const SemanticSettings& settings,
                   const RegionGrowingOptions& growing, const MaskRefineOptions& refine = {},
                   bool wait_for_due_labels = false);
  ~SemanticFrontEnd();

  // Frame `id` is loaded (ids increase): every frame mode segments it; predicted mode when the
  // schedule says so. bgr is shared, not copied: do not write to it afterwards.
  void Submit(std::int64_t id, double timestamp, const cv::Mat& bgr);
  // The mask of frame id (submitted; masks asked in id order). bgr: CV_8UC3, depth_m: CV_32F
  // metres of frame id. Throws Error if the segmenter failed.
  DynamicMaskResult MaskFor(std::int64_t id, const cv::Mat& bgr, const cv::Mat& depth_m);

  void Stop();
  SegmentationWorkerStats Stats() const { return worker_->Stats(); }
  bool predicted() const { return schedule_.has_value(); }

 private:
  void AddDueLabels(std::int64_t id, DynamicMaskResult& out);
  void AddLateMask(const SegmentedFrame& labelled, DynamicMaskResult& out);
  void RetireBackLabels(std::unique_lock<std::mutex>& lock, bool wait);
  SemanticMasks PredictedMasks(std::int64_t id, const cv::Mat& bgr, const cv::Mat& depth_m, DynamicMaskResult& out);
  void Refine(const SemanticMasks& masks, const cv::Mat& depth_m, DynamicMaskResult& out) const;

  ClassGroups groups_;
  RegionGrowingOptions growing_;
  MaskRefineOptions refine_;
  bool wait_for_due_labels_;
  // schedule_mutex_ guards schedule_, needs_labels_ and ready_ (Submit and MaskFor may come
  // from two threads); a leaf lock, never held while waiting for the network.
  std::mutex schedule_mutex_;
  std::optional<LabelSchedule> schedule_;        // predicted mode only
  bool needs_labels_ = false;                    // the newest prediction asks for labels (frame 0 is scheduled)
  std::deque<SegmentedFrame> ready_;             // labels back, not yet due (oldest first)
  std::unique_ptr<MaskPredictor> predictor_;     // predicted mode, made at the first frame; MaskFor's thread
  // MaskFor's thread, threaded predicted mode: depth (metres, shared) of the frames masked before
  // the run's first labels came back, oldest first, at most kMaxUnlabelledFrames; cleared then.
  static constexpr std::size_t kMaxUnlabelledFrames = 64;
  std::deque<std::pair<std::int64_t, cv::Mat>> unlabelled_depths_;
  double source_segment_ms_ = 0, source_latency_ms_ = 0;  // of the labels in the predictor
  std::unique_ptr<SegmentationWorker> worker_;
};

// Forward-warps the nonzero pixels of `mask` (frame a, depth_a in metres) into frame b
// (b_from_a), pinhole model; pixels without depth stay in place. Result dilated by dilation_px.
// (The camera-motion-only carrying; mask prediction follows the flow instead. Kept as the
// baseline of benchmarks/mask_prediction_bench.)
cv::Mat WarpMask(const cv::Mat& mask, const cv::Mat& depth_a, const Rigid3& b_from_a, const PinholeCamera& camera,
                 int dilation_px);

}  // namespace esdslam
