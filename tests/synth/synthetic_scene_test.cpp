// Known-answer tests of the synthetic scene generator: multi-view depth consistency, exact
// masks, determinism, texture quality for FAST, and the camera motion limits.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "synth/sequence_writer.h"
#include "synth/synth_layout.h"
#include "synth/synthetic_scene.h"
#include "support/small_synth.h"

namespace esdslam {
namespace {

// Quarter resolution (320x240) keeps the tests fast; the geometry is the same.
SynthOptions SmallOptions(const std::string& preset, int frames) {
  return ::esdslam::testing::SmallSynthOptions(preset, frames);
}

cv::Mat Quantised(const cv::Mat& depth_m) { return Png16ToDepth(DepthToPng16(depth_m)); }

struct ReprojectionStats {
  int checked = 0;
  double max_error = 0;  // metres
};

// Back-projects every static pixel of frame i (quantised depth as stored in the PNG), moves it
// into frame j with `j_from_i` and compares its depth with frame j's quantised depth, inverse-
// depth interpolated between the 4 pixels around the projection (exact on a plane). Only
// projections whose 4 neighbours see the same plane (surface id) and no mover are compared.
ReprojectionStats Reproject(const SyntheticScene& scene, const SynthFrame& fi, const SynthFrame& fj,
                            const Rigid3& j_from_i) {
  const PinholeCamera& camera = scene.camera();
  const cv::Mat zi = Quantised(fi.depth_m), zj = Quantised(fj.depth_m);
  ReprojectionStats stats;
  for (int v = 0; v < zi.rows; ++v) {
    for (int u = 0; u < zi.cols; ++u) {
      const float z = zi.at<float>(v, u);
      if (z <= 0 || fi.mover_mask.at<uchar>(v, u) != 0) continue;
      const Vec3 p_j = j_from_i * camera.Backproject(Vec2(u, v), z);
      if (p_j.z() < 0.1) continue;
      const Vec2 pixel = camera.Project(p_j);
      const int u0 = static_cast<int>(std::floor(pixel.x())), v0 = static_cast<int>(std::floor(pixel.y()));
      if (u0 < 0 || v0 < 0 || u0 + 1 >= zj.cols || v0 + 1 >= zj.rows) continue;
      const int surface = fi.surface_id.at<int>(v, u);
      bool same_plane = true;
      double inv[2][2];
      for (int dv = 0; dv < 2; ++dv) {
        for (int du = 0; du < 2; ++du) {
          const float zn = zj.at<float>(v0 + dv, u0 + du);
          same_plane = same_plane && zn > 0 && fj.surface_id.at<int>(v0 + dv, u0 + du) == surface;
          inv[dv][du] = zn > 0 ? 1.0 / zn : 0.0;
        }
      }
      if (!same_plane) continue;
      const double a = pixel.x() - u0, b = pixel.y() - v0;
      const double inv_z = (1 - b) * ((1 - a) * inv[0][0] + a * inv[0][1]) + b * ((1 - a) * inv[1][0] + a * inv[1][1]);
      stats.max_error = std::max(stats.max_error, std::abs(1.0 / inv_z - p_j.z()));
      ++stats.checked;
    }
  }
  return stats;
}

TEST(SyntheticScene, StaticDepthReprojectsIntoOtherFramesWithinQuantisation) {
  const SyntheticScene scene(SmallOptions("dynamic", 40));
  const int pairs[][2] = {{0, 3}, {5, 20}, {12, 39}, {39, 0}};
  for (const auto& pair : pairs) {
    const SynthFrame fi = scene.RenderFrame(pair[0]);
    const SynthFrame fj = scene.RenderFrame(pair[1]);
    const Rigid3 j_from_i = fj.world_from_cam.inverse() * fi.world_from_cam;
    const ReprojectionStats stats = Reproject(scene, fi, fj, j_from_i);
    EXPECT_GT(stats.checked, fi.depth_m.total() / 4) << pair[0] << "->" << pair[1];
    std::printf("frames %d -> %d: %d pixels compared, max depth error %.2e m\n", pair[0], pair[1], stats.checked,
                stats.max_error);
    // Two 1/5000 m quantisations (frame i and frame j) and the ray through them.
    EXPECT_LT(stats.max_error, 4e-4) << pair[0] << "->" << pair[1];
    // The check is sensitive: a ~1 cm pose error is far outside the tolerance.
    const Rigid3 wrong = Rigid3(Quat::Identity(), Vec3(0.005, 0, 0.01)) * j_from_i;
    EXPECT_GT(Reproject(scene, fi, fj, wrong).max_error, 5e-3);
  }
}

TEST(SyntheticScene, SameSeedGivesIdenticalImagesOtherSeedDiffers) {
  SynthOptions options = SmallOptions("dynamic", 20);
  options.depth_noise_at_1m = 0.002;
  const SynthFrame a = SyntheticScene(options).RenderFrame(7);
  const SynthFrame b = SyntheticScene(options).RenderFrame(7);
  EXPECT_EQ(cv::norm(a.bgr, b.bgr, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.depth_m, b.depth_m, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.mover_mask, b.mover_mask, cv::NORM_INF), 0.0);
  options.seed = 2;
  const SynthFrame c = SyntheticScene(options).RenderFrame(7);
  EXPECT_GT(cv::norm(a.bgr, c.bgr, cv::NORM_L1) / a.bgr.total(), 20.0);
}

TEST(SyntheticScene, DepthNoiseHasRequestedSpread) {
  SynthOptions options = SmallOptions("static", 5);
  const SyntheticScene exact_scene(options);
  options.depth_noise_at_1m = 0.003;
  const SyntheticScene noisy_scene(options);
  const SynthFrame exact = exact_scene.RenderFrame(2), noisy = noisy_scene.RenderFrame(2);
  double sum_sq = 0;  // of the normalised error (z_noisy - z) / (0.003 z^2)
  int n = 0;
  for (int v = 0; v < exact.depth_m.rows; ++v) {
    for (int u = 0; u < exact.depth_m.cols; ++u) {
      const double z = exact.depth_m.at<float>(v, u), zn = noisy.depth_m.at<float>(v, u);
      if (z <= 0 || zn <= 0) continue;
      const double e = (zn - z) / (0.003 * z * z);
      sum_sq += e * e;
      ++n;
    }
  }
  ASSERT_GT(n, 10000);
  EXPECT_NEAR(std::sqrt(sum_sq / n), 1.0, 0.05);
}

TEST(SyntheticScene, MoverMaskMarksExactlyThePixelsWhereAMoverIsTheNearestSurface) {
  const SyntheticScene scene(SmallOptions("dynamic", 30));
  ASSERT_EQ(scene.num_movers(), 3);
  int mover_pixels = 0;
  for (const int index : {0, 14, 29}) {
    const SynthFrame frame = scene.RenderFrame(index);
    const double time = scene.FrameTime(index);
    for (int v = 0; v < frame.depth_m.rows; v += 2) {
      for (int u = 0; u < frame.depth_m.cols; u += 2) {
        const Vec3 dir = frame.world_from_cam.rotation() * scene.camera().Backproject(Vec2(u, v), 1.0);
        const Vec3 origin = frame.world_from_cam.translation();
        const int id = frame.mover_mask.at<uchar>(v, u);
        const double depth = frame.depth_m.at<float>(v, u);
        for (int k = 1; k <= scene.num_movers(); ++k) {
          const int box = scene.MoverBox(k);
          const Rigid3 box_from_world = scene.WorldFromBox(box, time).inverse();
          double t = 0;
          int face = 0;
          const bool hit = IntersectBox(scene.boxes()[box], box_from_world * origin, box_from_world.rotation() * dir,
                                        1e-9, &t, &face);
          if (id == k) {
            ASSERT_TRUE(hit) << "mask says mover " << k << " at " << u << "," << v;
            EXPECT_NEAR(t, depth, 1e-5);  // ray parameter = depth since dir has z = 1 in the camera
            ++mover_pixels;
          } else if (hit) {
            EXPECT_GT(t, depth - 1e-5) << "mover " << k << " in front but not in the mask at " << u << "," << v;
          }
        }
      }
    }
  }
  EXPECT_GT(mover_pixels, 1000);
}

TEST(SyntheticScene, TexturedFrameHasFastCornersInEveryCell) {
  SynthOptions options = SynthPreset("dynamic");
  options.num_frames = 240;
  const SyntheticScene scene(options);
  for (const int index : {0, 120, 239}) {
    const SynthFrame frame = scene.RenderFrame(index);
    cv::Mat grey;
    cv::cvtColor(frame.bgr, grey, cv::COLOR_BGR2GRAY);
    std::vector<cv::KeyPoint> corners;
    cv::FAST(grey, corners, 20, true);
    int cells[4][4] = {};
    for (const auto& kp : corners) cells[static_cast<int>(kp.pt.y * 4 / grey.rows)][static_cast<int>(kp.pt.x * 4 / grey.cols)]++;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) EXPECT_GE(cells[r][c], 20) << "frame " << index << " cell " << r << "," << c;
  }
}

// ORB features match distinctively between frames: most ratio-test matches agree with the
// ground-truth geometry (keypoint of frame a lifted with its depth and pose, projected into b).
TEST(SyntheticScene, OrbMatchesBetweenFramesAreGeometricallyCorrect) {
  SynthOptions options = SynthPreset("static");
  const SyntheticScene scene(options);
  const SynthFrame a = scene.RenderFrame(100), b = scene.RenderFrame(106);
  auto orb = cv::ORB::create(1000, 1.2f, 8, 31, 0, 2, cv::ORB::HARRIS_SCORE, 31, 20);
  std::vector<cv::KeyPoint> kps_a, kps_b;
  cv::Mat desc_a, desc_b, grey_a, grey_b;
  cv::cvtColor(a.bgr, grey_a, cv::COLOR_BGR2GRAY);
  cv::cvtColor(b.bgr, grey_b, cv::COLOR_BGR2GRAY);
  orb->detectAndCompute(grey_a, cv::noArray(), kps_a, desc_a);
  orb->detectAndCompute(grey_b, cv::noArray(), kps_b, desc_b);
  std::vector<std::vector<cv::DMatch>> knn;
  cv::BFMatcher(cv::NORM_HAMMING).knnMatch(desc_a, desc_b, knn, 2);
  const Rigid3 b_from_a = b.world_from_cam.inverse() * a.world_from_cam;
  int matches = 0, correct = 0;
  for (const auto& pair : knn) {
    if (pair.size() < 2 || pair[0].distance > 0.8 * pair[1].distance) continue;
    const cv::Point2f pa = kps_a[pair[0].queryIdx].pt, pb = kps_b[pair[0].trainIdx].pt;
    const float z = a.depth_m.at<float>(cvRound(pa.y), cvRound(pa.x));
    if (z <= 0) continue;
    const Vec2 predicted = scene.camera().Project(b_from_a * scene.camera().Backproject(Vec2(pa.x, pa.y), z));
    ++matches;
    correct += (predicted - Vec2(pb.x, pb.y)).norm() < 3.0;
  }
  std::printf("ORB ratio-test matches %d, geometrically correct %d\n", matches, correct);
  EXPECT_GT(matches, 300);
  EXPECT_GT(correct, 0.9 * matches);
}

// Largest speed (m/s) and rotation rate (deg/s) between consecutive frames.
void MotionLimits(const SyntheticScene& scene, double* max_speed, double* max_rate) {
  *max_speed = *max_rate = 0;
  for (int i = 1; i < scene.num_frames(); ++i) {
    const Rigid3 delta = scene.WorldFromCam(i - 1).inverse() * scene.WorldFromCam(i);
    *max_speed = std::max(*max_speed, delta.translation().norm() * scene.options().fps);
    *max_rate = std::max(*max_rate, RotationAngle(delta.rotation()) * 180 / M_PI * scene.options().fps);
  }
}

TEST(SyntheticScene, TrajectoriesMoveLikeAHandheldCameraAndTheLoopCloses) {
  for (const char* preset : {"static", "loop"}) {
    const SyntheticScene scene(SynthPreset(preset));
    double speed, rate;
    MotionLimits(scene, &speed, &rate);
    EXPECT_GT(speed, 0.15) << preset;
    EXPECT_LT(speed, 0.6) << preset;
    EXPECT_LT(rate, 35.0) << preset;
  }
  const SyntheticScene loop(SynthPreset("loop"));
  const Rigid3 start_from_end = loop.WorldFromCam(0).inverse() * loop.WorldFromCam(loop.num_frames() - 1);
  EXPECT_LT(start_from_end.translation().norm(), 1e-9);
  EXPECT_LT(RotationAngle(start_from_end.rotation()), 1e-9);
  const Rigid3 half = loop.WorldFromCam(0).inverse() * loop.WorldFromCam(loop.num_frames() / 2);
  EXPECT_GT(RotationAngle(half.rotation()), 3.0);  // about half a turn in the middle
}

TEST(SyntheticScene, OrbitRevisitsItsStartAfterOneTurn) {
  const SyntheticScene orbit(SynthPreset("orbit"));
  EXPECT_EQ(orbit.num_frames(), 607);
  double speed, rate;
  MotionLimits(orbit, &speed, &rate);
  EXPECT_GT(speed, 0.3);
  EXPECT_LT(speed, 0.7);
  EXPECT_LT(rate, 35.0);
  // One turn every 449 frames: frame 449 is frame 0 again, frame 449 + k repeats frame k.
  for (const int k : {0, 60, 157}) {
    const Rigid3 same = orbit.WorldFromCam(k).inverse() * orbit.WorldFromCam(449 + k);
    EXPECT_LT(same.translation().norm(), 1e-9) << k;
    EXPECT_LT(RotationAngle(same.rotation()), 1e-9) << k;
  }
  const Rigid3 half = orbit.WorldFromCam(0).inverse() * orbit.WorldFromCam(225);
  EXPECT_GT(RotationAngle(half.rotation()), 3.0);
  // Looking at the room centre from 1.3 m: the centre is in front, near the optical axis.
  const Vec3 centre_in_cam = orbit.WorldFromCam(100).inverse() * Vec3(0, 0, 1.0);
  EXPECT_GT(centre_in_cam.z(), 1.0);
  EXPECT_LT(std::abs(centre_in_cam.x()), 0.3);
  SynthOptions with_movers = SynthPreset("orbit");
  with_movers.num_movers = 1;
  EXPECT_THROW(with_movers.Check(), Error);
}

TEST(SyntheticScene, OptionsAreChecked) {
  EXPECT_THROW(SynthPreset("crowd"), Error);
  SynthOptions options;
  options.trajectory = "spiral";
  EXPECT_THROW(options.Check(), Error);
  options = SynthOptions();
  options.num_movers = 5;
  EXPECT_THROW(options.Check(), Error);
  options = SynthOptions();
  options.depth_time_offset = 0.03;
  EXPECT_THROW(options.Check(), Error);
  options = SynthOptions();
  options.intrinsics.k1 = 0.1;
  EXPECT_THROW(SyntheticScene scene(options), Error);
  EXPECT_NO_THROW(SynthPreset("loop").Check());
}

// Distance (m) from a point to an axis-aligned box (0 inside).
double DistanceToBox(const Vec3& point, const StaticBox& box) {
  const Vec3 outside = ((point - box.centre).cwiseAbs() - box.half_size).cwiseMax(0.0);
  return outside.norm();
}

TEST(SyntheticScene, CorridorWalksAroundTheRingAndRevisitsItsStartAfterOneTurn) {
  const SynthOptions options = SynthPreset("corridor");
  EXPECT_EQ(options.num_frames, 781);
  const auto pose = [&](int frame) { return CameraPoseAt(options, frame / options.fps); };
  const SceneLayout layout = MakeSceneLayout(options);
  double max_speed = 0, min_speed = 1e9, max_rate = 0, min_clearance = 1e9, path_length = 0;
  for (int i = 1; i < options.num_frames; ++i) {
    const Rigid3 delta = pose(i - 1).inverse() * pose(i);
    const double speed = delta.translation().norm() * options.fps;
    max_speed = std::max(max_speed, speed), min_speed = std::min(min_speed, speed);
    max_rate = std::max(max_rate, RotationAngle(delta.rotation()) * 180 / M_PI * options.fps);
    if (i <= 600) path_length += delta.translation().norm();
    const Vec3 position = pose(i).translation();
    for (const StaticBox& box : layout.furniture) min_clearance = std::min(min_clearance, DistanceToBox(position, box));
    const Vec3 to_wall = layout.room_half_size - Vec3(std::abs(position.x()), std::abs(position.y()), 0);
    min_clearance = std::min({min_clearance, to_wall.x(), to_wall.y()});
  }
  std::printf("corridor: %.1f m per turn, speed %.2f-%.2f m/s, <= %.0f deg/s, clearance >= %.2f m\n", path_length,
              min_speed, max_speed, max_rate, min_clearance);
  EXPECT_NEAR(path_length, 23.3, 0.3);  // a walk through the floor, not a turn on the spot
  EXPECT_GT(min_speed, 0.9);
  EXPECT_LT(max_speed, 1.4);
  EXPECT_LT(max_rate, 120.0);
  EXPECT_GT(min_clearance, 0.5);  // never inside or against furniture, block or walls
  // One turn every 600 frames: frame 600 + k repeats frame k.
  for (const int k : {0, 75, 180}) {
    const Rigid3 same = pose(k).inverse() * pose(600 + k);
    EXPECT_LT(same.translation().norm(), 1e-9) << k;
    EXPECT_LT(RotationAngle(same.rotation()), 1e-9) << k;
  }
  const Rigid3 half = pose(0).inverse() * pose(300);
  EXPECT_GT(half.translation().norm(), 4.0);  // the far side of the ring
  SynthOptions with_movers = options;
  with_movers.num_movers = 1;
  EXPECT_THROW(with_movers.Check(), Error);
}

}  // namespace
}  // namespace esdslam

namespace esdslam {
namespace {

// The moved box is at its first place before moved_box_time and at first place + offset from then
// on; the crate is in view before and after, and the space it left shows the wall behind.
TEST(SyntheticScene, MovedBoxJumpsOnceAndTheSpaceItLeftIsSeenEmpty) {
  SynthOptions options = SynthPreset("moved_box");
  options.num_frames = 60;
  options.moved_box_time = 1.0;
  const SyntheticScene scene(options);
  const int box = options.moved_box + 1;  // box 0 is the room
  const Vec3 before = scene.WorldFromBox(box, 0.99).translation(), after = scene.WorldFromBox(box, 1.0).translation();
  EXPECT_LT((after - before - options.moved_box_offset).norm(), 1e-12);
  EXPECT_LT((scene.WorldFromBox(box, 1.9).translation() - after).norm(), 1e-12);
  EXPECT_LT((scene.WorldFromBox(box + 1, 1.9).translation() - scene.WorldFromBox(box + 1, 0.0).translation()).norm(), 1e-12);
  // A ray from a late frame's camera through the crate's first centre reaches beyond it.
  const Rigid3 late = scene.WorldFromCam(59);
  const Vec3 dir = (before - late.translation()).normalized();
  const double distance = (before - late.translation()).norm();
  EXPECT_GT(scene.CastRay(late.translation(), dir, scene.FrameTime(59)).t, distance + 0.2);
  EXPECT_LT(scene.CastRay(late.translation(), dir, 0.0).t, distance);  // at frame 0 the crate is there
  int crate_pixels = 0;
  for (const int frame : {0, 59}) {
    const cv::Mat ids = scene.RenderFrame(frame).surface_id;
    crate_pixels = 0;
    for (int v = 0; v < ids.rows; ++v)
      for (int u = 0; u < ids.cols; ++u) crate_pixels += ids.at<int>(v, u) / 6 == box;
    EXPECT_GT(crate_pixels, 1000) << "frame " << frame;
  }
  options.moved_box = 99;
  EXPECT_THROW(SyntheticScene{options}, Error);
}

}  // namespace
}  // namespace esdslam
