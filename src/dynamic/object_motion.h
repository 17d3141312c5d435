#pragma once
// Whole-object motion for carried masks (see dynamic/mask_predictor.h). Dense flow is smeared
// across an object's boundary (a patch there sees both the person and the background), so a mask
// carried pixel by pixel loses its leading edge a little at every step, and the loss adds up. Here
// every connected component ("object") of the source frame's dynamic mask moves as a whole: one
// similarity transform (scale, rotation in the image, translation) fitted to the carried positions
// of the pixels that map into the object's interior (the component eroded by interior_erosion_px,
// where the flow is that of the object), then the whole source component is drawn through it.
// The fit is made twice: the second time without the pixels whose residual exceeds
// max(min_inlier_px, 2 x the first RMS) (arms and legs swinging, a second person in the same
// component). An object whose interior no longer maps to at least min_fit_pixels flow pixels (it
// left the view, was occluded) or whose inliers are fewer than min_inlier_fraction is not fitted;
// the caller keeps its pixel-by-pixel carried mask.

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace esdslam {

struct ObjectMotionOptions {
  int interior_erosion_px = 6;        // full-resolution pixels
  int min_component_px = 100;         // smaller components are not objects (full-resolution pixels)
  int min_fit_pixels = 20;            // flow-resolution pixels mapping into the interior
  double min_inlier_px = 2.0;         // full-resolution pixels, see above
  double min_inlier_fraction = 0.5;

  // Throws Error naming the first value out of its bounds.
  void Check() const;
};

struct SourceObjects {
  cv::Mat ids;                // CV_16U at image size: component id (1..count), 0 = not dynamic
  cv::Mat interior_ids;       // CV_16U: the same ids on the eroded components only
  std::vector<cv::Rect> boxes;  // bounding box of component id i at boxes[i - 1]
  int count() const { return static_cast<int>(boxes.size()); }
};

// dynamic_mask: CV_8U, nonzero = dynamic. At most 65535 objects (more are merged into the last).
SourceObjects FindSourceObjects(const cv::Mat& dynamic_mask, const ObjectMotionOptions& options);

struct ObjectMotion {
  bool fitted = false;
  cv::Matx23d source_from_frame;  // current pixel -> source pixel (full resolution)
  double rms_px = 0;              // of the inliers
  int inliers = 0;
};

// frame_pixels: CV_32FC2 full-resolution position of every flow-resolution pixel of the current
// frame; source_pixels: CV_32FC2, where each was in the source frame (full resolution);
// consistent: CV_32F (>= 0.5: the path is valid). All at flow resolution.
std::vector<ObjectMotion> FitObjectMotions(const SourceObjects& objects, const cv::Mat& frame_pixels,
                                           const cv::Mat& source_pixels, const cv::Mat& consistent,
                                           const ObjectMotionOptions& options);

// The fitted objects drawn at their current place: CV_8U 255 at image_size.
cv::Mat DrawObjects(const SourceObjects& objects, const std::vector<ObjectMotion>& motions, cv::Size image_size);

}  // namespace esdslam
