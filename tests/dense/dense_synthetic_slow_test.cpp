// End-to-end checks of the static dense map on the synthetic dynamic scene: keyframes at the
// ground-truth poses, dynamic masks from the ground-truth mover masks. With masks no map point
// may lie in the volume the movers swept ("ghosts"); without masks (mode none) ghosts appear.
// Static surfaces must lie within 1 cm of the true geometry. The map must follow corrected poses
// and be buildable on demand while keyframes are still arriving.
#include <atomic>
#include <thread>

#include "synthetic_dense_fixture.h"

namespace esdslam {
namespace {

bool InsideSweptMoverVolume(const SyntheticScene& scene, const Vec3& point_world, const std::vector<double>& times) {
  for (int mover = 1; mover <= scene.num_movers(); ++mover) {
    const int box = scene.MoverBox(mover);
    const Vec3 half = scene.boxes()[box].half_size + Vec3::Constant(kTestVoxel);
    for (const double t : times) {
      const Vec3 p = scene.WorldFromBox(box, t).inverse() * point_world;
      if ((p.cwiseAbs().array() <= half.array()).all()) return true;
    }
  }
  return false;
}

// A ghost: a map point in the space a mover occupied at some keyframe time that is not on a
// static surface (movers stand on the floor, so floor points touch their boxes).
bool IsGhost(const SyntheticScene& scene, const Vec3& point_world, const std::vector<double>& times) {
  return InsideSweptMoverVolume(scene, point_world, times) && DistanceToStaticScene(scene, point_world) > 2 * kTestVoxel;
}

class DenseSyntheticTest : public SyntheticDenseTest {
 protected:
  static PointCloud BuildMap(const std::vector<DenseKeyframe>& keyframes) {
    DenseMapperOptions mapper;
    mapper.threaded = false;
    DenseMapper dense(scene_->camera(), Options(), {}, mapper);
    for (const DenseKeyframe& keyframe : keyframes) dense.AddKeyframe(keyframe);
    return dense.CurrentCloud();
  }
};

TEST_F(DenseSyntheticTest, NoGhostsWithMasksGhostsWithout) {
  const PointCloud masked = BuildMap(masked_);
  const PointCloud unmasked = BuildMap(unmasked_);
  ASSERT_GT(masked.size(), 10000u);
  const std::vector<double> times = KeyframeTimes();
  const auto count_ghosts = [&](const PointCloud& cloud) {
    return std::count_if(cloud.points.begin(), cloud.points.end(),
                         [&](const Eigen::Vector3f& p) { return IsGhost(*scene_, p.cast<double>(), times); });
  };
  const auto ghosts_masked = count_ghosts(masked), ghosts_unmasked = count_ghosts(unmasked);
  std::printf("ghosts: %ld of %zu points with masks, %ld of %zu without\n", static_cast<long>(ghosts_masked), masked.size(),
              static_cast<long>(ghosts_unmasked), unmasked.size());
  EXPECT_EQ(ghosts_masked, 0);
  EXPECT_GT(ghosts_unmasked, 1000);  // mode none: people are painted into the map
}

TEST_F(DenseSyntheticTest, StaticSurfacesWithinOneCentimetre) {
  const PointCloud masked = BuildMap(masked_);
  std::printf("exact depth: %.4f of %zu points within 1 cm\n", FractionWithin(*scene_, masked, 0.01), masked.size());
  EXPECT_GE(FractionWithin(*scene_, masked, 0.01), 0.95);
}

// Keyframes arrive with drifting poses (4 mm and 0.06 degrees more per keyframe, 6 cm and 0.9
// degrees at the last one, as odometry drifts before a loop closure); afterwards the pose source
// reports the true poses. The map rebuilt at the corrected poses must be as accurate, and about as
// compact, as one built without drift: readings merged under drifted poses are off by at most the
// relative drift of neighbouring keyframes.
TEST_F(DenseSyntheticTest, FollowsCorrectedPoses) {
  std::mutex mutex;
  bool corrected = false;
  const auto drifted = [](const DenseKeyframe& k) {
    const double step = static_cast<double>(k.id) / kKeyframeStep;
    return Rigid3(Quat(Eigen::AngleAxisd(0.001 * step, Vec3::UnitZ())), Vec3(0.0035 * step, 0.002 * step, 0)) * k.world_from_cam;
  };
  std::vector<DenseKeyframe> handed_over = masked_;
  for (DenseKeyframe& k : handed_over) k.world_from_cam = drifted(k);
  const KeyframePoseSource source = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    KeyframePoses poses;
    for (const DenseKeyframe& k : masked_) poses[k.id] = corrected ? k.world_from_cam : drifted(k);
    return poses;
  };
  DenseMapperOptions mapper;
  mapper.threaded = false;
  DenseMapper dense(scene_->camera(), Options(), source, mapper);
  for (const DenseKeyframe& keyframe : handed_over) dense.AddKeyframe(keyframe);
  const std::size_t stored_with_drift = dense.stats().map.points;
  const double drifted_accuracy = FractionWithin(*scene_, dense.CurrentCloud(), 0.01);
  EXPECT_LT(drifted_accuracy, 0.8);  // at the drifted poses: smeared copies
  {
    std::lock_guard<std::mutex> lock(mutex);
    corrected = true;
  }
  const PointCloud cloud = dense.CurrentCloud();
  const PointCloud reference = BuildMap(masked_);
  std::printf("within 1 cm: %.3f drifted, %.3f corrected, %.3f without drift; stored %zu -> %zu; output %zu (without drift %zu)\n",
              drifted_accuracy, FractionWithin(*scene_, cloud, 0.01), FractionWithin(*scene_, reference, 0.01),
              stored_with_drift, dense.stats().map.points, cloud.size(), reference.size());
  EXPECT_GE(FractionWithin(*scene_, cloud, 0.01), 0.95);
  // Readings merged under drifted poses stay merged: the corrected map is a little sparser.
  EXPECT_GT(cloud.size(), reference.size() * 8 / 10);
  EXPECT_LT(cloud.size(), reference.size() * 11 / 10);
  // Re-indexing at the corrected poses merged the drifted copies.
  EXPECT_LT(dense.stats().map.points, stored_with_drift * 8 / 10);
}

// The same keyframes with Kinect-like depth noise (sigma = 1.5 mm * z^2: 1.35 cm at 3 m, 2.4 cm
// at 4 m) at the default settings (Dense.depthNoiseAt1m 0.0015, maxDepth 4 m). This measures
// (and guards) what a 1 cm map of raw depth reaches; it does not meet the 1 cm / 95 % of exact
// depth (docs/RESULTS.md).
TEST_F(DenseSyntheticTest, StaticSurfacesWithKinectLikeNoise) {
  SynthOptions synth = SynthPreset("dynamic");
  synth.num_frames = 90;
  synth.depth_noise_at_1m = 0.0015;
  const SyntheticScene noisy(synth);
  DenseOptions options;
  options.voxel_size = kTestVoxel;
  DenseMapperOptions mapper;
  mapper.threaded = false;
  DenseMapper dense(noisy.camera(), options, {}, mapper);
  for (int i = 0; i < noisy.num_frames(); i += kKeyframeStep) dense.AddKeyframe(SceneKeyframe(noisy, i, true));
  const PointCloud cloud = dense.CurrentCloud();
  const double within_1cm = FractionWithin(noisy, cloud, 0.01), within_2cm = FractionWithin(noisy, cloud, 0.02);
  std::printf("Kinect-like noise: %zu points (%zu stored), %.3f within 1 cm, %.3f within 2 cm\n", cloud.size(),
              dense.stats().map.points, within_1cm, within_2cm);
  EXPECT_GE(within_1cm, 0.45);
  EXPECT_GE(within_2cm, 0.7);
}

// The worker integrates while another thread builds the map on demand; the final map equals a
// single-threaded build (same order, fixed poses).
TEST_F(DenseSyntheticTest, OnDemandBuildsWhileTheWorkerRuns) {
  DenseMapper dense(scene_->camera(), Options());
  std::atomic<bool> done{false};
  std::atomic<int> builds{0}, non_empty{0};
  std::thread reader([&] {
    while (!done) {
      non_empty += !dense.CurrentCloud().empty();
      ++builds;
    }
  });
  for (const DenseKeyframe& keyframe : masked_) dense.AddKeyframe(keyframe);
  dense.Finish();
  done = true;
  reader.join();
  EXPECT_GT(builds.load(), 0);
  EXPECT_GT(non_empty.load(), 0);  // partial maps seen while keyframes were still arriving
  EXPECT_EQ(dense.CurrentCloud().size(), BuildMap(masked_).size());
  EXPECT_EQ(dense.stats().keyframes, static_cast<long>(masked_.size()));
}

}  // namespace
}  // namespace esdslam
