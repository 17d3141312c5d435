#pragma once
// Mask prediction between network frames (issue 12). The network labels only some frames; every
// frame in between gets the labels of the newest labelled frame s carried to it along the dense
// optical flow of the frames in between, so that the masks follow the people's own motion (and
// the camera's: the flow holds both).
//
// Per frame k (AddFrame): grey image and depth are resized to flow_width_px wide (area / nearest),
// and the backward flow F_k from frame k to the previous added frame is computed there (OpenCV
// DIS optical flow): pixel x of frame k was at P_k(x) = x + F_k(x) in frame k-1. A pixel is
// *disoccluded* when its depth and the depth at P_k(x) in frame k-1 differ by more than
//     occlusion_abs_tolerance_m + occlusion_depth_sq_tolerance * z^2
// (background appearing behind a walking person: the flow there is smeared from the person, the
// depth is that of the background; the constant part covers a person's own depth change per frame,
// the z^2 part the sensor noise). Pixels without depth are not tested. The last history_frames
// frames are kept.
// Carrying the labels of frame s: for every pixel x of frame k at flow resolution, M_k(x) holds
// where it was in frame s (full-resolution pixels) and v_k(x) whether its path stayed consistent:
//     M_s(x) = x,   M_k(x) = M_{k-1}(P_k(x)),   v_s = 1,   v_k(x) = v_{k-1}(P_k(x)) * [not disoccluded]
// (bilinear lookups). The labels of s are looked up through M upsampled to the image size
// (nearest); where v < 0.5 the label is 0 (unlabelled: nothing in frame s showed that surface).
// A path that leaves the image continues from the nearest border pixel (a person cut by the image
// border who walks in stays labelled) but no longer counts as covered by the labels (c_k, carried
// like v, is 0 for paths that left the image or were disoccluded).
// Late labels: labels of frame s added after frames s+1..j are carried through the stored flows
// at once (j - s steps at flow resolution), then by one step per new frame.
// Determinism: the prediction for frame j depends only on the images and depths added and on which
// labels were added before it (ids, never clock times): a scheduler that adds labels by a fixed
// frame schedule gets the same masks on every run. DIS runs under OpenCV's parallel_for_ on
// independent stripes: its result does not depend on the thread count (tested).
//
// The predicted dynamic mask is dilated by a radius that grows with the label age:
// min(max_age_dilation_px, floor(age_dilation_px_per_frame * age)) full-resolution pixels. The
// prediction then goes through the same refinement as a fresh mask (region growing on the current
// depth, see region_growing.h).
//
// Trust (MaskPrediction::trust, in [0, 1]): the smaller of the age term, 1 - age / max_trusted_age,
// and the coverage term, 1 - uncovered / max_uncovered_fraction, where `uncovered` is the fraction
// of the current image that the labels do not cover (came into view or was disoccluded since s:
// a person there would be missed). needs_labels = trust < min_trust.
//
// Not thread-safe: one caller (the tracking thread). Memory per kept frame at 320x240 flow
// resolution: about 1.5 MB.

#include <cstdint>
#include <deque>
#include <optional>

#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include "dynamic/object_motion.h"
#include "semantic/class_groups.h"

namespace esdslam {

// How the dynamic mask is carried: pixel by pixel along the flow, or each object (connected
// component) as a whole by the motion fitted to its interior (dynamic/object_motion.h), or both
// (union).
enum class DynamicCarry { kPixels, kObjects, kObjectsAndPixels };

struct MaskPredictorOptions {
  int flow_width_px = 320;              // width the flow is computed at (height in proportion)
  // DIS optical flow (cv::DISOpticalFlow); sizes in pixels at flow resolution.
  int flow_finest_scale = 2;            // finest pyramid level searched (0 = flow resolution)
  int flow_patch_size = 8;
  int flow_patch_stride = 4;
  int flow_gradient_iterations = 16;
  int flow_variational_iterations = 5;  // variational refinement; 0 = off
  // Disocclusion test (see above); a non-positive abs tolerance disables it.
  double occlusion_abs_tolerance_m = 0.1;
  double occlusion_depth_sq_tolerance = 0.01;  // 1/m
  // Disoccluded pixels take the label of a neighbour on the same surface: depth step between
  // neighbouring flow pixels <= fill_abs_tolerance_m + fill_depth_sq_tolerance * z^2. <= 0: off.
  double fill_abs_tolerance_m = 0.05;
  double fill_depth_sq_tolerance = 0.02;  // 1/m
  DynamicCarry dynamic_carry = DynamicCarry::kObjects;
  ObjectMotionOptions objects;
  int cleanup_radius_px = 3;            // opening + closing of the carried dynamic mask (full resolution); 0 = off
  int history_frames = 30;              // frames kept: labels of an older frame can no longer be carried
  // Dilation of the carried dynamic mask, growing with the label age (full-resolution pixels).
  double age_dilation_px_per_frame = 0.0;
  int max_age_dilation_px = 10;
  int max_trusted_age = 20;             // frames: the age term of the trust is 0 here
  double max_uncovered_fraction = 0.5;  // the coverage term of the trust is 0 here
  double min_trust = 0.25;              // below this, needs_labels is set

  // Throws Error naming the first value out of its bounds.
  void Check() const;
};

struct MaskPrediction {
  std::int64_t frame_id = -1;   // the frame predicted (the newest added)
  std::int64_t source_id = -1;  // frame whose labels were carried; -1: no labels yet
  int label_age = -1;           // frame_id - source_id (0: fresh labels); -1: no labels yet
  cv::Mat labels;               // CV_8U class ids carried to frame_id; empty without labels
  SemanticMasks masks;          // of `labels`; `dynamic` dilated by the age radius; empty without labels
  double uncovered_fraction = 1;  // of the image: not covered by the carried labels (see above)
  double trust = 0;             // [0, 1]; 0 without labels
  bool needs_labels = true;     // trust < min_trust, or no labels yet
};

class MaskPredictor {
 public:
  // image_size: size of the images, depths and labels (e.g. 640x480). Throws Error on bad options.
  MaskPredictor(cv::Size image_size, const MaskPredictorOptions& options = {}, const ClassGroups& groups = ClassGroups());

  // Frame `id` (ids increase; the flow links consecutive added frames). image: CV_8UC1 grey or
  // CV_8UC3 BGR; depth_m: CV_32F metres (0 = invalid), or empty to skip the disocclusion test for
  // this frame. Throws Error on a wrong type or size or an id that does not increase.
  void AddFrame(std::int64_t id, const cv::Mat& image, const cv::Mat& depth_m);

  // Network labels (CV_8U class ids of image_size) of an added frame source_id <= the newest.
  // They replace the labels in use if they are newer. Returns false (and changes nothing) when
  // they are not newer than the labels in use or their frame has left the history (too late).
  // Throws Error on a wrong type or size, or labels of a frame not added yet.
  bool AddLabels(std::int64_t source_id, const cv::Mat& labels);

  // The prediction for the newest added frame.
  MaskPrediction Predict() const;

  std::int64_t newest_frame() const { return frames_.empty() ? -1 : frames_.back().id; }
  std::int64_t source_frame() const { return source_ ? source_->id : -1; }
  const MaskPredictorOptions& options() const { return options_; }

 private:
  struct FlowFrame {
    std::int64_t id;
    cv::Mat grey;              // CV_8U, flow resolution
    cv::Mat depth_m;           // CV_32F, flow resolution (nearest); empty: no depth
    cv::Mat position_in_prev;  // CV_32FC2 P_k (flow-resolution pixels of frame k-1); empty for the first frame
    cv::Mat step_factor;       // CV_32FC2 per pixel: (not disoccluded, P_k inside frame k-1) as 0/1
    cv::Mat nearer;            // CV_8U 255: disoccluded because a surface moved in front
  };
  struct Source {
    std::int64_t id;
    cv::Mat labels;      // CV_8U, image size
    cv::Mat map;         // CV_32FC2 M_k: position in frame s, full-resolution pixels
    cv::Mat state;       // CV_32FC2 (v_k, c_k)
    cv::Mat filled;      // CV_8U labels of disoccluded pixels from their surface's neighbours (255: none)
    SourceObjects objects;  // of the dynamic mask of `labels`
  };

  FlowFrame MakeFrame(std::int64_t id, const cv::Mat& image, const cv::Mat& depth_m) const;
  void CarryOneStep(Source& source, const FlowFrame& frame) const;
  cv::Mat CarryDynamic(const cv::Mat& per_pixel, const cv::Mat& full_map, const cv::Mat& lost) const;

  cv::Size image_size_;
  cv::Size flow_size_;
  MaskPredictorOptions options_;
  ClassGroups groups_;
  cv::Ptr<cv::DISOpticalFlow> flow_;
  cv::Mat identity_;               // CV_32FC2: x, flow resolution
  cv::Mat identity_full_units_;    // CV_32FC2: x in full-resolution pixels (pixel centres)
  std::deque<FlowFrame> frames_;   // oldest first, at most history_frames
  std::optional<Source> source_;
};

}  // namespace esdslam
