#pragma once
// Test helpers shared by the core's tests (map, tracking, mapping, system): hand-built feature
// sets and keyframes with known geometry, and settings for the synthetic scenes.

#include <algorithm>
#include <memory>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "feature/feature_grid.h"
#include "map/feature_set.h"
#include "map/keyframe.h"
#include "map/map.h"
#include "map/map_point.h"

namespace esdslam::testing {

inline CameraIntrinsics TestIntrinsics() {
  CameraIntrinsics k;
  k.fx = k.fy = 525.0;
  k.cx = 319.5;
  k.cy = 239.5;
  return k;
}

inline std::shared_ptr<const RgbdRig> TestRig() {
  auto rig = std::make_shared<RgbdRig>();
  rig->camera = PinholeCamera(TestIntrinsics());
  rig->bf = 40.0;
  rig->th_depth_m = 40.0 * 40.0 / 525.0;
  ScalePyramid& p = rig->pyramid;
  p.num_levels = 8;
  p.scale_factor = 1.2;
  p.log_scale_factor = std::log(1.2);
  double s = 1;
  for (int i = 0; i < 8; ++i, s *= 1.2) {
    p.scale_factors.push_back(s);
    p.level_sigma2.push_back(s * s);
    p.inv_level_sigma2.push_back(1 / (s * s));
  }
  return rig;
}

// Random 32-byte descriptors, one per landmark (fixed seed).
inline cv::Mat RandomDescriptors(int n, unsigned seed = 7) {
  cv::Mat d(n, 32, CV_8U);
  std::mt19937 rng(seed);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 32; ++j) d.at<unsigned char>(i, j) = static_cast<unsigned char>(rng() & 0xff);
  return d;
}

// Features of a camera at `cam_from_world` seeing `landmarks` (world, m): one level-0 keypoint per
// landmark in front of the camera and inside the image, with exact depth when `with_depth`.
// `landmark_of_keypoint` receives the landmark index of each keypoint.
inline std::shared_ptr<FeatureSet> ProjectLandmarks(const std::vector<Vec3>& landmarks, const cv::Mat& descriptors,
                                                    const Rigid3& cam_from_world, bool with_depth,
                                                    std::vector<int>* landmark_of_keypoint) {
  auto f = std::make_shared<FeatureSet>();
  f->rig = TestRig();
  std::vector<int> levels;
  landmark_of_keypoint->clear();
  for (int i = 0; i < static_cast<int>(landmarks.size()); ++i) {
    const Vec3 p = cam_from_world * landmarks[i];
    if (p.z() <= 0.1) continue;
    const Vec2 px = f->rig->camera.Project(p);
    if (!f->rig->camera.InImage(px)) continue;
    cv::KeyPoint kp(static_cast<float>(px.x()), static_cast<float>(px.y()), 31.f, 0.f, 1.f, 0);
    f->keypoints.push_back(kp);
    f->undistorted.push_back(kp.pt);
    f->depth.push_back(with_depth ? static_cast<float>(p.z()) : 0.f);
    f->right_u.push_back(with_depth ? static_cast<float>(px.x() - f->rig->bf / p.z()) : -1.f);
    f->is_dynamic.push_back(0);
    levels.push_back(0);
    landmark_of_keypoint->push_back(i);
  }
  f->descriptors = cv::Mat(static_cast<int>(f->keypoints.size()), 32, CV_8U);
  for (int k = 0; k < f->size(); ++k) descriptors.row((*landmark_of_keypoint)[k]).copyTo(f->descriptors.row(k));
  const auto& cam = f->rig->camera;
  f->grid = std::make_unique<FeatureGrid>(f->undistorted, levels, cam.min_u(), cam.max_u(), cam.min_v(), cam.max_v());
  return f;
}

// Random landmarks 2-4 m in front of the world origin, inside the test camera's view.
inline std::vector<Vec3> RandomLandmarks(int n, unsigned seed = 3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(-1.0, 1.0), y(-0.8, 0.8), z(2.0, 4.0);
  std::vector<Vec3> out;
  for (int i = 0; i < n; ++i) out.emplace_back(x(rng), y(rng), z(rng));
  return out;
}

// Keyframes along x looking at the same landmarks; each keyframe keypoint k sees landmark ids[k].
struct LandmarkScene {
  Map map;
  std::vector<Vec3> landmarks;
  cv::Mat descriptors;
  std::vector<KeyFrame*> keyframes;
  std::vector<std::vector<int>> landmark_of_keypoint;

  LandmarkScene(int num_landmarks, int num_keyframes, double spacing_m, bool with_depth) {
    landmarks = RandomLandmarks(num_landmarks);
    descriptors = RandomDescriptors(num_landmarks);
    for (int k = 0; k < num_keyframes; ++k) AddKeyFrame(Rigid3(Quat::Identity(), Vec3(-spacing_m * k, 0, 0)), with_depth);
  }
  // A keyframe at `cam_from_world` seeing the landmarks (its pose in the map may differ later).
  KeyFrame* AddKeyFrame(const Rigid3& cam_from_world, bool with_depth) {
    std::vector<int> ids;
    auto features = ProjectLandmarks(landmarks, descriptors, cam_from_world, with_depth, &ids);
    const long k = static_cast<long>(keyframes.size());
    keyframes.push_back(map.CreateKeyFrame(k, static_cast<double>(k), features, cam_from_world));
    map.AddKeyFrame(keyframes.back());
    landmark_of_keypoint.push_back(ids);
    return keyframes.back();
  }
  int KeypointOf(int keyframe, int landmark) const {
    const auto& ids = landmark_of_keypoint[keyframe];
    const auto it = std::find(ids.begin(), ids.end(), landmark);
    return it == ids.end() ? -1 : static_cast<int>(it - ids.begin());
  }
  // A map point for `landmark` observed by `observers` (with depth as the features have it).
  MapPoint* AddPoint(int landmark, const std::vector<int>& observers, const Vec3& offset = Vec3::Zero()) {
    MapPoint* point = map.CreateMapPoint(landmarks[landmark] + offset, keyframes[observers[0]]);
    for (int k : observers) {
      const int index = KeypointOf(k, landmark);
      point->AddObservation(keyframes[k], index, keyframes[k]->features().has_depth(index));
      keyframes[k]->AddMapPoint(point, index);
    }
    point->ComputeDistinctiveDescriptor();
    point->UpdateNormalAndDepth();
    map.AddMapPoint(point);
    return point;
  }
};

}  // namespace esdslam::testing
