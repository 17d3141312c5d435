// Multi-view geometry check on synthetic frames with known poses and ground-truth mover masks.
#include <algorithm>
#include <cstdio>
#include <set>

#include <gtest/gtest.h>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "dynamic/geometry_check.h"
#include "dynamic/reference_keyframes.h"
#include "synth/synthetic_scene.h"
#include "support/small_synth.h"

namespace esdslam {
namespace {

SynthOptions SmallOptions(const std::string& preset, int frames) {
  return ::esdslam::testing::SmallSynthOptions(preset, frames);
}

GeometryCheckOptions SmallGeometryOptions() {
  GeometryCheckOptions options;
  options.cluster_radius_px = 12;
  options.max_mask_radius_px = 80;
  return options;
}

// A keyframe as tracking would give it: FAST corners of its image with valid depth, lifted to
// the world with the keyframe's (true) pose. Points on movers are included, as in a real map
// before culling.
ReferenceKeyframe MakeKeyframe(const SyntheticScene& scene, const SynthFrame& frame, bool with_depth) {
  cv::Mat grey;
  cv::cvtColor(frame.bgr, grey, cv::COLOR_BGR2GRAY);
  std::vector<cv::KeyPoint> corners;
  cv::FAST(grey, corners, 20, true);
  cv::KeyPointsFilter::retainBest(corners, 800);
  ReferenceKeyframe keyframe;
  keyframe.world_from_cam = frame.world_from_cam;
  for (const auto& kp : corners) {
    const cv::Point pixel(cvRound(kp.pt.x), cvRound(kp.pt.y));
    const float z = frame.depth_m.at<float>(pixel);
    if (z <= 0) continue;
    keyframe.points_world.push_back(frame.world_from_cam * scene.camera().Backproject(Vec2(pixel.x, pixel.y), z));
  }
  if (with_depth) keyframe.depth_m = frame.depth_m;
  return keyframe;
}

struct Scores {
  int flagged = 0, flagged_on_movers = 0;
  int detectable = 0, detected = 0;
};

// Precision: flagged pixels on a mover in the current frame. Recall: among tested points (in
// view, parallax <= 30 deg) that project onto a mover standing >= 0.3 m in front of them, the
// fraction flagged.
Scores Score(const SyntheticScene& scene, const SynthFrame& current, const std::vector<ReferenceKeyframe>& keyframes,
             const GeometryCheckResult& result) {
  Scores s;
  for (const auto& flag : result.dynamic_points) {
    ++s.flagged;
    s.flagged_on_movers += current.mover_mask.at<uchar>(flag.pixel) != 0;
  }
  const Rigid3 cam_from_world = current.world_from_cam.inverse();
  std::set<std::pair<int, int>> flagged_ids;
  for (const auto& flag : result.dynamic_points) flagged_ids.insert({flag.keyframe, flag.point});
  for (int k = 0; k < static_cast<int>(keyframes.size()); ++k) {
    for (int i = 0; i < static_cast<int>(keyframes[k].points_world.size()); ++i) {
      const Vec3& point = keyframes[k].points_world[i];
      const Vec3 in_cam = cam_from_world * point;
      if (in_cam.z() < 0.2) continue;
      const Vec2 pixel = scene.camera().Project(in_cam);
      const cv::Point p(cvRound(pixel.x()), cvRound(pixel.y()));
      if (p.x < 1 || p.y < 1 || p.x >= current.depth_m.cols - 1 || p.y >= current.depth_m.rows - 1) continue;
      const Vec3 a = (point - keyframes[k].world_from_cam.translation()).normalized();
      const Vec3 b = (point - current.world_from_cam.translation()).normalized();
      if (std::acos(std::clamp(a.dot(b), -1.0, 1.0)) > 30.0 * M_PI / 180) continue;
      if (current.mover_mask.at<uchar>(p) == 0 || in_cam.z() - current.depth_m.at<float>(p) < 0.3) continue;
      ++s.detectable;
      s.detected += flagged_ids.count({k, i});
    }
  }
  return s;
}

// Runs the check with the true pose of frame `current_index` against 4 earlier keyframes,
// with (variant 0) and without (variant 1) keyframe depth images; accumulates the scores.
void ScoreFrame(const SyntheticScene& scene, int current_index, Scores total[2]) {
  const SynthFrame current = scene.RenderFrame(current_index);
  std::vector<ReferenceKeyframe> keyframes;
  for (const int back : {24, 18, 12, 6})
    keyframes.push_back(MakeKeyframe(scene, scene.RenderFrame(current_index - back), true));
  for (int variant = 0; variant < 2; ++variant) {
    if (variant == 1) {
      for (auto& keyframe : keyframes) keyframe.depth_m = cv::Mat();
    }
    const GeometryCheckResult result = CheckMultiViewGeometry(scene.camera(), current.world_from_cam.inverse(),
                                                              current.depth_m, keyframes, SmallGeometryOptions());
    const Scores s = Score(scene, current, keyframes, result);
    const int mask_px = cv::countNonZero(result.dynamic_mask);
    const int mask_on_movers = cv::countNonZero(result.dynamic_mask & (current.mover_mask != 0));
    std::printf("frame %d %s: tested %d, flagged %d (%d on movers), detectable %d, detected %d, mask %d px (%d on movers)\n",
                current_index, variant == 0 ? "with keyframe depth" : "points only", result.num_tested, s.flagged,
                s.flagged_on_movers, s.detectable, s.detected, mask_px, mask_on_movers);
    total[variant].flagged += s.flagged;
    total[variant].flagged_on_movers += s.flagged_on_movers;
    total[variant].detectable += s.detectable;
    total[variant].detected += s.detected;
    // The mask grown from the flags lies mostly on the movers. Growth reaches up to 0.5 m from the
    // flags (across a person) and leaks onto the floor at the feet, where depth is continuous:
    // worst for a mover close to the camera (frame 59: 71 % on the mover).
    EXPECT_GE(mask_on_movers, 0.65 * mask_px);
  }
}

TEST(GeometryCheck, FlagsPointsCoveredByMoversWithHighPrecisionAndRecall) {
  const SyntheticScene scene(SmallOptions("dynamic", 60));
  Scores total[2];
  for (const int current_index : {24, 45, 59}) ScoreFrame(scene, current_index, total);
  for (const Scores& s : total) {
    ASSERT_GT(s.detectable, 200);
    EXPECT_GE(static_cast<double>(s.flagged_on_movers) / s.flagged, 0.9);
    EXPECT_GE(static_cast<double>(s.detected) / s.detectable, 0.9);
  }
}

TEST(GeometryCheck, StaticSceneWithTruePosesHasAlmostNoFlags) {
  const SyntheticScene scene(SmallOptions("static", 40));
  const SynthFrame current = scene.RenderFrame(39);
  std::vector<ReferenceKeyframe> keyframes;
  for (const int index : {0, 10, 20, 30}) keyframes.push_back(MakeKeyframe(scene, scene.RenderFrame(index), true));
  const GeometryCheckResult result = CheckMultiViewGeometry(scene.camera(), current.world_from_cam.inverse(),
                                                            current.depth_m, keyframes, SmallGeometryOptions());
  ASSERT_GT(result.num_tested, 1500);
  EXPECT_LE(result.dynamic_points.size(), result.num_tested / 200u);
  EXPECT_EQ(cv::countNonZero(result.dynamic_mask), 0);
  std::vector<ReferenceKeyframe> points_only = keyframes;
  for (auto& keyframe : points_only) keyframe.depth_m = cv::Mat();
  const GeometryCheckResult without_depth = CheckMultiViewGeometry(
      scene.camera(), current.world_from_cam.inverse(), current.depth_m, points_only, SmallGeometryOptions());
  std::printf("static scene: tested %d, flagged %zu with keyframe depth, %zu points only\n", result.num_tested,
              result.dynamic_points.size(), without_depth.dynamic_points.size());
  EXPECT_LE(without_depth.dynamic_points.size(), without_depth.num_tested / 100u);
  // A wrong pose (60 cm backwards) makes most points look occluded: the check really compares depth.
  const Rigid3 wrong = Rigid3(Quat::Identity(), Vec3(0, 0, 0.6)) * current.world_from_cam.inverse();
  const GeometryCheckResult bad =
      CheckMultiViewGeometry(scene.camera(), wrong, current.depth_m, keyframes, SmallGeometryOptions());
  EXPECT_GT(bad.dynamic_points.size(), bad.num_tested / 2u);
}

TEST(GeometryCheck, VanishedPointsAreReportedNotFlagged) {
  // The keyframe saw a point 1 m in front of a wall at 3 m; now the wall is measured there.
  CameraIntrinsics k = SynthOptions::DefaultIntrinsics();
  const PinholeCamera camera(k);
  cv::Mat depth(k.height, k.width, CV_32F, cv::Scalar(3.0f));
  ReferenceKeyframe keyframe;
  keyframe.points_world = {camera.Backproject(Vec2(320, 240), 2.0), camera.Backproject(Vec2(100, 100), 3.0)};
  const GeometryCheckResult result =
      CheckMultiViewGeometry(camera, Rigid3::Identity(), depth, {keyframe}, GeometryCheckOptions{});
  EXPECT_EQ(result.num_tested, 2);
  EXPECT_TRUE(result.dynamic_points.empty());
  ASSERT_EQ(result.vanished_points.size(), 1u);
  EXPECT_EQ(result.vanished_points[0].point, 0);
}

TEST(GeometryCheck, NoMeasurementAtThePointIsNotSeeingThroughIt) {
  // A thin static object 1 m in front of a wall whose own pixels the sensor does not measure
  // (dropouts on thin, dark or edge structures): the wall beside it is no evidence that it left.
  CameraIntrinsics k = SynthOptions::DefaultIntrinsics();
  const PinholeCamera camera(k);
  cv::Mat depth(k.height, k.width, CV_32F, cv::Scalar(3.0f));
  cv::rectangle(depth, cv::Rect(320, 200, 1, 80), cv::Scalar(0.0f), cv::FILLED);  // no reading on the 1-px pole
  ReferenceKeyframe keyframe;
  keyframe.points_world = {camera.Backproject(Vec2(320, 240), 2.0)};
  const GeometryCheckResult result =
      CheckMultiViewGeometry(camera, Rigid3::Identity(), depth, {keyframe}, GeometryCheckOptions{});
  EXPECT_EQ(result.num_tested, 0);
  EXPECT_TRUE(result.vanished_points.empty());
  EXPECT_TRUE(result.dynamic_points.empty());
}

// Depth image of a camera at (centre_x, 0, 0) looking along +z: a static board at z = 1.5 m
// covering x < 0, a wall at z = 3 m behind it.
cv::Mat BoardAndWallDepth(const PinholeCamera& camera, double centre_x) {
  cv::Mat depth(camera.height(), camera.width(), CV_32F);
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u)
      depth.at<float>(v, u) = centre_x + 1.5 * (u - camera.cx()) / camera.fx() < 0 ? 1.5f : 3.0f;
  return depth;
}

TEST(GeometryCheck, StaticOcclusionFromViewpointChangeIsVetoedByKeyframeDepth) {
  const PinholeCamera camera(SynthOptions::DefaultIntrinsics());
  ReferenceKeyframe keyframe;  // at the origin; sees the wall point right of the board's edge
  keyframe.points_world = {Vec3(0.1, 0.0, 3.0)};
  // The current camera 0.3 m to the left sees the board in front of that point (parallax 5.7 deg).
  const Rigid3 cam_from_world = Rigid3(Quat::Identity(), Vec3(0.3, 0, 0));
  const cv::Mat current_depth = BoardAndWallDepth(camera, -0.3);
  GeometryCheckResult result =
      CheckMultiViewGeometry(camera, cam_from_world, current_depth, {keyframe}, GeometryCheckOptions{});
  EXPECT_EQ(result.dynamic_points.size(), 1u);  // points only: indistinguishable from a mover
  keyframe.depth_m = BoardAndWallDepth(camera, 0.0);
  result = CheckMultiViewGeometry(camera, cam_from_world, current_depth, {keyframe}, GeometryCheckOptions{});
  EXPECT_EQ(result.num_tested, 1);
  EXPECT_TRUE(result.dynamic_points.empty());  // the keyframe saw the board there: static
  // Had the keyframe seen the wall where the board is now, the board moved in: dynamic.
  keyframe.depth_m = cv::Mat(camera.height(), camera.width(), CV_32F, cv::Scalar(3.0f));
  result = CheckMultiViewGeometry(camera, cam_from_world, current_depth, {keyframe}, GeometryCheckOptions{});
  EXPECT_EQ(result.dynamic_points.size(), 1u);
}

TEST(GeometryCheck, SkipsPointsSeenWithLargeParallax) {
  CameraIntrinsics k = SynthOptions::DefaultIntrinsics();
  const PinholeCamera camera(k);
  cv::Mat depth(k.height, k.width, CV_32F, cv::Scalar(1.0f));  // occluder 1 m in front
  ReferenceKeyframe keyframe;
  keyframe.points_world = {Vec3(0, 0, 3.0)};
  keyframe.world_from_cam = Rigid3(Quat::Identity(), Vec3(2.0, 0, 0));  // 33.7 deg between the rays
  GeometryCheckResult result = CheckMultiViewGeometry(camera, Rigid3::Identity(), depth, {keyframe}, GeometryCheckOptions{});
  EXPECT_EQ(result.num_parallax_skipped, 1);
  EXPECT_TRUE(result.dynamic_points.empty());
  keyframe.world_from_cam = Rigid3(Quat::Identity(), Vec3(1.5, 0, 0));  // 26.6 deg
  result = CheckMultiViewGeometry(camera, Rigid3::Identity(), depth, {keyframe}, GeometryCheckOptions{});
  EXPECT_EQ(result.dynamic_points.size(), 1u);
}

TEST(ReferenceKeyframes, PicksMostSharedAndMostOverlapping) {
  EXPECT_EQ(SelectReferenceKeyframes({5, 0, 9, 9, 1, 3, 7}, 5), (std::vector<int>{2, 3, 6, 0, 5}));
  EXPECT_EQ(SelectReferenceKeyframes({0, 2, 0}, 5), (std::vector<int>{1}));
  const SyntheticScene scene(SynthPreset("loop"));
  std::vector<Rigid3> poses;
  for (const int index : {0, 100, 225, 330, 445}) poses.push_back(scene.WorldFromCam(index));
  // Current = frame 440: frames 445 and 0 look the same way (loop), 225 the opposite way.
  const std::vector<int> chosen =
      SelectKeyframesByViewOverlap(scene.camera(), scene.WorldFromCam(440).inverse(), poses, 2.5, 5);
  ASSERT_GE(chosen.size(), 2u);
  EXPECT_TRUE((chosen[0] == 4 && chosen[1] == 0) || (chosen[0] == 0 && chosen[1] == 4));
  EXPECT_EQ(std::count(chosen.begin(), chosen.end(), 2), 0);
}

// Current frame at t = 10 s, minimum age 0.25 s: keyframes from 9.8 and 9.9 s drop out when an
// older one shares points; with none old enough (the start of a run) all stay.
TEST(ReferenceKeyframes, DropsYoungKeyframesWhenOldOnesShare) {
  EXPECT_EQ(WithoutYoungKeyframes({40, 90, 70, 0}, {9.0, 9.8, 9.75, 5.0}, 10.0, 0.25), (std::vector<int>{40, 0, 70, 0}));
  EXPECT_EQ(WithoutYoungKeyframes({0, 90, 70}, {5.0, 9.8, 9.9}, 10.0, 0.25), (std::vector<int>{0, 90, 70}));
  EXPECT_EQ(WithoutYoungKeyframes({10, 90}, {9.8, 9.9}, 10.0, 0.0), (std::vector<int>{10, 90}));
  EXPECT_EQ(SelectReferenceKeyframes(WithoutYoungKeyframes({40, 90, 70}, {9.0, 9.9, 8.0}, 10.0, 0.25), 5),
            (std::vector<int>{2, 0}));
  EXPECT_THROW(WithoutYoungKeyframes({1, 2}, {1.0}, 10.0, 0.25), Error);
}

// Depth images are sensor images: with lens distortion a projection must be distorted before the
// depth is read. Current depth (raw grid): 3 m, with a 1 m block over raw columns u >= 582.
TEST(GeometryCheck, ReadsDepthAtTheDistortedPixel) {
  CameraIntrinsics k = SynthOptions::DefaultIntrinsics();
  k.k1 = 0.26, k.k2 = -0.95, k.k3 = 1.16;  // TUM freiburg1-like
  const PinholeCamera camera(k);
  cv::Mat depth(k.height, k.width, CV_32F, cv::Scalar(3.0f));
  depth(cv::Rect(582, 0, k.width - 582, k.height)).setTo(1.0f);
  const auto on_ray_of_raw = [&](float u, float v) {
    const cv::Point2f ideal = camera.Undistort({{u, v}})[0];
    return camera.Backproject(Vec2(ideal.x, ideal.y), 3.0);
  };
  ReferenceKeyframe keyframe;
  keyframe.points_world = {on_ray_of_raw(586, 10), on_ray_of_raw(560, 10)};
  // The first point's raw pixel is on the block, its ideal projection is not.
  ASSERT_LT(camera.Project(keyframe.points_world[0]).x(), 580.5);
  const GeometryCheckResult result =
      CheckMultiViewGeometry(camera, Rigid3::Identity(), depth, {keyframe}, GeometryCheckOptions{});
  ASSERT_EQ(result.outcomes.size(), 1u);
  EXPECT_EQ(result.outcomes[0][0], PointOutcome::kCovered);
  EXPECT_EQ(result.outcomes[0][1], PointOutcome::kConsistent);
  ASSERT_EQ(result.dynamic_points.size(), 1u);
  EXPECT_NEAR(result.dynamic_points[0].pixel.x, 586, 1);
  EXPECT_NEAR(result.dynamic_points[0].pixel.y, 10, 1);
}

TEST(GeometryCheck, ExemptPixelsAreNeitherFlaggedNorMasked) {
  const PinholeCamera camera(SynthOptions::DefaultIntrinsics());
  cv::Mat depth(camera.height(), camera.width(), CV_32F, cv::Scalar(3.0f));
  depth(cv::Rect(200, 150, 120, 200)).setTo(1.5f);  // something 1.5 m in front of a 3 m wall
  ReferenceKeyframe keyframe;                       // saw the wall there
  for (int v = 160; v < 340; v += 12)
    for (int u = 210; u < 310; u += 12) keyframe.points_world.push_back(camera.Backproject(Vec2(u, v), 3.0));
  GeometryCheckResult result = CheckMultiViewGeometry(camera, Rigid3::Identity(), depth, {keyframe}, {});
  const int flagged = static_cast<int>(result.dynamic_points.size());
  EXPECT_EQ(flagged, static_cast<int>(keyframe.points_world.size()));
  EXPECT_GT(cv::countNonZero(result.dynamic_mask(cv::Rect(200, 150, 120, 200))), 0.9 * 120 * 200);
  cv::Mat exempt = cv::Mat::zeros(depth.size(), CV_8U);
  exempt(cv::Rect(0, 0, 260, camera.height())).setTo(255);  // left part trusted (e.g. a static class)
  result = CheckMultiViewGeometry(camera, Rigid3::Identity(), depth, {keyframe}, {}, exempt);
  for (const FlaggedPoint& flag : result.dynamic_points) EXPECT_GE(flag.pixel.x, 260);
  EXPECT_GT(std::count(result.outcomes[0].begin(), result.outcomes[0].end(), PointOutcome::kExempt), 0);
  EXPECT_EQ(cv::countNonZero(result.dynamic_mask & exempt), 0);
  EXPECT_GT(cv::countNonZero(result.dynamic_mask), 0);
  EXPECT_THROW(CheckMultiViewGeometry(camera, Rigid3::Identity(), depth, {keyframe}, {}, cv::Mat::zeros(4, 4, CV_8U)),
               Error);
}

TEST(GeometryCheck, RejectsBadInput) {
  GeometryCheckOptions options;
  options.max_parallax_deg = 0;
  EXPECT_THROW(options.Check(), Error);
  const PinholeCamera camera(SynthOptions::DefaultIntrinsics());
  EXPECT_THROW(CheckMultiViewGeometry(camera, Rigid3::Identity(), cv::Mat::zeros(10, 10, CV_32F), {}, {}), Error);
}

}  // namespace
}  // namespace esdslam
