#pragma once
// What every frame and keyframe of one run shares: the camera, the RGB-D "stereo" constants and
// the ORB scale pyramid. Immutable after construction; shared by pointer.

#include <cmath>
#include <memory>
#include <vector>

#include "camera/pinhole_camera.h"

namespace esdslam {

struct ScalePyramid {
  int num_levels = 1;
  double scale_factor = 1.2;
  double log_scale_factor = std::log(1.2);
  std::vector<double> scale_factors;     // level 0 = 1
  std::vector<double> level_sigma2;      // scale^2
  std::vector<double> inv_level_sigma2;  // 1 / scale^2
};

struct RgbdRig {
  PinholeCamera camera;
  double bf = 40.0;         // px * m: focal length times virtual baseline (Camera.bf)
  double th_depth_m = 3.0;  // "close" keypoints have depth in (0, th_depth_m): ThDepth * bf / fx
  // Rolling shutter of the colour camera: seconds from the first to the last row (0 = global
  // shutter). Row r is exposed at (r / (height - 1) - 0.5) * readout_time_s after the frame's
  // timestamp, which stands for the middle row.
  double readout_time_s = 0.0;
  ScalePyramid pyramid;
};

}  // namespace esdslam
