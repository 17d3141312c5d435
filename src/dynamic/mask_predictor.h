#pragma once
// Mask prediction between network frames (issue 12). The network labels only some frames; every
// frame in between gets the labels of the newest labelled frame s carried to it along the dense
// optical flow of the frames in between, so that the masks follow the people's own motion, not
// only the camera's (the flow holds both).
//
// Per frame k (AddFrame): grey image and depth are resized to flow_width_px wide (area /
// nearest) and the backward flow from frame k to the previous added frame is computed there
// (OpenCV DIS optical flow, PRESET_FAST with the sizes below). The last history_frames frames
// are kept. The labels of s are carried one frame at a time along these flows, with the
// disocclusion test and fill of dynamic/label_carry.h (the background uncovered behind a walking
// person does not inherit the person's label; the person's leading edge does), then looked up at
// the image size. Late labels (AddLabels of frame s after frames s+1..j were added) are carried
// through the stored flows at once, then one step per new frame.
//
// The carried labels are computed at flow resolution and upsampled (nearest) to the image size;
// the dynamic mask is upsampled from the source mask interpolated at the carried positions
// (bilinear, threshold 0.5), so its boundary is finer than a flow pixel. It is cleaned (opening
// then closing with a (2 cleanup_radius_px + 1) square: removes specks and thin lines picked up
// along boundaries, which region growing would otherwise grow into the background) and dilated
// by a radius that grows with the label age, min(max_age_dilation_px,
// floor(age_dilation_px_per_frame * age)).
// It then goes through the same refinement as a fresh mask (region growing on the current depth,
// dynamic/region_growing.h).
//
// Trust (MaskPrediction::trust, in [0, 1]): the smaller of the age term, 1 - age / max_trusted_age,
// and the coverage term, 1 - uncovered / max_uncovered_fraction, where `uncovered` is the fraction
// of the current image the labels do not cover (it came into view or was disoccluded since s: a
// person there would be missed). needs_labels = trust < min_trust. A scheduler labels every K-th
// frame anyway and asks for labels early when needs_labels is set.
//
// Determinism: the prediction for frame j depends only on the images and depths added and on which
// labels were added before it (frame ids, never clock times), so a scheduler that adds labels by a
// fixed frame schedule gets the same masks on every run. DIS runs under OpenCV's parallel_for_ on
// independent stripes; its result does not depend on the thread count (tested).
//
// Not thread-safe: one owner thread calls everything. Label value 255 is reserved (kNoLabel).
// Memory: about 0.3 MB per kept frame at the default 160-pixel-wide flow (9 MB for the default 30), plus
// the labels in use. Predict() computes the masks anew on every call (about 1 ms): call it once
// per frame.

#include <cstdint>
#include <deque>
#include <optional>

#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include "dynamic/label_carry.h"
#include "semantic/class_groups.h"

namespace esdslam {

struct MaskPredictorOptions {
  int flow_width_px = 160;              // width the flow is computed at (height in proportion; 160: RESULTS "flow width")
  // DIS optical flow (cv::DISOpticalFlow); sizes in pixels at flow resolution.
  int flow_finest_scale = 2;            // finest pyramid level searched (0 = flow resolution)
  int flow_patch_size = 8;
  int flow_patch_stride = 4;
  int flow_gradient_iterations = 16;
  int flow_variational_iterations = 0;  // variational refinement iterations (0 = none: as accurate here, 20 % cheaper)
  DisocclusionOptions disocclusion;
  int cleanup_radius_px = 3;            // full-resolution pixels; 0 = no clean-up
  double age_dilation_px_per_frame = 0.0;
  int max_age_dilation_px = 10;
  int history_frames = 30;              // frames kept: labels of an older frame can no longer be carried
  // frames: the age term of the trust is 0 here. With min_trust 0.25, labels are asked for from
  // age 8: up to age 7 the carried masks stay within 0.05 IoU of fresh ones on the synthetic
  // dynamic preset (docs/RESULTS.md, "Mask prediction").
  int max_trusted_age = 10;
  double max_uncovered_fraction = 0.5;  // the coverage term of the trust is 0 here
  double min_trust = 0.25;              // below this, needs_labels is set

  // Throws Error naming the first value out of its bounds.
  void Check() const;
};

struct MaskPrediction {
  std::int64_t frame_id = -1;     // the frame predicted (the newest added)
  std::int64_t source_id = -1;    // frame whose labels were carried; -1: no labels yet
  int label_age = -1;             // frame_id - source_id (0: fresh labels); -1: no labels yet
  cv::Mat labels;                 // CV_8U class ids carried to frame_id; empty without labels
  SemanticMasks masks;            // of `labels` (CV_8U 255); `dynamic` cleaned and dilated as above
  double uncovered_fraction = 1;  // of the image, not covered by the carried labels (0 when fresh)
  double trust = 0;               // [0, 1]; 0 without labels
  bool needs_labels = true;       // trust < min_trust, or no labels yet
};

class MaskPredictor {
 public:
  // image_size: size of the images, depths and labels (e.g. 640x480). Throws Error on bad options.
  MaskPredictor(cv::Size image_size, const MaskPredictorOptions& options = {}, const ClassGroups& groups = ClassGroups());

  // Frame `id` (ids increase; the flow links consecutive added frames). image: CV_8UC1 grey or
  // CV_8UC3 BGR; depth_m: CV_32F metres (0 = invalid), or empty (no disocclusion test for this
  // frame). Throws Error on a wrong type or size or an id that does not increase.
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
    cv::Mat grey;     // CV_8U, flow resolution
    cv::Mat depth_m;  // CV_32F, flow resolution (nearest); empty: no depth
    RememberedDepth remembered;  // for the next frame's disocclusion test (newest frame only)
    FlowStep step;    // from the previous added frame; empty for the first
  };
  struct Source {
    std::int64_t id;
    cv::Mat labels;          // CV_8U, image size
    cv::Mat dynamic;         // CV_8U 0 / 255: its dynamic mask
    CarriedLabels carried;   // to the newest frame
  };

  cv::Size image_size_;
  cv::Size flow_size_;
  MaskPredictorOptions options_;
  ClassGroups groups_;
  std::array<std::uint8_t, 256> dynamic_of_label_{};  // 255 for the dynamic classes
  cv::Ptr<cv::DISOpticalFlow> flow_;
  std::deque<FlowFrame> frames_;  // oldest first, at most history_frames
  std::optional<Source> source_;
};

}  // namespace esdslam
