#pragma once
// Pictures of the dense map for looking at results without a 3-D viewer.
//  - Top view: orthographic, looking down the estimated gravity direction (the mean "down"
//    axis of the keyframe cameras, which are held roughly upright in hand-held and robot
//    sequences); points above the cameras' height + ceiling_margin are clipped so that the
//    ceiling does not hide the room; colour encodes height; the camera path is drawn in white.
//  - Perspective view: a virtual camera behind and above the mean keyframe pose looking at the
//    map centre, real colours, z-buffered splats.

#include <vector>

#include <opencv2/core.hpp>

#include "dense/point_cloud.h"

namespace esdslam {

struct MapRenderOptions {
  int width = 960;
  int height = 720;
  double ceiling_margin = 0.4;  // m above the highest camera centre
  int splat_px = 2;             // minimum splat radius in pixels
  double point_spacing = 0.01;  // m: spacing of the map's points (voxel size), sets the top-view splat size
};

cv::Mat RenderTopView(const PointCloud& cloud_world, const std::vector<Rigid3>& world_from_cams, const MapRenderOptions& options = {});
cv::Mat RenderPerspectiveView(const PointCloud& cloud_world, const std::vector<Rigid3>& world_from_cams,
                              const MapRenderOptions& options = {});

}  // namespace esdslam
