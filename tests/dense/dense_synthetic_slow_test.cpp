// End-to-end check of the static dense map on the synthetic dynamic scene: keyframes at the
// ground-truth poses, dynamic masks from the ground-truth mover masks. With masks no map point
// may lie in the volume the movers swept ("ghosts"); without masks (mode none) ghosts appear.
// Static surfaces must lie within 1 cm of the true geometry.
#include <algorithm>

#include <gtest/gtest.h>

#include "dense/dense_mapper.h"
#include "synth/synthetic_scene.h"

namespace esdslam {
namespace {

constexpr double kVoxel = 0.01;

// Distance from a world point to the surface of box `box` (inside or outside).
double DistanceToBoxSurface(const SyntheticScene& scene, int box, const Vec3& point_world, double time) {
  const Vec3 p = scene.WorldFromBox(box, time).inverse() * point_world;
  const Vec3& h = scene.boxes()[box].half_size;
  const Vec3 excess = (p.cwiseAbs() - h);
  if ((excess.array() <= 0).all()) return -excess.maxCoeff();  // inside: distance to the nearest face
  return excess.cwiseMax(0.0).norm();
}

bool InsideSweptMoverVolume(const SyntheticScene& scene, const Vec3& point_world, const std::vector<double>& times) {
  for (int mover = 1; mover <= scene.num_movers(); ++mover) {
    const int box = scene.MoverBox(mover);
    const Vec3 half = scene.boxes()[box].half_size + Vec3::Constant(kVoxel);
    for (const double t : times) {
      const Vec3 p = scene.WorldFromBox(box, t).inverse() * point_world;
      if ((p.cwiseAbs().array() <= half.array()).all()) return true;
    }
  }
  return false;
}

double DistanceToStaticScene(const SyntheticScene& scene, const Vec3& point_world) {
  double best = 1e9;
  for (int b = 0; b < static_cast<int>(scene.boxes().size()); ++b)
    if (scene.boxes()[b].object_id == 0) best = std::min(best, DistanceToBoxSurface(scene, b, point_world, 0.0));
  return best;
}

// A ghost: a map point in the space a mover occupied at some keyframe time that is not on a
// static surface (movers stand on the floor, so floor points touch their boxes).
bool IsGhost(const SyntheticScene& scene, const Vec3& point_world, const std::vector<double>& times) {
  return InsideSweptMoverVolume(scene, point_world, times) && DistanceToStaticScene(scene, point_world) > 2 * kVoxel;
}

struct MapResult {
  PointCloud cloud;
  std::vector<double> times;
};

MapResult BuildMap(const SyntheticScene& scene, bool use_masks) {
  DenseOptions options;
  options.voxel_size = kVoxel;
  DenseMapper mapper(scene.camera(), options, /*threaded=*/false);
  std::map<long, Rigid3> poses;
  MapResult result;
  for (int i = 0; i < scene.num_frames(); i += 6) {
    const SynthFrame frame = scene.RenderFrame(i);
    mapper.AddKeyframe(i, frame.bgr, frame.depth_m, use_masks ? frame.mover_mask : cv::Mat());
    poses[i] = frame.world_from_cam;
    result.times.push_back(scene.FrameTime(i));
  }
  result.cloud = mapper.map().BuildGlobalCloud(poses);
  return result;
}

class DenseSyntheticTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    SynthOptions options = SynthPreset("dynamic");
    options.num_frames = 90;
    scene_ = new SyntheticScene(options);
  }
  static void TearDownTestSuite() { delete scene_; }
  static SyntheticScene* scene_;
};
SyntheticScene* DenseSyntheticTest::scene_ = nullptr;

TEST_F(DenseSyntheticTest, NoGhostsWithMasksGhostsWithout) {
  const MapResult masked = BuildMap(*scene_, true);
  const MapResult unmasked = BuildMap(*scene_, false);
  ASSERT_GT(masked.cloud.size(), 10000u);
  const auto count_ghosts = [&](const MapResult& r) {
    return std::count_if(r.cloud.points.begin(), r.cloud.points.end(),
                         [&](const Eigen::Vector3f& p) { return IsGhost(*scene_, p.cast<double>(), r.times); });
  };
  EXPECT_EQ(count_ghosts(masked), 0);
  EXPECT_GT(count_ghosts(unmasked), 1000);  // mode none: people are painted into the map
}

TEST_F(DenseSyntheticTest, StaticSurfacesWithinOneCentimetre) {
  const MapResult masked = BuildMap(*scene_, true);
  std::size_t close = 0;
  for (const auto& p : masked.cloud.points)
    if (DistanceToStaticScene(*scene_, p.cast<double>()) <= 0.01) ++close;
  EXPECT_GE(static_cast<double>(close) / masked.cloud.size(), 0.95) << close << " of " << masked.cloud.size();
}

}  // namespace
}  // namespace esdslam
