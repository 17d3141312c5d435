#pragma once
// The whole per-frame pipeline, given one frame's images at a time: the dynamic stages switched
// by PipelineOptions::mode (system/run_config.h), the SLAM system, the dense mapper. It knows
// nothing about where frames come from (a folder, a camera, a library caller): the run loop
// (system/run_loop.h) feeds it from a FrameSource.
//
// Per frame, Track():
//   1. the frame's dynamic mask from the semantic stage (every frame: waits for its labels;
//      predicted: the newest labels carried to the frame along the optical flow,
//      dynamic/semantic_front_end.h), empty without segmentation;
//   2. tracking with it (SlamSystem::TrackRgbd: the extractor spends its budget on the static
//      area; the geometry check runs inside tracking, the semantic mask and labelled static
//      classes exempt from it);
//   3. a new keyframe handed to the dense mapper with its depth masked by the semantic and the
//      geometry masks;
//   4. the FrameReport (system/frame_report.h).
// Look-ahead: SubmitAhead(frame) hands a frame to the network's label schedule before the frames
// before it are tracked (the run loop submits look_ahead() frames ahead: frame i+1, or i+A with
// Semantic.lookAhead A on a recorded sequence, then tracks frame i), so the network labels it
// while earlier frames are tracked. Track(i) queues the masks of frames i and i+1: in a threaded
// run the mask of i+1 is made on the mask thread (dynamic/mask_ahead.h) while frame i is
// extracted and tracked. A frame not submitted ahead is submitted by Track itself (a live caller
// without look-ahead simply calls Track). Frames are numbered in
// submission order (FrameReport::index); they must be tracked in that order.
// Late labels: a threaded run does not wait for the network's first labels. A keyframe made
// before any labels came (the map's first one) is held back from the dense mapper; when the
// labels come, the map points it made on the people are removed (SlamSystem::RemovePointsUnder)
// and it goes to the dense mapper with its late mask; keyframes of other unlabelled frames go
// with their own masks then (or at StopSlam if no labels ever came).
// Which frames the network labels is decided by frame id in the semantic stage (LabelSchedule);
// a caller's own dynamic mask (RgbdFrame::dynamic_mask) joins the mask in step 1, and with
// Semantic.segmenter: provided the caller's labels (RgbdFrame::labels) take the network's place.
//
// Threading: all calls from one thread (the tracking thread). The mask, segmentation,
// local-mapping, loop-closing and dense threads are owned here and stopped by Finish() or the destructor.

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "dense/dense_mapper.h"
#include "dense/slam_keyframe_poses.h"
#include "dynamic/mask_ahead.h"
#include "dynamic/semantic_front_end.h"
#include "io/frame_source.h"
#include "semantic/provided_labels.h"
#include "system/frame_report.h"
#include "system/run_config.h"
#include "system/slam_system.h"

namespace esdslam {

class Pipeline {
 public:
  // Takes the configuration as it is (checked, never changed). Throws Error.
  explicit Pipeline(const RunConfig& config);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Starts segmenting `frame` (no-op without segmentation) and gives it the next frame id.
  // The images are shared, not copied: never write into them afterwards.
  void SubmitAhead(const RgbdFrame& frame);
  // Tracks the oldest frame submitted ahead (it must be `frame`: same timestamp), or `frame` if
  // none waits. Throws Error on bad images, a failed stage, or after Finish.
  FrameReport Track(const RgbdFrame& frame);
  // Stops segmentation, local mapping and loop closing (SlamSystem::Shutdown): the trajectory
  // is final afterwards; the dense thread goes on. Idempotent; Track throws afterwards. Throws
  // Error when a thread failed.
  void StopSlam();
  // StopSlam, then stops the dense thread; with dense, writes out_dir/dense.ply, octomap.bt, dense_top.png,
  // dense_view.png and dense_keyframes.txt (every dense keyframe, culled ones included) at the
  // keyframes' final poses. Idempotent. Throws Error when a thread failed (the dense outputs are written first).
  void Finish(const std::string& out_dir);

  const RunConfig& config() const { return config_; }
  // Frames a run loop submits ahead of the frame it tracks (PipelineOptions::look_ahead_frames).
  int look_ahead() const { return config_.pipeline.look_ahead_frames; }
  SlamSystem& system() { return *system_; }
  const SlamSystem& system() const { return *system_; }
  // Null without dense. Thread-safe on-demand builds at the current keyframe poses.
  const DenseMapper* dense() const { return dense_.get(); }
  const SemanticFrontEnd* semantic() const { return masks_ ? &masks_->front_end() : nullptr; }

 private:
  void AddDenseKeyframe(const RgbdFrame& frame, const cv::Mat& mask, KeyFrame* keyframe);
  void QueueMasks(std::int64_t last_id);
  void ApplyLateMask(std::int64_t frame_index, const cv::Mat& late_mask);
  void ReleaseUnlabelledKeyframes();

  const RunConfig config_;
  std::shared_ptr<ProvidedLabels> provided_labels_;  // Semantic.segmenter: provided; else null
  std::unique_ptr<MaskAhead> masks_;  // the semantic stage (dynamic/mask_ahead.h); null without segmentation
  std::unique_ptr<SlamSystem> system_;
  std::unique_ptr<SlamKeyframePoses> dense_poses_;  // before dense_: its worker reads them
  std::unique_ptr<DenseMapper> dense_;
  std::int64_t next_id_ = 0;         // id of the next frame submitted
  std::deque<RgbdFrame> ahead_;      // the frames submitted but not tracked, oldest first (images shared)
  std::int64_t next_masked_ = 0;     // id of the next frame whose mask is queued
  // Keyframes made before the run's first labels came (threaded runs), with their frame and the
  // mask they were tracked with (the keyframes are the map's: never freed before it); handed to
  // the dense mapper (if any) when the labels come.
  struct UnlabelledKeyframe {
    std::int64_t index;
    RgbdFrame frame;
    cv::Mat mask;
    KeyFrame* keyframe;
  };
  std::vector<UnlabelledKeyframe> unlabelled_keyframes_;
  bool labels_seen_ = false;   // a frame's mask had labels (source_id >= 0)
  bool slam_stopped_ = false;  // StopSlam ran: no more frames
  bool finished_ = false;
};

}  // namespace esdslam
