#pragma once
// Shared by the dense slow tests: the synthetic dynamic scene (90 frames, 3 movers), keyframes
// every 6 frames at the ground-truth poses, and geometry helpers with known answers.
#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include <gtest/gtest.h>

#include "dense/dense_mapper.h"
#include "synth/synthetic_scene.h"

namespace esdslam {

constexpr double kTestVoxel = 0.01;
constexpr int kKeyframeStep = 6;

// Distance from a world point to the surface of box `box` (inside or outside).
inline double DistanceToBoxSurface(const SyntheticScene& scene, int box, const Vec3& point_world, double time) {
  const Vec3 p = scene.WorldFromBox(box, time).inverse() * point_world;
  const Vec3& h = scene.boxes()[box].half_size;
  const Vec3 excess = (p.cwiseAbs() - h);
  if ((excess.array() <= 0).all()) return -excess.maxCoeff();  // inside: distance to the nearest face
  return excess.cwiseMax(0.0).norm();
}

inline double DistanceToStaticScene(const SyntheticScene& scene, const Vec3& point_world) {
  double best = 1e9;
  for (int b = 0; b < static_cast<int>(scene.boxes().size()); ++b)
    if (scene.boxes()[b].object_id == 0) best = std::min(best, DistanceToBoxSurface(scene, b, point_world, 0.0));
  return best;
}

inline double FractionWithin(const SyntheticScene& scene, const PointCloud& cloud, double tolerance) {
  const auto close = std::count_if(cloud.points.begin(), cloud.points.end(), [&](const Eigen::Vector3f& p) {
    return DistanceToStaticScene(scene, p.cast<double>()) <= tolerance;
  });
  return cloud.empty() ? 0.0 : static_cast<double>(close) / cloud.size();
}

// Keyframe `index` of the scene; mask = ground-truth mover mask (or none).
inline DenseKeyframe SceneKeyframe(const SyntheticScene& scene, int index, bool use_masks) {
  const SynthFrame frame = scene.RenderFrame(index);
  return DenseKeyframe{index, frame.timestamp, frame.world_from_cam, frame.bgr, frame.depth_m,
                       use_masks ? frame.mover_mask : cv::Mat()};
}

class SyntheticDenseTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    SynthOptions options = SynthPreset("dynamic");
    options.num_frames = 90;
    scene_ = new SyntheticScene(options);
    for (int i = 0; i < scene_->num_frames(); i += kKeyframeStep) {
      masked_.push_back(SceneKeyframe(*scene_, i, true));
      unmasked_.push_back(masked_.back());
      unmasked_.back().dynamic_mask = cv::Mat();
    }
  }
  static void TearDownTestSuite() {
    delete scene_;
    masked_.clear();
    unmasked_.clear();
  }
  static DenseOptions Options() {
    DenseOptions options;
    options.voxel_size = kTestVoxel;
    options.depth_noise_at_1m = 0;  // the scene renders exact depth
    return options;
  }
  static std::vector<double> KeyframeTimes() {
    std::vector<double> times;
    for (const DenseKeyframe& k : masked_) times.push_back(scene_->FrameTime(static_cast<int>(k.id)));
    return times;
  }

  static inline SyntheticScene* scene_ = nullptr;
  static inline std::vector<DenseKeyframe> masked_, unmasked_;
};

}  // namespace esdslam
