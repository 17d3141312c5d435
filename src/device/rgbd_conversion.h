#pragma once
// Turning a depth camera's raw images into the pipeline's RgbdFrame images (io/frame_source.h),
// independent of any driver (the OpenNI2 source uses them; so can a user's own camera):
//   depth in millimetres (uint16, 0 = no reading)  -> CV_32F metres, 0 = invalid
//   RGB888 rows (red first)                        -> CV_8UC3 in OpenCV's BGR order
//   software depth registration: the depth camera's image re-projected into the colour camera
//   (for devices without hardware registration): every depth pixel back-projected with the
//   depth camera's pinhole model, moved by colour_from_depth, projected with the colour
//   camera's; the nearest surface wins where several land on one pixel.
// Rows may be padded: stride_bytes is the distance between row starts (>= width * pixel size).

#include <cstddef>
#include <cstdint>

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "common/geometry.h"

namespace esdslam {

// Throws Error on a null buffer, an empty size or a stride shorter than a row.
cv::Mat DepthMmToMetres(const std::uint16_t* depth_mm, int width, int height, std::size_t stride_bytes);
cv::Mat Rgb888ToBgr(const std::uint8_t* rgb, int width, int height, std::size_t stride_bytes);

// depth_m: CV_32F metres in the depth camera (size of depth_camera; distortion ignored: the
// drivers deliver undistorted depth). Returns CV_32F metres of colour_camera's size, 0 where no
// depth lands. Throws Error when depth_m is not CV_32F of depth_camera's size.
cv::Mat RegisterDepthToColour(const cv::Mat& depth_m, const CameraIntrinsics& depth_camera,
                              const CameraIntrinsics& colour_camera, const Rigid3& colour_from_depth);

}  // namespace esdslam
