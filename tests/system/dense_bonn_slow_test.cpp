// `esdslam run --dense` on ../shared/data/bonn_crowd_dev (config/bonn.yaml, the CLI's default
// mode full: ESPNetv2 person masks every 4th frame, predicted between, region growing, geometry check;
// single thread), then its octomap.bt read back with OctoMap's own
// reader: wherever a keyframe's depth sees the floor or a wall (outside the dilated person mask,
// within the OctoMap range) the cell is occupied, and half way along that ray the cell is free.
// Floor and walls are told apart by the depth normal against "up" (the keyframes' mean up axis).
// (The ground-truth poses of this dataset are the motion-capture markers', not the camera's:
// maps at those poses are blurred by the offset, so the run's own keyframe poses are used.)
#include <filesystem>

#include <gtest/gtest.h>
#include <octomap/OcTree.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "dense/cloud_io.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "system/pipeline.h"
#include "system/run_loop.h"
#include "support/temp_path.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

const std::string kDir = ::esdslam::testing::TestDataDir() + "/data/bonn_crowd_dev";

struct Counts {
  int floor = 0, floor_occupied = 0, wall = 0, wall_occupied = 0, probes = 0, free = 0;
  // Wall or floor probes whose cell is not occupied, by where the tree's nearest occupied cell
  // along the probe's ray is (within kMissSearchCells cells): behind the reading (the map holds the
  // surface farther than this keyframe saw it), in front of it, or nowhere (the map holds nothing
  // there: space later keyframes saw empty). Grazing: probes whose ray meets the estimated
  // surface at |cos| < 0.2 (thin structures whose 4-px neighbours fall on other surfaces too).
  int missed_behind = 0, missed_in_front = 0, missed_nothing = 0, missed_grazing = 0;
};

constexpr double kMissSearchCells = 5.0;

bool OccupiedNear(const octomap::OcTree& tree, const Vec3& p, const Vec3& dir) {
  for (const double t : {0.0, -0.5, 0.5, -1.0, 1.0}) {  // the cell at the reading or one cell off along the ray
    const Vec3 q = p + t * tree.getResolution() * dir;
    const octomap::OcTreeNode* node = tree.search(q.x(), q.y(), q.z());
    if (node != nullptr && tree.isNodeOccupied(node)) return true;
  }
  return false;
}

// Signed distance in cells along `dir` from `p` to the nearest occupied cell (positive: behind
// p, seen from the camera), 0 when none is within kMissSearchCells.
double NearestOccupiedAlongRay(const octomap::OcTree& tree, const Vec3& p, const Vec3& dir) {
  for (double t = 1.25; t <= kMissSearchCells; t += 0.25)
    for (const double sign : {1.0, -1.0}) {
      const Vec3 q = p + sign * t * tree.getResolution() * dir;
      const octomap::OcTreeNode* node = tree.search(q.x(), q.y(), q.z());
      if (node != nullptr && tree.isNodeOccupied(node)) return sign * t;
    }
  return 0.0;
}

void CountMiss(const octomap::OcTree& tree, const Vec3& p, const Vec3& dir, const Vec3& normal, Counts* counts) {
  if (std::abs(normal.dot(dir)) < 0.2) ++counts->missed_grazing;
  const double nearest = NearestOccupiedAlongRay(tree, p, dir);
  (nearest > 0 ? counts->missed_behind : nearest < 0 ? counts->missed_in_front : counts->missed_nothing) += 1;
}

void CheckKeyframe(const octomap::OcTree& tree, const PinholeCamera& camera, const DenseKeyframe& k, const Vec3& up,
                   double floor_height, double max_range, Counts* counts) {
  const auto point = [&](int u, int v) {
    const float z = k.depth_m.at<float>(v, u);
    const cv::Point2f undistorted = camera.Undistort({cv::Point2f(static_cast<float>(u), static_cast<float>(v))})[0];
    return Vec3(k.world_from_cam * camera.Backproject(Vec2(undistorted.x, undistorted.y), z));
  };
  for (int v = 8; v < k.depth_m.rows - 8; v += 16)
    for (int u = 8; u < k.depth_m.cols - 8; u += 16) {
      const float z = k.depth_m.at<float>(v, u);
      if (!(z > 0.3f) || k.dynamic_mask.at<std::uint8_t>(v, u)) continue;
      bool valid = true;
      for (const auto& [du, dv] : {std::pair{4, 0}, {-4, 0}, {0, 4}, {0, -4}})
        valid = valid && k.depth_m.at<float>(v + dv, u + du) > 0 && !k.dynamic_mask.at<std::uint8_t>(v + dv, u + du);
      if (!valid) continue;
      const Vec3 p = point(u, v);
      const Vec3 normal = (point(u + 4, v) - point(u - 4, v)).cross(point(u, v + 4) - point(u, v - 4)).normalized();
      const Vec3 origin = k.world_from_cam.translation(), dir = (p - origin).normalized();
      if ((p - origin).norm() > max_range - 0.2) continue;  // beyond the OctoMap range: free space only
      const double height = (p - origin).dot(up) + origin.dot(up);
      const bool floor = std::abs(normal.dot(up)) > 0.9 && height < floor_height + 0.15;
      const bool wall = std::abs(normal.dot(up)) < 0.3 && height > floor_height + 0.3;
      if (!floor && !wall) continue;
      const bool occupied = OccupiedNear(tree, p, dir);
      if (!occupied) CountMiss(tree, p, dir, normal, counts);
      (floor ? counts->floor : counts->wall) += 1;
      (floor ? counts->floor_occupied : counts->wall_occupied) += occupied;
      const Vec3 middle = origin + 0.5 * (p - origin);
      const octomap::OcTreeNode* node = tree.search(middle.x(), middle.y(), middle.z());
      ++counts->probes;
      counts->free += node != nullptr && !tree.isNodeOccupied(node);
    }
}

TEST(DenseBonnSlowTest, OctomapFloorAndWallsOccupiedRaysFree) {
  if (!std::filesystem::exists(kDir)) GTEST_SKIP() << kDir << " not found";
  const TumSequence sequence = TumSequence::Open(kDir);
  const std::string out = testing::TestTempPath("dense_bonn");
  std::filesystem::remove_all(out);
  RunFlags flags;
  flags.single_thread = true;  // dense mapping on the tracking thread too
  flags.dense = true;
  flags.run.out_dir = out;  // masks in OUT/masks
  const RunConfig config =
      ResolveRunConfig(LoadRunSettings(::esdslam::testing::SourceDir() + "/config/bonn.yaml"), flags);
  const RunSettings& settings = config.settings;
  {
    TumFolderSource source(sequence.frames(), settings.core.depth_map_factor);
    Pipeline run(config);
    RunFrames(source, run, [](const FrameReport&) {});
    run.Finish(out);
  }
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(out + "/octomap.bt"));  // OctoMap's own reader
  EXPECT_DOUBLE_EQ(tree.getResolution(), settings.dense.octomap_resolution);
  const PinholeCamera camera(settings.core.camera);
  const int dilation = settings.dense.mask_dilation_px;
  const cv::Mat disk = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * dilation + 1, 2 * dilation + 1));
  std::vector<DenseKeyframe> keyframes;
  Vec3 down = Vec3::Zero();
  for (const StampedPose& pose : ReadTumTrajectory(out + "/dense_keyframes.txt")) {
    const auto frame = std::find_if(sequence.frames().begin(), sequence.frames().end(),
                                    [&](const FrameEntry& f) { return std::abs(f.timestamp - pose.timestamp) < 1e-5; });
    ASSERT_NE(frame, sequence.frames().end());
    const RgbdImages images = LoadRgbd(*frame, settings.core.depth_map_factor);
    cv::Mat mask = cv::imread(fmt::format("{}/masks/{:.6f}.png", out, frame->timestamp), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(mask.empty());
    cv::dilate(mask, mask, disk);
    keyframes.push_back({0, pose.timestamp, pose.world_from_cam, images.bgr, images.depth_m, mask});
    down += pose.world_from_cam.rotation() * Vec3::UnitY();
  }
  ASSERT_GE(keyframes.size(), 15u);
  const Vec3 up = -down.normalized();
  // Floor level: the 2nd percentile of the map points' heights.
  std::vector<double> heights;
  for (const auto& p : ReadPly(out + "/dense.ply").points) heights.push_back(p.cast<double>().dot(up));
  ASSERT_GT(heights.size(), 100000u);
  std::nth_element(heights.begin(), heights.begin() + heights.size() / 50, heights.end());
  const double floor_height = heights[heights.size() / 50];
  Counts counts;
  for (const DenseKeyframe& k : keyframes)
    CheckKeyframe(tree, camera, k, up, floor_height, settings.dense.octomap_max_range, &counts);
  std::printf("bonn octomap: %zu keyframes; floor %d/%d occupied, walls %d/%d occupied, mid-ray free %d/%d\n",
              keyframes.size(), counts.floor_occupied, counts.floor, counts.wall_occupied, counts.wall, counts.free,
              counts.probes);
  std::printf("bonn octomap misses: %d with the surface 1.25-%.0f cells behind the reading, %d in front, %d with no "
              "occupied cell within %.0f cells along the ray; %d of them at grazing incidence\n",
              counts.missed_behind, kMissSearchCells, counts.missed_in_front, counts.missed_nothing, kMissSearchCells,
              counts.missed_grazing);
  ASSERT_GT(counts.floor, 200);
  ASSERT_GT(counts.wall, 200);
  EXPECT_GE(counts.floor_occupied, 0.95 * counts.floor);
  EXPECT_GE(counts.wall_occupied, 0.95 * counts.wall);
  EXPECT_GE(counts.free, 0.95 * counts.probes);
  for (const char* file : {"dense_top.png", "dense_view.png"}) EXPECT_TRUE(std::filesystem::exists(out + "/" + file)) << file;
}

}  // namespace
}  // namespace esdslam
