#pragma once
// Frame reports with known content for the viewer tests: a 640x480 colour frame, its left half
// on the semantic mask, and keypoints of every kind with depth.
#include <memory>

#include <opencv2/core.hpp>

#include "map/feature_set.h"
#include "system/frame_report.h"

namespace esdslam::testing {

// keypoints: kept ones at (100 + 10 k, 300), then `semantic` on the mask at (50 + 10 k, 100),
// then `geometry` at (400 + 10 k, 200); all with depth 2 m. The pose is the identity.
inline FrameReport MakeViewerFrame(long index, int kept = 6, int semantic = 3, int geometry = 2) {
  FrameReport report;
  report.index = index;
  report.timestamp = 1.0 + 0.033 * static_cast<double>(index);
  report.bgr = cv::Mat(480, 640, CV_8UC3, cv::Scalar(40, 80, 120));
  report.mask.mask = cv::Mat::zeros(480, 640, CV_8U);
  report.mask.mask(cv::Rect(0, 0, 320, 480)).setTo(255);
  report.track.state = TrackingState::kOk;
  report.track.has_pose = true;
  report.track.extract_ms = 12.5;
  report.track.track_ms = 7.25;
  auto rig = std::make_shared<RgbdRig>();
  CameraIntrinsics intrinsics;
  intrinsics.fx = intrinsics.fy = 500;
  intrinsics.cx = 320;
  intrinsics.cy = 240;
  rig->camera = PinholeCamera(intrinsics);
  auto features = std::make_shared<FeatureSet>();
  features->rig = rig;
  auto add = [&](float u, float v, std::uint8_t flag) {
    features->keypoints.emplace_back(cv::Point2f(u, v), 8.f);
    features->undistorted.emplace_back(u, v);
    features->depth.push_back(2.0f);
    features->right_u.push_back(u - 20.f);
    features->is_dynamic.push_back(flag);
  };
  for (int k = 0; k < kept; ++k) add(100.f + 10.f * k, 300.f, 0);
  for (int k = 0; k < semantic; ++k) add(50.f + 10.f * k, 100.f, kDynamicByMask);
  for (int k = 0; k < geometry; ++k) add(400.f + 10.f * k, 200.f, kDynamicByGeometry);
  report.features = features;
  report.keypoints = CountKeypoints(*features);
  return report;
}

}  // namespace esdslam::testing
