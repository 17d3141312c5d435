#pragma once
// Carrying the labels of a source frame s along chained dense optical flow, one frame at a time
// (the steps of dynamic/mask_predictor.h, which explains the method). Everything here works at
// flow resolution (a reduced image size); positions in the source frame are kept in
// full-resolution pixels.
//
// A step from frame k-1 to frame k is the backward flow of frame k: pixel x was at
// P_k(x) = x + F_k(x) in frame k-1. It is *disoccluded* when its depth z and the depth z' seen at
// P_k(x) in frame k-1 differ by more than occlusion_abs_tolerance_m + occlusion_depth_sq_tolerance
// * z^2: the constant part covers a walking person's own depth change per frame (about 0.05 m at
// 30 fps), the z^2 part the depth noise of structured-light sensors (sigma about 1.5e-3 z^2).
// z' is the *remembered* depth of frame k-1: where frame k-1 had no depth, the depth its pixel
// had along the flow in the frames before (at most depth_memory_frames back). Structured-light
// sensors lose depth in a band beside every foreground edge (the projector's shadow), and that
// band moves with a walking person: the background a person uncovers is often first seen without
// depth, and without the memory its path would keep the person's label. Without z or z' the
// test is skipped. Disoccluded pixels have no path into the source: what frame k-1 saw there was
// another surface.
//   - z < z' (a surface moved in front: the leading edge of a person, where the flow is smeared
//     towards the background's) takes the label of a labelled 4-neighbour on the same surface:
//     depth step <= fill_abs_tolerance_m + fill_depth_sq_tolerance * z^2, breadth first;
//   - z > z' (the background uncovered behind a person) stays unlabelled (label 0).
// Paths that leave the image continue from the nearest border pixel (a person cut by the image
// border who walks in stays labelled) but count as not covered by the labels, as disoccluded
// pixels do.

#include <array>
#include <cstdint>

#include <opencv2/core.hpp>

namespace esdslam {

struct DisocclusionOptions {
  double occlusion_abs_tolerance_m = 0.1;      // <= 0: no disocclusion test
  double occlusion_depth_sq_tolerance = 0.01;  // 1/m
  // Depth step between neighbouring flow pixels on one surface (a pixel of a 320-wide flow image
  // spans 2 image pixels: 0.05 m is a surface at 3 m slanted about 70 degrees).
  double fill_abs_tolerance_m = 0.05;          // <= 0: no fill
  double fill_depth_sq_tolerance = 0.02;       // 1/m
  int depth_memory_frames = 8;                 // see above (a path can run inside the moving band for several frames); 0 = no memory

  // Throws Error naming the first value out of its bounds.
  void Check() const;
};

// A frame's depth at flow resolution with the memory above.
struct RememberedDepth {
  cv::Mat depth_m;  // CV_32F metres, 0 = none
  cv::Mat age;      // CV_8U frames since the depth was seen (0: seen in this frame)
};

// Frame k relative to frame k-1, at flow resolution.
struct FlowStep {
  cv::Mat position_in_prev;  // CV_32FC2: P_k(x), flow-resolution pixels of frame k-1
  cv::Mat keep;              // CV_8UC2: (not disoccluded, not disoccluded and P_k inside frame k-1), 0 or 255
  cv::Mat nearer;            // CV_8U: 255 where disoccluded because a surface moved in front
};

// The first frame's remembered depth: its depth (CV_32F metres at flow resolution, may be empty).
RememberedDepth RememberDepth(const cv::Mat& depth_m);

// backward_flow: CV_32FC2 F_k; depth_m: frame k's CV_32F depth at flow resolution (may be empty:
// no test); prev: frame k-1's remembered depth (may be empty). Sets *remembered to frame k's.
FlowStep MakeFlowStep(const cv::Mat& backward_flow, const cv::Mat& depth_m, const RememberedDepth& prev,
                      const DisocclusionOptions& options, RememberedDepth* remembered);

inline constexpr std::uint8_t kNoLabel = 255;

// The labels of a source frame carried to the newest frame, per flow pixel.
struct CarriedLabels {
  cv::Mat source_position;  // CV_32FC2: where the pixel was in the source frame (full-resolution pixels)
  cv::Mat state;            // CV_8UC2: (path valid, covered by the labels), 0 or 255
  cv::Mat filled;           // CV_8U: label given by the fill (kNoLabel: none)
};

// The carry at the source frame itself: every pixel where it is, valid and covered.
CarriedLabels StartCarry(cv::Size flow_size, cv::Size image_size);

// One step to frame k (depth_m: frame k's depth at flow resolution, may be empty; source_labels:
// CV_8U at image size).
void CarryOneStep(const FlowStep& step, const cv::Mat& depth_m, const cv::Mat& source_labels,
                  const DisocclusionOptions& options, CarriedLabels& carried);

// The carried labels at flow resolution.
struct CarriedImages {
  cv::Mat labels;   // CV_8U class ids: the source label at the nearest source pixel where the path is
                    // valid, else the filled label, else 0
  cv::Mat dynamic;  // CV_8U 0..255: the source dynamic mask interpolated (bilinear) where the path is
                    // valid, else dynamic_of_label of `labels`; upsample bilinearly and threshold
                    // at 128 for a boundary finer than a flow pixel
  double uncovered_fraction = 0;  // of the pixels: not covered by the labels
};

// source_labels, source_dynamic (CV_8U 0 / 255): at image size; dynamic_of_label[c] = 255 if
// class c is dynamic, else 0.
CarriedImages CarriedLabelImages(const CarriedLabels& carried, const cv::Mat& source_labels,
                                 const cv::Mat& source_dynamic, const std::array<std::uint8_t, 256>& dynamic_of_label);

}  // namespace esdslam
