#pragma once
// The semantic stage of a run: segmentation thread hand-off and dynamic masks.
//
// Every frame's image is submitted to the SegmentationWorker as soon as it is loaded; the caller
// submits frame i+1 before tracking frame i, so segmentation runs in parallel with ORB
// extraction and tracking (2 cores) while the mask of the frame being tracked is already known
// at extraction time (no keypoint budget is lost on people: the extractor spends it on the
// static area).
//   every frame (SegmentationMode::kEveryFrame): MaskFor(id) waits for frame id's labels.
//   real time  (kNewestWins): MaskFor(id) never waits; it takes the newest finished result and,
//               if that is an older frame, forward-warps its dynamic pixels into the current
//               frame with the older frame's depth and the relative pose predicted by the
//               constant-velocity model of the recorded poses, then dilates by warp_dilation_px.
// Dynamic mask = RefineDynamicMask(dynamic-class mask, current depth) plus the network mask's
// interior (eroded by 3 px), dilated by mask_dilation_px (Dynamic.maskDilation).

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "common/geometry.h"
#include "dynamic/region_growing.h"
#include "semantic/class_groups.h"
#include "semantic/segmentation_worker.h"
#include "semantic/semantic_settings.h"

namespace esdslam {

struct DynamicMaskResult {
  cv::Mat mask;                    // CV_8U, 255 = dynamic (refined); empty if no result yet
  cv::Mat potentially_dynamic;     // CV_8U, 255 = potentially dynamic class; empty if none
  cv::Mat static_objects;          // CV_8U, 255 = labelled static class (not background); empty if none
  std::int64_t source_id = -1;     // frame whose labels were used (-1: none)
  bool warped = false;             // labels of an older frame carried to this one
  double wait_ms = 0;              // time MaskFor blocked on the worker
  double segment_ms = 0;           // network time of the source frame
  double latency_ms = 0;           // submit -> result of the source frame
  double refine_ms = 0;            // class masks + warp + region growing + dilation
  double grow_ms = 0;              // region growing alone (RefineDynamicMask)
  double grow_cpu_ms = 0;          // the same, CPU time of the calling thread
  double dynamic_fraction = 0;     // of the image area
};

class SemanticFrontEnd {
 public:
  SemanticFrontEnd(const SemanticSettings& settings, const RegionGrowingOptions& growing,
                   const PinholeCamera& camera, int mask_dilation_px = 0, int warp_dilation_px = 5);
  ~SemanticFrontEnd();

  // Ids must increase. bgr is shared, not copied: do not write to it afterwards.
  void Submit(std::int64_t id, double timestamp, const cv::Mat& bgr);
  // depth_m: CV_32F metres of frame `id`. Throws Error if the segmenter failed.
  DynamicMaskResult MaskFor(std::int64_t id, const cv::Mat& depth_m);
  // After tracking frame id: its pose (if any) and depth, for the real-time warp.
  void RecordPose(std::int64_t id, const cv::Mat& depth_m, const std::optional<Rigid3>& world_from_cam);

  void Stop();
  SegmentationWorkerStats Stats() const { return worker_->Stats(); }
  SegmentationMode mode() const { return mode_; }

 private:
  struct PoseRecord {
    std::int64_t id;
    cv::Mat depth_m;
    Rigid3 world_from_cam;
  };
  cv::Mat CarryToFrame(const cv::Mat& mask, std::int64_t source_id, std::int64_t id) const;
  const PoseRecord* Record(std::int64_t id) const;

  SegmentationMode mode_;
  ClassGroups groups_;
  RegionGrowingOptions growing_;
  PinholeCamera camera_;
  int mask_dilation_px_;
  int warp_dilation_px_;
  std::unique_ptr<SegmentationWorker> worker_;
  std::deque<PoseRecord> poses_;  // recent tracked frames, oldest first
};

// Forward-warps the nonzero pixels of `mask` (frame a, depth_a in metres) into frame b
// (b_from_a), pinhole model; pixels without depth stay in place. Result dilated by dilation_px.
cv::Mat WarpMask(const cv::Mat& mask, const cv::Mat& depth_a, const Rigid3& b_from_a, const PinholeCamera& camera,
                 int dilation_px);

}  // namespace esdslam
