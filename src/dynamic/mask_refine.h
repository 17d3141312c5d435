#pragma once
// How a class mask becomes the dynamic mask: the options (Dynamic.maskDilation,
// Dynamic.refineScale; used by SemanticFrontEnd), and masks and depth at a reduced resolution
// and back (issue 12: the mask stage's region growing, core and dilation run on a quarter of the
// pixels). `factor` >= 1 is the reduction along each
// axis; a reduced image has ceil(cols / factor) x ceil(rows / factor) pixels, and reduced pixel
// (x, y) stands for the block of full-resolution pixels [x f, x f + f) x [y f, y f + f), cut at
// the image border.

#include <opencv2/core.hpp>

namespace esdslam {

// How a class mask becomes the dynamic mask (Dynamic.* keys).
struct MaskRefineOptions {
  int dilation_px = 0;  // Dynamic.maskDilation: the refined mask grown by this (full-resolution px)
  // Dynamic.refineScale: region growing, the class mask's core and the dilation run on the image
  // reduced by this factor along each axis (1: full resolution; 2: a quarter of the pixels, the
  // mask then has 2x2-pixel steps at its edge); pixel distances are scaled by it.
  int scale = 2;
  void Check() const;  // throws SettingError naming the key
};

// CV_8U mask reduced: a reduced pixel is 255 where any pixel of its block is nonzero (a
// reduced mask never loses a masked pixel). factor 1 returns the mask unchanged (shared).
cv::Mat ReduceMaskAny(const cv::Mat& mask, int factor);

// CV_32F depth (metres, 0 = invalid) reduced by taking each block's first pixel (top left): no
// value is invented across a depth edge. factor 1 returns the depth unchanged (shared).
cv::Mat SubsampleDepth(const cv::Mat& depth_m, int factor);

// CV_8U image enlarged to `size` by copying each pixel into its block (nearest neighbour; the
// inverse of the block layout above). small must cover size: ceil(size / factor) pixels or more.
// factor 1 with small of `size` returns it unchanged (shared).
cv::Mat EnlargeNearest(const cv::Mat& small, int factor, cv::Size size);

}  // namespace esdslam
