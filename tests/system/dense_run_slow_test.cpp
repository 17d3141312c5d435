// `esdslam run --dense` end to end on the synthetic dynamic sequence (perfect VOC labels through
// the folder segmenter, single thread): the dense map built at the SLAM poses has no ghosts of the
// movers in mode semantic and has them in mode none, its static surfaces are where the true room
// is, culled keyframes stay in it, and the map can be rebuilt (as `esdslam map` does) from the
// run's saved dense_keyframes.txt and masks/.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "dense/cloud_io.h"
#include "eval/ate.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "synth/synthetic_scene.h"
#include "system/pipeline.h"
#include "system/run_loop.h"
#include "system/dynamic_sequence.h"
#include "support/temp_path.h"

namespace esdslam {
namespace {

constexpr int kFrames = 50;

const std::string& SequenceDir() { return testing::DynamicTestSequence(kFrames); }

const SyntheticScene& Scene() {  // the scene DynamicTestSequence wrote (deterministic)
  static const SyntheticScene scene([] {
    SynthOptions options = SynthPreset("dynamic");
    options.num_frames = kFrames;
    options.supersampling = 1;
    return options;
  }());
  return scene;
}

double DistanceToStatic(const Vec3& p_world) {
  double best = 1e9;
  for (int b = 0; b < static_cast<int>(Scene().boxes().size()); ++b) {
    if (Scene().boxes()[b].object_id != 0) continue;
    const Vec3 p = Scene().WorldFromBox(b, 0).inverse() * p_world;
    const Vec3 excess = p.cwiseAbs() - Scene().boxes()[b].half_size;
    best = std::min(best, (excess.array() <= 0).all() ? -excess.maxCoeff() : excess.cwiseMax(0.0).norm());
  }
  return best;
}

bool InMoverVolume(const Vec3& p_world, double margin) {
  for (int mover = 1; mover <= Scene().num_movers(); ++mover) {
    const int box = Scene().MoverBox(mover);
    for (int i = 0; i < kFrames; ++i) {
      const Vec3 p = Scene().WorldFromBox(box, Scene().FrameTime(i)).inverse() * p_world;
      if ((p.cwiseAbs().array() <= (Scene().boxes()[box].half_size + Vec3::Constant(margin)).array()).all()) return true;
    }
  }
  return false;
}

struct DenseRun {
  std::string out;
  PointCloud cloud_world;  // dense.ply mapped into the scene's world frame
  // How far the keyframes' pose errors (after the ATE alignment) can move a reading within the
  // depth range: max over keyframes of |translation error| + rotation error * max depth (m).
  double pose_displacement_m = 0;
  int ghosts = 0;           // points in the movers' volume farther than 2 cm + that from static surfaces
  int ghosts_2cm = 0;       // the same with 2 cm alone (counts points of surfaces moved by pose error)
  double within_1cm = 0, within_2cm = 0;
  std::size_t dense_keyframes = 0, live_keyframes = 0;
};

double FractionWithin(const PointCloud& cloud_world, double tolerance) {
  const auto close = std::count_if(cloud_world.points.begin(), cloud_world.points.end(),
                                   [&](const Eigen::Vector3f& p) { return DistanceToStatic(p.cast<double>()) <= tolerance; });
  return static_cast<double>(close) / std::max<std::size_t>(1, cloud_world.size());
}

double PoseDisplacement(const std::vector<StampedPose>& truth, const std::vector<StampedPose>& keyframes,
                        const Similarity3& truth_from_slam, double max_depth_m) {
  double worst = 0;
  for (const StampedPose& keyframe : keyframes) {
    const StampedPose& true_pose = *std::min_element(truth.begin(), truth.end(), [&](const auto& a, const auto& b) {
      return std::abs(a.timestamp - keyframe.timestamp) < std::abs(b.timestamp - keyframe.timestamp);
    });
    const Vec3 position = truth_from_slam * keyframe.world_from_cam.translation();
    const Mat3 rotation = truth_from_slam.rotation * keyframe.world_from_cam.rotation().toRotationMatrix();
    const double angle = Eigen::AngleAxisd(true_pose.world_from_cam.rotation().toRotationMatrix().transpose() * rotation).angle();
    worst = std::max(worst, (position - true_pose.world_from_cam.translation()).norm() + angle * max_depth_m);
  }
  return worst;
}

DenseRun RunDenseUncached(DynamicMode mode) {
  DenseRun result;
  result.out = testing::TestTempPath(fmt::format("dense_run_{}", ToString(mode)));
  std::filesystem::remove_all(result.out);
  RunFlags flags;
  flags.single_thread = true;  // dense mapping on the tracking thread too
  flags.mode = mode;
  // Every frame's own labels: the map's static fidelity with exact masks. With predicted masks
  // in mode semantic (no geometry check behind them) slivers of the movers that the carried
  // mask misses reach some keyframes (measured: 67 ghosts, 0.77 within 2 cm; docs/RESULTS.md).
  flags.segment_every = 1;
  flags.dense = true;
  flags.run.out_dir = result.out;  // masks in OUT/masks
  const RunConfig config = ResolveRunConfig(LoadRunSettings(SequenceDir() + "/run.yaml"), flags);
  const RunSettings& settings = config.settings;
  TumFolderSource source(TumSequence::Open(SequenceDir()).frames(), settings.core.depth_map_factor);
  Pipeline run(config);
  RunFrames(source, run, [](const FrameReport&) {});
  run.Finish(result.out);
  const std::vector<StampedPose> truth = ReadTumTrajectory(SequenceDir() + "/groundtruth.txt");
  const Similarity3 truth_from_slam = ComputeAte(truth, run.system().Trajectory()).groundtruth_from_estimate;
  result.dense_keyframes = ReadTumTrajectory(result.out + "/dense_keyframes.txt").size();
  result.pose_displacement_m = PoseDisplacement(truth, ReadTumTrajectory(result.out + "/dense_keyframes.txt"),
                                                truth_from_slam, settings.dense.max_depth);
  for (const Eigen::Vector3f& p : ReadPly(result.out + "/dense.ply").points) {
    const Vec3 q = truth_from_slam * p.cast<double>();
    result.cloud_world.push_back(q.cast<float>(), {});
    const double to_static = DistanceToStatic(q);
    if (to_static <= 0.02 || !InMoverVolume(q, 0.01)) continue;
    ++result.ghosts_2cm;
    result.ghosts += to_static > 0.02 + result.pose_displacement_m;
  }
  result.within_1cm = FractionWithin(result.cloud_world, 0.01);
  result.within_2cm = FractionWithin(result.cloud_world, 0.02);
  result.live_keyframes = static_cast<std::size_t>(run.system().num_keyframes());
  return result;
}

const DenseRun& RunDense(DynamicMode mode) {
  static std::map<DynamicMode, DenseRun> runs;
  auto it = runs.find(mode);
  if (it == runs.end()) it = runs.emplace(mode, RunDenseUncached(mode)).first;
  return it->second;
}

// The map at the SLAM poses: its accuracy is bounded by the poses' (keyframe ATE about 4 mm,
// rotation errors up to about 0.2 degree, which move a wall 4 m away by 14 mm), so 1 cm is
// checked at the true poses below and 2 cm here, and a ghost is a point in the movers' volume
// farther from every static surface than 2 cm plus what the run's own pose errors explain. A
// copy of a person is a body-sized block, far from static surfaces; ghosts_2cm (printed) also
// counts floor and wall points the pose errors moved into the margin.
TEST(DenseRunTest, SemanticModeMapsNoGhostsModeNoneDoes) {
  const DenseRun& semantic = RunDense(DynamicMode::kSemantic);
  const DenseRun& none = RunDense(DynamicMode::kNone);
  std::printf("semantic: %zu points, %d ghosts (%d at 2 cm; pose displacement %.1f mm), %.3f within 1 cm, %.3f within "
              "2 cm, %zu dense keyframes (%zu live)\n",
              semantic.cloud_world.size(), semantic.ghosts, semantic.ghosts_2cm, 1e3 * semantic.pose_displacement_m,
              semantic.within_1cm, semantic.within_2cm, semantic.dense_keyframes, semantic.live_keyframes);
  std::printf("none: %zu points, %d ghosts (%d at 2 cm; pose displacement %.1f mm), %.3f within 2 cm\n",
              none.cloud_world.size(), none.ghosts, none.ghosts_2cm, 1e3 * none.pose_displacement_m, none.within_2cm);
  ASSERT_GT(semantic.cloud_world.size(), 10000u);
  EXPECT_EQ(semantic.ghosts, 0);
  EXPECT_GT(none.ghosts, 1000);
  EXPECT_GE(semantic.within_2cm, 0.9);
  EXPECT_GE(semantic.dense_keyframes, semantic.live_keyframes);  // culled keyframes keep their points
  for (const char* file : {"octomap.bt", "dense_top.png", "dense_view.png"})
    EXPECT_TRUE(std::filesystem::exists(semantic.out + "/" + file)) << file;
}

// What `esdslam map --trajectory FILE --masks OUT/masks` does, from the run's saved keyframes.
PointCloud Rebuild(const std::string& out, const std::vector<StampedPose>& poses) {
  const RunSettings settings = LoadRunSettings(SequenceDir() + "/run.yaml");
  const TumSequence sequence = TumSequence::Open(SequenceDir());
  DenseMapperOptions mapper;
  mapper.threaded = false;
  DenseMapper dense(PinholeCamera(settings.core.camera), settings.dense, {}, mapper);
  long id = 0;
  for (const StampedPose& pose : poses) {
    const auto frame = std::find_if(sequence.frames().begin(), sequence.frames().end(),
                                    [&](const FrameEntry& f) { return std::abs(f.timestamp - pose.timestamp) < 1e-5; });
    if (frame == sequence.frames().end()) throw Error(fmt::format("no frame at {:.6f}", pose.timestamp));
    const RgbdImages images = LoadRgbd(*frame, settings.core.depth_map_factor);
    const cv::Mat mask = cv::imread(fmt::format("{}/masks/{:.6f}.png", out, frame->timestamp), cv::IMREAD_GRAYSCALE);
    if (mask.empty()) throw Error(fmt::format("no mask for {:.6f}", frame->timestamp));
    dense.AddKeyframe({id++, pose.timestamp, pose.world_from_cam, images.bgr, images.depth_m, mask});
  }
  return dense.CurrentCloud();
}

// Rebuilt at the run's final poses, the map matches the run's (the run merged some readings at
// earlier, pre-BA poses, so it is a little sparser). Rebuilt with the same keyframes and the
// run's own masks at the true poses, static surfaces are within 1 cm and there are no ghosts.
TEST(DenseRunTest, MapRebuiltFromSavedKeyframesAndMasks) {
  const DenseRun& run = RunDense(DynamicMode::kSemantic);
  const std::vector<StampedPose> keyframes = ReadTumTrajectory(run.out + "/dense_keyframes.txt");
  const PointCloud rebuilt = Rebuild(run.out, keyframes);
  EXPECT_GT(rebuilt.size(), run.cloud_world.size() * 9 / 10);
  EXPECT_LT(rebuilt.size(), run.cloud_world.size() * 13 / 10);
  const std::vector<StampedPose> truth = Scene().GroundTruth();
  std::vector<StampedPose> true_keyframes;
  for (const StampedPose& pose : keyframes)
    true_keyframes.push_back(*std::min_element(truth.begin(), truth.end(), [&](const StampedPose& a, const StampedPose& b) {
      return std::abs(a.timestamp - pose.timestamp) < std::abs(b.timestamp - pose.timestamp);
    }));
  const PointCloud at_truth = Rebuild(run.out, true_keyframes);
  const auto ghosts = std::count_if(at_truth.points.begin(), at_truth.points.end(), [](const Eigen::Vector3f& p) {
    return DistanceToStatic(p.cast<double>()) > 0.02 && InMoverVolume(p.cast<double>(), 0.01);
  });
  std::printf("rebuilt: %zu points at the run's poses, %zu at the true poses (%.3f within 1 cm, %ld ghosts)\n", rebuilt.size(),
              at_truth.size(), FractionWithin(at_truth, 0.01), static_cast<long>(ghosts));
  EXPECT_GE(FractionWithin(at_truth, 0.01), 0.95);
  EXPECT_EQ(ghosts, 0);
}

}  // namespace
}  // namespace esdslam
